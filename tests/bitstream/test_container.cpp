// Container: round trip, every-byte truncation, corruption of every field, limits, and
// truncate_file producing valid files that decode like the prefix.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "meshlift/byte_io.h"
#include "meshlift/container.h"

using namespace meshlift;

namespace {

struct TestChunk {
  std::uint32_t tag;
  std::vector<std::uint8_t> payload;
};

std::vector<TestChunk> test_chunks() {
  std::mt19937 rng(77);
  auto random_bytes = [&](std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    return bytes;
  };
  return {
      {kTagHeader, random_bytes(40)},
      {make_tag('x', 't', 'r', 'a'), {}},  // ancillary, unknown, empty
      {kTagBaseMesh, random_bytes(300)},   // two-byte length
      {kTagCoefficients, random_bytes(20000)},
      {make_tag('n', 'o', 't', 'e'), random_bytes(3)},
  };
}

std::vector<std::uint8_t> build(const std::vector<TestChunk>& chunks) {
  ContainerWriter writer;
  for (const auto& c : chunks) writer.add_chunk(c.tag, c.payload);
  const std::size_t size = writer.size();
  auto file = writer.finish();
  REQUIRE(file.size() == size);
  return file;
}

// Byte ranges of each chunk in the file built from `chunks`.
struct Layout {
  std::size_t begin, payload_begin, payload_end, end;
};
std::vector<Layout> layout(const std::vector<TestChunk>& chunks) {
  std::vector<Layout> result;
  std::size_t offset = container::kFileHeaderBytes;
  for (const auto& c : chunks) {
    Layout l;
    l.begin = offset;
    l.payload_begin = offset + 4 + varint_size(c.payload.size());
    l.payload_end = l.payload_begin + c.payload.size();
    l.end = l.payload_end + 4;
    result.push_back(l);
    offset = l.end;
  }
  return result;
}

std::vector<std::uint8_t> to_vector(std::span<const std::uint8_t> s) { return {s.begin(), s.end()}; }

}  // namespace

TEST_CASE("container: round trip", "[container]") {
  const auto chunks = test_chunks();
  const auto file = build(chunks);
  CHECK(file[0] == 'M');
  CHECK(file[1] == 'L');
  CHECK(file[2] == 'Z');
  CHECK(file[3] == 0x1A);
  CHECK(file[4] == 5);
  ContainerReader reader;
  REQUIRE(reader.parse(file) == Status::ok);
  CHECK(reader.version() == 5);
  CHECK_FALSE(reader.truncated());
  REQUIRE(reader.chunks().size() == chunks.size());
  const auto expected_layout = layout(chunks);
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    const Chunk& c = reader.chunks()[i];
    CHECK(c.tag == chunks[i].tag);
    CHECK(to_vector(c.payload) == chunks[i].payload);
    CHECK(c.declared_size == chunks[i].payload.size());
    CHECK(c.offset == expected_layout[i].begin);
    CHECK(c.complete);
    CHECK(c.checksum_ok);
    CHECK(c.payload.data() == file.data() + expected_layout[i].payload_begin);  // no copy
  }
  REQUIRE(reader.find(kTagCoefficients) != nullptr);
  CHECK(reader.find(kTagCoefficients)->payload.size() == 20000);
  CHECK(reader.find(make_tag('n', 'o', 'p', 'e')) == nullptr);

  ContainerReader empty_file;
  CHECK(empty_file.parse(ContainerWriter().finish()) == Status::ok);
  CHECK(empty_file.chunks().empty());
}

TEST_CASE("container: tags", "[container]") {
  CHECK(tag_to_string(kTagHeader) == "HEAD");
  CHECK(tag_to_string(make_tag('a', '\n', '\\', char(0xFF))) == "a\\x0A\\x5C\\xFF");
  CHECK(is_critical_tag(kTagCoefficients));
  CHECK_FALSE(is_critical_tag(make_tag('n', 'o', 't', 'e')));
  CHECK(chunk_checksum({}) == static_cast<std::uint32_t>(0x2D06800538D394C2ull));  // XXH3_64bits("")
}

TEST_CASE("container: a file cut at every byte parses with the right complete flags", "[container][truncation]") {
  const auto chunks = test_chunks();
  const auto file = build(chunks);
  const auto expected = layout(chunks);
  for (std::size_t length = 0; length <= file.size(); ++length) {
    INFO("cut at " << length);
    const std::vector<std::uint8_t> prefix(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(length));
    ContainerReader reader;
    const Status status = reader.parse(prefix);
    if (length < container::kFileHeaderBytes) {
      CHECK(status == Status::truncated);
      CHECK(reader.chunks().empty());
      continue;
    }
    REQUIRE(status == Status::ok);
    std::size_t started = 0;
    while (started < expected.size() && expected[started].begin < length) ++started;
    REQUIRE(reader.chunks().size() == started);
    for (std::size_t i = 0; i < started; ++i) {
      const Chunk& c = reader.chunks()[i];
      const Layout& l = expected[i];
      const bool complete = l.end <= length;
      CHECK(c.complete == complete);
      CHECK(c.checksum_ok == complete);
      CHECK(c.offset == l.begin);
      // Tag known once its 4 bytes are in; payload = the bytes present once the length is in.
      CHECK(c.tag == (length >= l.begin + 4 ? chunks[i].tag : 0u));
      const std::size_t present = length <= l.payload_begin ? 0 : std::min(length, l.payload_end) - l.payload_begin;
      CHECK(c.payload.size() == present);
      CHECK(to_vector(c.payload) == std::vector<std::uint8_t>(chunks[i].payload.begin(),
                                                              chunks[i].payload.begin() + static_cast<std::ptrdiff_t>(present)));
    }
    CHECK(reader.truncated() == (started > 0 && expected[started - 1].end > length));
  }
}

TEST_CASE("container: a flipped payload bit is a checksum mismatch in that chunk", "[container][corruption]") {
  const auto chunks = test_chunks();
  const auto file = build(chunks);
  const auto expected = layout(chunks);
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    for (std::size_t at = expected[i].payload_begin; at < expected[i].end; at += 1 + (at > expected[i].begin + 200 ? 97 : 0)) {
      auto damaged = file;
      damaged[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));  // payload or stored checksum
      ContainerReader reader;
      REQUIRE(reader.parse(damaged) == Status::checksum_mismatch);
      CHECK(reader.error().chunk_index == i);
      CHECK(reader.error().offset == expected[i].begin);
      CHECK(reader.chunks().size() == i);  // only the verified chunks before it
    }
  }
}

TEST_CASE("container: header corruption gives the specific status", "[container][corruption]") {
  const auto file = build(test_chunks());
  for (std::size_t at = 0; at < 8; ++at) {
    for (int bit = 0; bit < 8; ++bit) {
      auto damaged = file;
      damaged[at] ^= static_cast<std::uint8_t>(1u << bit);
      ContainerReader reader;
      const Status status = reader.parse(damaged);
      const Status expected = at < 4 ? Status::bad_magic : at == 4 ? Status::unsupported_version : Status::reserved_bits_set;
      CHECK(status == expected);
      CHECK(reader.error().offset == at);
      CHECK(reader.chunks().empty());
    }
  }
  // A short file with a wrong first byte is bad_magic, not truncated; a right one is truncated.
  const std::uint8_t png[3] = {0x89, 'P', 'N'};
  CHECK(ContainerReader().parse(png) == Status::bad_magic);
  CHECK(ContainerReader().parse(std::span(file).first(3)) == Status::truncated);
  CHECK(ContainerReader().parse({}) == Status::truncated);
}

TEST_CASE("container: declared sizes and counts above the limits", "[container][limits]") {
  // 20 bytes: header, tag, a varint declaring 2^40 payload bytes, a few bytes of "payload".
  ByteWriter writer;
  for (std::uint8_t b : container::kMagic) writer.u8(b);
  writer.u8(container::kFormatVersion);
  writer.u8(0);
  writer.u16(0);
  writer.u32(kTagCoefficients);
  writer.varint(std::uint64_t{1} << 40);
  while (writer.size() < 20) writer.u8(0xAA);
  const auto file = writer.take();
  REQUIRE(file.size() == 20);
  ContainerReader reader;
  CHECK(reader.parse(file) == Status::limit_exceeded);
  CHECK(reader.error().chunk_index == 0);
  CHECK(reader.error().offset == 8);
  ContainerLimits huge;
  huge.max_chunk_bytes = std::uint64_t{1} << 41;
  CHECK(reader.parse(file, huge) == Status::ok);  // allowed: then it is just a cut-short chunk
  REQUIRE(reader.chunks().size() == 1);
  CHECK_FALSE(reader.chunks()[0].complete);
  CHECK(reader.chunks()[0].payload.size() == 2);  // 8 header + 4 tag + 6 varint bytes before it
  CHECK(reader.chunks()[0].payload.data() == file.data() + 18);

  const auto many = build(test_chunks());
  ContainerLimits few;
  few.max_chunks = 3;
  CHECK(reader.parse(many, few) == Status::limit_exceeded);
  CHECK(reader.error().chunk_index == 3);
  CHECK(reader.chunks().size() == 3);
  few.max_chunk_bytes = 299;
  few.max_chunks = 100;
  CHECK(reader.parse(many, few) == Status::limit_exceeded);
  CHECK(reader.error().chunk_index == 2);
}

TEST_CASE("container: a malformed length varint is corrupt", "[container][corruption]") {
  ByteWriter writer;
  for (std::uint8_t b : container::kMagic) writer.u8(b);
  writer.u8(container::kFormatVersion);
  writer.u8(0);
  writer.u16(0);
  writer.u32(kTagHeader);
  writer.u8(0x80);  // overlong encoding of 0
  writer.u8(0x00);
  writer.u32(chunk_checksum({}));
  ContainerReader reader;
  CHECK(reader.parse(writer.data()) == Status::corrupt);
  CHECK(reader.error().offset == 8);
}

TEST_CASE("container: random garbage after a valid header never crashes", "[container][robustness]") {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<std::uint8_t> file = {'M', 'L', 'Z', 0x1A, 1, 0, 0, 0};
    const std::size_t extra = rng() % 64;
    for (std::size_t i = 0; i < extra; ++i) file.push_back(static_cast<std::uint8_t>(rng() % (trial % 2 ? 256 : 8)));
    ContainerReader reader;
    reader.parse(file);
    for (const Chunk& c : reader.chunks()) {
      if (c.payload.empty()) continue;
      CHECK(c.payload.data() >= file.data());
      CHECK(c.payload.data() + c.payload.size() <= file.data() + file.size());
    }
  }
}

TEST_CASE("container: truncate_file gives valid files that match the prefix", "[container][truncation]") {
  const auto chunks = test_chunks();
  const auto file = build(chunks);
  std::vector<std::uint8_t> out;
  CHECK(truncate_file(file, 7, out) == Status::truncated);
  CHECK(out.empty());
  for (std::size_t max_bytes = 8; max_bytes <= file.size() + 2; ++max_bytes) {
    INFO("max_bytes " << max_bytes);
    REQUIRE(truncate_file(file, max_bytes, out) == Status::ok);
    CHECK(out.size() <= max_bytes + 4);
    ContainerReader truncated_reader;
    REQUIRE(truncated_reader.parse(out) == Status::ok);
    ContainerReader prefix_reader;
    REQUIRE(prefix_reader.parse(std::span(file).first(std::min(max_bytes, file.size()))) == Status::ok);
    // Same chunks, same payload bytes; the prefix's empty cut-off chunk (if any) is dropped.
    std::vector<Chunk> prefix_chunks = prefix_reader.chunks();
    if (!prefix_chunks.empty() && !prefix_chunks.back().complete && prefix_chunks.back().payload.empty()) {
      prefix_chunks.pop_back();
    }
    REQUIRE(truncated_reader.chunks().size() == prefix_chunks.size());
    for (std::size_t i = 0; i < prefix_chunks.size(); ++i) {
      CHECK(truncated_reader.chunks()[i].complete);
      CHECK(truncated_reader.chunks()[i].tag == prefix_chunks[i].tag);
      CHECK(to_vector(truncated_reader.chunks()[i].payload) == to_vector(prefix_chunks[i].payload));
    }
    if (max_bytes >= file.size()) CHECK(out == file);
  }
  // A damaged chunk beyond the cut still fails: truncation does not launder corruption.
  auto damaged = file;
  damaged[file.size() - 6] ^= 1;
  CHECK(truncate_file(damaged, 100, out) == Status::checksum_mismatch);
  CHECK(out.empty());
}

TEST_CASE("container: golden file of format version 5", "[container][golden]") {
  // Header, then one 'HEAD' chunk holding {1, 2, 3}; checksum = low 32 bits of XXH3_64bits.
  const std::vector<std::uint8_t> golden = {0x4D, 0x4C, 0x5A, 0x1A, 0x05, 0x00, 0x00, 0x00, 0x48,
                                            0x45, 0x41, 0x44, 0x03, 0x01, 0x02, 0x03, 0x3B, 0x73,
                                            0xAE, 0x32};
  const std::uint8_t payload[3] = {1, 2, 3};
  ContainerWriter writer;
  writer.add_chunk(kTagHeader, payload);
  CHECK(writer.finish() == golden);
  ContainerReader reader;
  REQUIRE(reader.parse(golden) == Status::ok);
  REQUIRE(reader.chunks().size() == 1);
  CHECK(reader.chunks()[0].tag == kTagHeader);
  CHECK(to_vector(reader.chunks()[0].payload) == std::vector<std::uint8_t>{1, 2, 3});
}

TEST_CASE("container: versions 1 to 4 and 6 are refused with unsupported_version at byte 4", "[container][golden]") {
  // The golden files of format versions 1 to 4 (FORMAT.md change log): the same container as
  // version 5's, but this build no longer reads them (their chunks say other things).
  for (const std::uint8_t version : {std::uint8_t{1}, std::uint8_t{2}, std::uint8_t{3}, std::uint8_t{4}, std::uint8_t{6},
                                     std::uint8_t{0}}) {
    const std::vector<std::uint8_t> file = {0x4D, 0x4C, 0x5A, 0x1A, version, 0x00, 0x00, 0x00, 0x48, 0x45,
                                            0x41, 0x44, 0x03, 0x01, 0x02, 0x03, 0x3B, 0x73, 0xAE, 0x32};
    ContainerReader reader;
    CHECK(reader.parse(file) == Status::unsupported_version);
    CHECK(reader.error().offset == 4);
    CHECK(reader.version() == version);
    CHECK(reader.chunks().empty());
  }
}

TEST_CASE("status: frozen values and names", "[status]") {
  CHECK(static_cast<int>(Status::ok) == 0);
  CHECK(static_cast<int>(Status::truncated) == 1);
  CHECK(static_cast<int>(Status::bad_magic) == 2);
  CHECK(static_cast<int>(Status::unsupported_version) == 3);
  CHECK(static_cast<int>(Status::corrupt) == 4);
  CHECK(static_cast<int>(Status::checksum_mismatch) == 5);
  CHECK(static_cast<int>(Status::limit_exceeded) == 6);
  CHECK(static_cast<int>(Status::reserved_bits_set) == 7);
  CHECK(static_cast<int>(Status::io_error) == 8);
  CHECK(std::string(to_string(Status::checksum_mismatch)) == "checksum_mismatch");
  CHECK(std::string(to_string(static_cast<Status>(200))) == "unknown");
  for (int code = 0; code <= 8; ++code) {
    CHECK(std::string(describe(static_cast<Status>(code))).size() > 5);
  }
}

TEST_CASE("container: parse_more over a growing file gives parse()'s chunks and errors at every length",
          "[container][truncation]") {
  const auto chunks = test_chunks();
  auto whole = build(chunks);
  auto damaged = whole;
  damaged[layout(chunks)[2].payload_begin + 100] ^= 0x10;  // the base mesh's checksum fails once it is whole
  auto bad_length = whole;
  bad_length[layout(chunks)[3].begin + 4] = 0xFF;  // a length varint of 0xFF bytes: corrupt
  for (int limit = 0; limit < 2; ++limit)
    for (const std::vector<std::uint8_t>* file : {&whole, &damaged, &bad_length}) {
      ContainerLimits limits;
      if (limit == 1) limits.max_chunk_bytes = 1000;  // the coefficient chunk exceeds it
      // Random steps, and every chunk's boundaries (a cut between two chunks, inside a header,
      // just before a checksum), each once.
      std::mt19937 rng(9);
      std::set<std::size_t> lengths;
      for (std::size_t length = 0; length <= file->size(); length += 1 + (rng() % 3 == 0 ? 0 : rng() % 700))
        lengths.insert(length);
      for (const Layout& l : layout(chunks))
        for (std::size_t at : {l.begin, l.begin + 2, l.payload_begin, l.payload_end, l.end - 1, l.end}) lengths.insert(at);
      lengths.insert(file->size());
      ContainerReader growing;
      std::vector<std::uint8_t> received;  // copied into a new buffer at every step: the chunks must follow
      for (const std::size_t length : lengths) {
        received = std::vector<std::uint8_t>(file->begin(), file->begin() + static_cast<std::ptrdiff_t>(length));
        INFO("length " << length << ", limit " << limit);
        ContainerReader fresh;
        const Status expected = fresh.parse(received, limits);
        REQUIRE(growing.parse_more(received, limits) == expected);
        CHECK(growing.error().offset == fresh.error().offset);
        CHECK(growing.error().chunk_index == fresh.error().chunk_index);
        CHECK(growing.truncated() == fresh.truncated());
        REQUIRE(growing.chunks().size() == fresh.chunks().size());
        for (std::size_t i = 0; i < fresh.chunks().size(); ++i) {
          const Chunk &a = growing.chunks()[i], &b = fresh.chunks()[i];
          CHECK(a.tag == b.tag);
          CHECK(a.offset == b.offset);
          CHECK(a.declared_size == b.declared_size);
          CHECK(a.complete == b.complete);
          CHECK(a.checksum_ok == b.checksum_ok);
          CHECK(a.payload.data() == b.payload.data());  // both point into `received`
          CHECK(a.payload.size() == b.payload.size());
        }
      }
    }
}
