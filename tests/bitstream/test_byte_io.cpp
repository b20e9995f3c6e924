// Byte I/O: exact little-endian layout, varint edge values, rejection of malformed varints,
// every truncation of a buffer of varints, sticky errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "meshlift/byte_io.h"

using namespace meshlift;

namespace {
std::vector<std::uint8_t> bytes_of(std::initializer_list<int> values) {
  std::vector<std::uint8_t> bytes;
  for (int v : values) bytes.push_back(static_cast<std::uint8_t>(v));
  return bytes;
}
}  // namespace

TEST_CASE("byte io: fixed-width integers are little-endian", "[byte_io]") {
  ByteWriter writer;
  writer.u8(0xAB);
  writer.u16(0x1234);
  writer.u32(0xDEADBEEF);
  writer.u64(0x0102030405060708ull);
  CHECK(writer.data() == bytes_of({0xAB, 0x34, 0x12, 0xEF, 0xBE, 0xAD, 0xDE, 8, 7, 6, 5, 4, 3, 2, 1}));

  ByteReader reader(writer.data());
  std::uint8_t a = 0;
  std::uint16_t b = 0;
  std::uint32_t c = 0;
  std::uint64_t d = 0;
  CHECK(reader.u8(a) == Status::ok);
  CHECK(reader.u16(b) == Status::ok);
  CHECK(reader.u32(c) == Status::ok);
  CHECK(reader.u64(d) == Status::ok);
  CHECK(a == 0xAB);
  CHECK(b == 0x1234);
  CHECK(c == 0xDEADBEEF);
  CHECK(d == 0x0102030405060708ull);
  CHECK(reader.remaining() == 0);
  CHECK(reader.u8(a) == Status::truncated);
}

TEST_CASE("byte io: varint encodings of edge values", "[byte_io][varint]") {
  const std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
  const std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>> cases = {
      {0, bytes_of({0x00})},
      {1, bytes_of({0x01})},
      {127, bytes_of({0x7F})},
      {128, bytes_of({0x80, 0x01})},
      {300, bytes_of({0xAC, 0x02})},
      {16383, bytes_of({0xFF, 0x7F})},
      {16384, bytes_of({0x80, 0x80, 0x01})},
      {std::uint64_t{1} << 63, bytes_of({0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x01})},
      {max, bytes_of({0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01})},
  };
  for (const auto& [value, encoding] : cases) {
    ByteWriter writer;
    writer.varint(value);
    CHECK(writer.data() == encoding);
    CHECK(varint_size(value) == encoding.size());
    ByteReader reader(encoding);
    std::uint64_t decoded = 1234;
    CHECK(reader.varint(decoded) == Status::ok);
    CHECK(decoded == value);
    CHECK(reader.remaining() == 0);
  }
}

TEST_CASE("byte io: malformed varints are corrupt", "[byte_io][varint]") {
  const std::vector<std::vector<std::uint8_t>> malformed = {
      bytes_of({0x80, 0x00}),                                                    // overlong zero
      bytes_of({0xFF, 0x00}),                                                    // overlong 127
      bytes_of({0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02}),    // bit 64 set
      bytes_of({0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x01}),  // 11 bytes
      bytes_of({0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x81}),    // 10th continues
  };
  for (const auto& bytes : malformed) {
    ByteReader reader(bytes);
    std::uint64_t value = 99;
    CHECK(reader.varint(value) == Status::corrupt);
    CHECK(value == 0);
    CHECK(reader.position() == 0);
    CHECK(reader.status() == Status::corrupt);
  }
}

TEST_CASE("byte io: every truncation of a buffer of varints", "[byte_io][varint][truncation]") {
  std::mt19937_64 rng(9);
  std::vector<std::uint64_t> values;
  std::vector<std::size_t> ends;  // byte offset after each varint
  ByteWriter writer;
  for (int i = 0; i < 200; ++i) {
    const std::uint64_t value = rng() >> (rng() % 64);
    values.push_back(value);
    writer.varint(value);
    ends.push_back(writer.size());
  }
  const std::vector<std::uint8_t> buffer = writer.take();
  for (std::size_t length = 0; length <= buffer.size(); ++length) {
    // Exact-size copy so an overread would touch unowned memory under AddressSanitizer.
    const std::vector<std::uint8_t> prefix(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(length));
    ByteReader reader(prefix);
    std::size_t count = 0;
    std::uint64_t value = 0;
    Status status = Status::ok;
    while ((status = reader.varint(value)) == Status::ok) {
      REQUIRE(count < values.size());
      CHECK(value == values[count]);
      ++count;
    }
    const std::size_t complete = static_cast<std::size_t>(std::upper_bound(ends.begin(), ends.end(), length) - ends.begin());
    CHECK(count == complete);
    CHECK(status == Status::truncated);
    CHECK(reader.position() == (complete == 0 ? 0 : ends[complete - 1]));
  }
}

TEST_CASE("byte io: errors are sticky and reads never pass the end", "[byte_io]") {
  const auto bytes = bytes_of({1, 2, 3});
  ByteReader reader(bytes);
  std::uint32_t big = 7;
  CHECK(reader.u32(big) == Status::truncated);
  CHECK(big == 0);
  std::uint8_t small = 7;
  CHECK(reader.u8(small) == Status::truncated);  // would fit, but the error is sticky
  CHECK(small == 0);
  CHECK(reader.position() == 0);

  ByteReader views(bytes);
  std::span<const std::uint8_t> view;
  CHECK(views.bytes(2, view) == Status::ok);
  CHECK(view.size() == 2);
  CHECK(view.data() == bytes.data());  // a view, not a copy
  CHECK(views.bytes(2, view) == Status::truncated);
  CHECK(view.empty());
  CHECK(views.skip(1) == Status::truncated);

  ByteReader skipper(bytes);
  CHECK(skipper.skip(3) == Status::ok);
  CHECK(skipper.rest().empty());
  CHECK(skipper.skip(std::numeric_limits<std::size_t>::max()) == Status::truncated);
}
