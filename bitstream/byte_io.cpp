// Byte I/O: little-endian fixed-width integers and unsigned LEB128 varints (FORMAT.md §2).
#include "meshlift/byte_io.h"

namespace meshlift {

void ByteWriter::fixed(std::uint64_t value, int count) {
  for (int i = 0; i < count; ++i) bytes_.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

void ByteWriter::varint(std::uint64_t value) {
  while (value >= 0x80) {
    bytes_.push_back(static_cast<std::uint8_t>(value | 0x80));
    value >>= 7;
  }
  bytes_.push_back(static_cast<std::uint8_t>(value));
}

std::size_t varint_size(std::uint64_t value) {
  std::size_t size = 1;
  while (value >= 0x80) {
    value >>= 7;
    ++size;
  }
  return size;
}

template <typename T>
Status ByteReader::fixed(T& value) {
  value = 0;
  if (status_ != Status::ok) return status_;
  if (remaining() < sizeof(T)) return fail(Status::truncated);
  T result = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    result = static_cast<T>(result | (static_cast<T>(bytes_[position_ + i]) << (8 * i)));
  }
  position_ += sizeof(T);
  value = result;
  return Status::ok;
}

Status ByteReader::u8(std::uint8_t& value) { return fixed(value); }
Status ByteReader::u16(std::uint16_t& value) { return fixed(value); }
Status ByteReader::u32(std::uint32_t& value) { return fixed(value); }
Status ByteReader::u64(std::uint64_t& value) { return fixed(value); }

// Byte i carries bits 7i .. 7i+6. The 10th byte (i = 9) holds bit 63 only, so it must be 0 or 1;
// anything longer or larger cannot be a 64-bit value. A final 0 byte after others would encode
// the same value as a shorter form and is rejected so encodings are unique.
Status ByteReader::varint(std::uint64_t& value) {
  value = 0;
  if (status_ != Status::ok) return status_;
  std::uint64_t result = 0;
  for (std::size_t i = 0; i < kMaxVarintBytes; ++i) {
    if (position_ + i >= bytes_.size()) return fail(Status::truncated);
    const std::uint8_t byte = bytes_[position_ + i];
    if (i == kMaxVarintBytes - 1 && byte > 1) return fail(Status::corrupt);
    result |= static_cast<std::uint64_t>(byte & 0x7F) << (7 * i);
    if ((byte & 0x80) == 0) {
      if (byte == 0 && i > 0) return fail(Status::corrupt);
      position_ += i + 1;
      value = result;
      return Status::ok;
    }
  }
  return fail(Status::corrupt);
}

Status ByteReader::bytes(std::size_t count, std::span<const std::uint8_t>& view) {
  view = {};
  if (status_ != Status::ok) return status_;
  if (remaining() < count) return fail(Status::truncated);
  view = bytes_.subspan(position_, count);
  position_ += count;
  return Status::ok;
}

Status ByteReader::skip(std::size_t count) {
  if (status_ != Status::ok) return status_;
  if (remaining() < count) return fail(Status::truncated);
  position_ += count;
  return Status::ok;
}

}  // namespace meshlift
