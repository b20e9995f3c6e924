// The .mlz container (FORMAT.md §1-§2): an 8-byte file header, then chunks of
//   u32 tag | varint payload length | payload | u32 checksum (low 32 bits of XXH3_64bits(payload)).
// Knows bytes only: what a payload means is the codec's business.
//
// A file may be cut at any byte (embedded streams are meant to be truncated): the reader then
// returns the chunks before the cut as complete and the cut chunk as incomplete with the
// payload bytes present, so its embedded stream can still be decoded as a prefix.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "meshlift/byte_io.h"
#include "meshlift/status.h"

namespace meshlift {

namespace container {
inline constexpr std::uint8_t kMagic[4] = {'M', 'L', 'Z', 0x1A};
/// The only version this build reads and writes (FORMAT.md change log: each version changed how
/// the coefficients are coded, so an older stream is refused, not misread).
inline constexpr std::uint8_t kFormatVersion = 5;
inline constexpr std::size_t kFileHeaderBytes = 8;
inline constexpr std::size_t kChecksumBytes = 4;
/// Smallest possible chunk: tag, one-byte length 0, checksum.
inline constexpr std::size_t kMinChunkBytes = 4 + 1 + kChecksumBytes;
}  // namespace container

/// A chunk tag: four ASCII characters stored in file order, read as a little-endian u32.
constexpr std::uint32_t make_tag(char a, char b, char c, char d) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(a)) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(b)) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(c)) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(d)) << 24;
}

/// Tags defined by format version 1 (FORMAT.md §2.3).
inline constexpr std::uint32_t kTagHeader = make_tag('H', 'E', 'A', 'D');
inline constexpr std::uint32_t kTagBaseMesh = make_tag('B', 'A', 'S', 'E');
inline constexpr std::uint32_t kTagCoefficients = make_tag('C', 'O', 'E', 'F');

/// A tag whose first character is an uppercase ASCII letter is critical: a reader that does not
/// know it cannot decode the file correctly (FORMAT.md §2.4). Any other unknown tag is
/// ancillary and is skipped.
constexpr bool is_critical_tag(std::uint32_t tag) {
  const std::uint32_t first = tag & 0xFF;
  return first >= 'A' && first <= 'Z';
}

/// The four characters of a tag, non-printable bytes as \xNN (for messages).
std::string tag_to_string(std::uint32_t tag);

/// Caps checked before anything sized by the file is allocated.
struct ContainerLimits {
  std::uint64_t max_chunk_bytes = std::uint64_t{1} << 30;  ///< largest declared payload (1 GiB)
  std::size_t max_chunks = 1u << 16;                       ///< most chunks in one file
};

/// One chunk as found in the input. `payload` points into the parsed span (no copy).
struct Chunk {
  std::uint32_t tag = 0;  ///< 0 if the file was cut inside the tag itself
  std::span<const std::uint8_t> payload;  ///< the payload bytes present (all of them if complete)
  std::uint64_t declared_size = 0;  ///< payload length from the chunk header (0 if cut before it)
  std::size_t offset = 0;           ///< file offset of the chunk's first byte (its tag)
  bool complete = false;     ///< header, whole payload and checksum present
  bool checksum_ok = false;  ///< checksum verified (complete chunks only)
};

/// Where parsing stopped and why. offset is the file offset of the offending field: the header
/// byte for file-header errors, the chunk's first byte for chunk errors.
struct ContainerError {
  Status status = Status::ok;
  std::size_t offset = 0;
  std::size_t chunk_index = 0;  ///< index of the offending chunk (chunk errors only)
};

/// Parses a whole or truncated file. Never throws, never reads outside the input, allocates
/// only the chunk list (at most one entry per 9 input bytes and at most limits.max_chunks).
class ContainerReader {
 public:
  /// Returns ok for any file that is a prefix of a valid file cut after its 8-byte header (the
  /// cut chunk, if any, comes last with complete == false). Otherwise the first error, in file
  /// order: truncated (cut inside the file header), bad_magic, unsupported_version,
  /// reserved_bits_set, limit_exceeded, checksum_mismatch, corrupt (a malformed length varint).
  /// bad_magic is reported as soon as any present magic byte is wrong, even in a short file.
  /// On error, chunks() holds the chunks verified before the offending one.
  Status parse(std::span<const std::uint8_t> file, const ContainerLimits& limits = {});
  /// parse() of a longer prefix of the file parsed before (its first bytes the same, perhaps at
  /// another address): the complete chunks found before are kept, and only the bytes from the
  /// end of the last of them on are read (a streaming decoder's push, O(new bytes)). The same
  /// result as parse(file). After an error or a cut inside the file header, parses `file` whole.
  Status parse_more(std::span<const std::uint8_t> file, const ContainerLimits& limits = {});

  /// Every entry is complete with its checksum verified, except possibly the last, which is
  /// incomplete if the file was cut inside it. Unknown tags are included as they are.
  const std::vector<Chunk>& chunks() const { return chunks_; }
  const ContainerError& error() const { return error_; }
  Status status() const { return error_.status; }
  std::uint8_t version() const { return version_; }
  /// True if the file ends inside a chunk (the last chunk is incomplete). A cut exactly between
  /// two chunks cannot be seen here; the codec's header chunk says what should follow.
  bool truncated() const { return !chunks_.empty() && !chunks_.back().complete; }
  /// The first chunk with `tag`, or nullptr.
  const Chunk* find(std::uint32_t tag) const;

 private:
  Status fail(Status status, std::size_t offset, std::size_t chunk_index = 0);
  /// Reads chunks from end_of_complete_ on, appending to chunks_.
  Status parse_chunks(std::span<const std::uint8_t> file, const ContainerLimits& limits);

  const std::uint8_t* base_ = nullptr;  ///< the file parsed last (chunks' payloads point into it)
  std::size_t end_of_complete_ = container::kFileHeaderBytes;  ///< offset after the last complete chunk
  std::vector<Chunk> chunks_;
  ContainerError error_;
  std::uint8_t version_ = 0;
};

/// Builds a file: the header, then chunks in the order added.
class ContainerWriter {
 public:
  ContainerWriter();
  void add_chunk(std::uint32_t tag, std::span<const std::uint8_t> payload);
  /// Bytes of the file so far (what finish() would return now).
  std::size_t size() const { return writer_.size(); }
  /// Returns the file; the writer starts a new file afterwards.
  std::vector<std::uint8_t> finish();

 private:
  ByteWriter writer_;
};

/// The low 32 bits of XXH3_64bits(payload): the chunk checksum.
std::uint32_t chunk_checksum(std::span<const std::uint8_t> payload);

/// Rewrites the first `max_bytes` bytes of `file` as a valid, complete file into `out`: the
/// chunks complete within the prefix are copied, the chunk the cut falls in is rewritten as a
/// complete chunk holding the payload bytes the prefix has (length and checksum recomputed;
/// dropped if none), so the result parses with every chunk complete and decodes exactly as the
/// prefix does. The output can be up to 4 bytes longer than max_bytes (the new checksum).
/// The whole input is validated first, so a damaged chunk is never given a fresh checksum.
/// Returns the input's parse status (out is empty unless ok), or truncated if max_bytes < 8.
Status truncate_file(std::span<const std::uint8_t> file, std::size_t max_bytes,
                     std::vector<std::uint8_t>& out, const ContainerLimits& limits = {});

}  // namespace meshlift
