// The .mlz container: file header, chunk framing, checksums, truncation (FORMAT.md §1-§2).
#include "meshlift/container.h"

#include <algorithm>

#include <xxhash.h>

namespace meshlift {

std::string tag_to_string(std::uint32_t tag) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string text;
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<unsigned char>(tag >> (8 * i));
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      text += static_cast<char>(c);
    } else {
      text += "\\x";
      text += kHex[c >> 4];
      text += kHex[c & 0xF];
    }
  }
  return text;
}

// Fuzzing builds (MESHLIFT_FUZZ defines the macro libFuzzer projects use for this) accept any
// checksum, so that mutated bytes reach the header, base mesh and coefficient decoders instead of
// stopping at the checksum (docs/HARDENING.md). Never defined in a normal build.
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
constexpr bool kEnforceChecksums = false;
#else
constexpr bool kEnforceChecksums = true;
#endif

std::uint32_t chunk_checksum(std::span<const std::uint8_t> payload) {
  return static_cast<std::uint32_t>(XXH3_64bits(payload.data(), payload.size()));
}

Status ContainerReader::fail(Status status, std::size_t offset, std::size_t chunk_index) {
  error_ = {status, offset, chunk_index};
  return status;
}

const Chunk* ContainerReader::find(std::uint32_t tag) const {
  for (const Chunk& chunk : chunks_) {
    if (chunk.tag == tag) return &chunk;
  }
  return nullptr;
}

Status ContainerReader::parse(std::span<const std::uint8_t> file, const ContainerLimits& limits) {
  chunks_.clear();
  error_ = {};
  version_ = 0;
  base_ = file.data();
  end_of_complete_ = container::kFileHeaderBytes;
  // File header: magic[4] | version u8 | flags u8 | reserved u16 (FORMAT.md §1).
  for (std::size_t i = 0; i < 4 && i < file.size(); ++i) {
    if (file[i] != container::kMagic[i]) return fail(Status::bad_magic, i);
  }
  if (file.size() < container::kFileHeaderBytes) return fail(Status::truncated, file.size());
  version_ = file[4];
  if (version_ != container::kFormatVersion) return fail(Status::unsupported_version, 4);
  if (file[5] != 0) return fail(Status::reserved_bits_set, 5);
  if (file[6] != 0 || file[7] != 0) return fail(Status::reserved_bits_set, file[6] != 0 ? 6 : 7);
  return parse_chunks(file, limits);
}

Status ContainerReader::parse_more(std::span<const std::uint8_t> file, const ContainerLimits& limits) {
  // Only after a parse that read the file header and found no error, of a prefix of `file`.
  if (version_ == 0 || error_.status != Status::ok || base_ == nullptr || file.size() < end_of_complete_)
    return parse(file, limits);
  if (!chunks_.empty() && !chunks_.back().complete) chunks_.pop_back();
  for (Chunk& chunk : chunks_)  // the same bytes, perhaps moved
    chunk.payload = file.subspan(static_cast<std::size_t>(chunk.payload.data() - base_), chunk.payload.size());
  base_ = file.data();
  return parse_chunks(file, limits);
}

Status ContainerReader::parse_chunks(std::span<const std::uint8_t> file, const ContainerLimits& limits) {
  ByteReader reader(file.subspan(end_of_complete_));
  while (reader.remaining() > 0) {
    const std::size_t index = chunks_.size();
    const std::size_t offset = end_of_complete_ + reader.position();
    if (index >= limits.max_chunks) return fail(Status::limit_exceeded, offset, index);
    Chunk chunk;
    chunk.offset = offset;
    if (reader.u32(chunk.tag) != Status::ok) {
      chunk.tag = 0;  // cut inside the tag
      chunks_.push_back(chunk);
      break;
    }
    const Status length_status = reader.varint(chunk.declared_size);
    if (length_status == Status::corrupt) return fail(Status::corrupt, offset, index);
    if (length_status != Status::ok) {  // cut inside the length
      chunks_.push_back(chunk);
      break;
    }
    if (chunk.declared_size > limits.max_chunk_bytes) return fail(Status::limit_exceeded, offset, index);
    // declared_size <= max_chunk_bytes, but a caller could raise that above SIZE_MAX on 32-bit.
    const std::size_t available = reader.remaining();
    if (chunk.declared_size > available) {  // cut inside the payload
      reader.bytes(available, chunk.payload);
      chunks_.push_back(chunk);
      break;
    }
    reader.bytes(static_cast<std::size_t>(chunk.declared_size), chunk.payload);
    std::uint32_t stored_checksum = 0;
    if (reader.u32(stored_checksum) != Status::ok) {  // cut inside the checksum
      chunks_.push_back(chunk);
      break;
    }
    chunk.checksum_ok = stored_checksum == chunk_checksum(chunk.payload);
    if (!chunk.checksum_ok && kEnforceChecksums) return fail(Status::checksum_mismatch, offset, index);
    chunk.complete = true;
    chunks_.push_back(chunk);
  }
  // Where the next parse_more() starts: after the last complete chunk.
  end_of_complete_ = chunks_.empty() || chunks_.back().complete ? end_of_complete_ + reader.position()
                                                                : chunks_.back().offset;
  return Status::ok;
}

ContainerWriter::ContainerWriter() {
  for (std::uint8_t byte : container::kMagic) writer_.u8(byte);
  writer_.u8(container::kFormatVersion);
  writer_.u8(0);   // flags: none defined
  writer_.u16(0);  // reserved
}

void ContainerWriter::add_chunk(std::uint32_t tag, std::span<const std::uint8_t> payload) {
  writer_.u32(tag);
  writer_.varint(payload.size());
  writer_.bytes(payload);
  writer_.u32(chunk_checksum(payload));
}

std::vector<std::uint8_t> ContainerWriter::finish() {
  std::vector<std::uint8_t> file = writer_.take();
  *this = ContainerWriter();
  return file;
}

Status truncate_file(std::span<const std::uint8_t> file, std::size_t max_bytes,
                     std::vector<std::uint8_t>& out, const ContainerLimits& limits) {
  out.clear();
  ContainerReader whole;
  if (const Status status = whole.parse(file, limits); status != Status::ok) return status;
  if (max_bytes < container::kFileHeaderBytes) return Status::truncated;

  ContainerWriter writer;
  for (const Chunk& chunk : whole.chunks()) {
    if (chunk.offset >= max_bytes) break;
    // The payload bytes inside the prefix: chunk header = tag + length varint.
    const std::size_t payload_offset = chunk.offset + 4 + varint_size(chunk.declared_size);
    std::size_t kept = 0;
    if (max_bytes > payload_offset) kept = std::min(chunk.payload.size(), max_bytes - payload_offset);
    const bool whole_chunk = chunk.complete && max_bytes >= payload_offset + chunk.payload.size() + 4;
    if (whole_chunk || kept > 0) writer.add_chunk(chunk.tag, chunk.payload.first(kept));
    if (!whole_chunk) break;
  }
  out = writer.finish();
  return Status::ok;
}

}  // namespace meshlift
