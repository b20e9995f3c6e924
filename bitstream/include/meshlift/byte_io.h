// Little-endian fixed-width integers and LEB128 varints: a growing writer and a bounds-checked
// reader over untrusted bytes (FORMAT.md §0 defines the encodings).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/status.h"

namespace meshlift {

/// Longest LEB128 encoding of a 64-bit value.
inline constexpr std::size_t kMaxVarintBytes = 10;

/// Appends encoded values to a byte vector. May throw std::bad_alloc.
class ByteWriter {
 public:
  void u8(std::uint8_t value) { bytes_.push_back(value); }
  void u16(std::uint16_t value) { fixed(value, 2); }
  void u32(std::uint32_t value) { fixed(value, 4); }
  void u64(std::uint64_t value) { fixed(value, 8); }
  /// Unsigned LEB128: 7 bits per byte, least significant group first, high bit = "more follows".
  void varint(std::uint64_t value);
  void bytes(std::span<const std::uint8_t> data) { bytes_.insert(bytes_.end(), data.begin(), data.end()); }

  std::size_t size() const { return bytes_.size(); }
  const std::vector<std::uint8_t>& data() const { return bytes_; }
  /// Moves the bytes out; the writer is empty afterwards.
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  void fixed(std::uint64_t value, int count);
  std::vector<std::uint8_t> bytes_;
};

/// Number of bytes ByteWriter::varint writes for `value` (1..10).
std::size_t varint_size(std::uint64_t value);

/// Reads encoded values from a span it does not own. Never reads past the end, never throws,
/// never allocates. Errors are sticky: after the first failure every read fails with the same
/// status, sets its output to 0 (or an empty span) and leaves position() where the failure was.
/// The failing read itself consumes nothing.
class ByteReader {
 public:
  ByteReader() = default;
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  Status u8(std::uint8_t& value);
  Status u16(std::uint16_t& value);
  Status u32(std::uint32_t& value);
  Status u64(std::uint64_t& value);
  /// LEB128 as written by ByteWriter::varint. truncated if the input ends inside it; corrupt if
  /// it is longer than 10 bytes, overflows 64 bits, or is not minimal (a final byte of 0 after
  /// other bytes): every value has exactly one valid encoding.
  Status varint(std::uint64_t& value);
  /// A view of the next `count` bytes (no copy); truncated if fewer remain.
  Status bytes(std::size_t count, std::span<const std::uint8_t>& view);
  Status skip(std::size_t count);

  Status status() const { return status_; }
  bool ok() const { return status_ == Status::ok; }
  std::size_t position() const { return position_; }
  std::size_t remaining() const { return bytes_.size() - position_; }
  std::span<const std::uint8_t> rest() const { return bytes_.subspan(position_); }

 private:
  template <typename T>
  Status fixed(T& value);
  Status fail(Status status) { return status_ = status; }

  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;
  Status status_ = Status::ok;
};

}  // namespace meshlift
