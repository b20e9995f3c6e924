// Numbered, stable status codes for everything that reads untrusted bytes.
//
// The numeric values are part of the format (bitstream/FORMAT.md §6): they appear in CLI exit
// codes and golden error tests, so they are frozen. New codes get new numbers; none is ever
// renumbered or reused.
#pragma once

#include <cstdint>

namespace meshlift {

enum class Status : std::uint8_t {
  ok = 0,                   ///< success
  truncated = 1,            ///< the input ends before a required field is complete
  bad_magic = 2,            ///< not a meshlift file (the first four bytes are not "MLZ\x1A")
  unsupported_version = 3,  ///< a format version this build cannot read
  corrupt = 4,              ///< a field holds an impossible value
  checksum_mismatch = 5,    ///< a complete chunk's payload does not match its checksum
  limit_exceeded = 6,       ///< a declared size or count is above the caller's limits
  reserved_bits_set = 7,    ///< a reserved field or flag that must be zero is not
  io_error = 8,             ///< the operating system failed to read or write a file
};

/// Short stable name, e.g. "checksum_mismatch" (for logs, tests and machine-readable output).
/// Unknown values give "unknown".
constexpr const char* to_string(Status status) {
  switch (status) {
    case Status::ok: return "ok";
    case Status::truncated: return "truncated";
    case Status::bad_magic: return "bad_magic";
    case Status::unsupported_version: return "unsupported_version";
    case Status::corrupt: return "corrupt";
    case Status::checksum_mismatch: return "checksum_mismatch";
    case Status::limit_exceeded: return "limit_exceeded";
    case Status::reserved_bits_set: return "reserved_bits_set";
    case Status::io_error: return "io_error";
  }
  return "unknown";
}

/// One sentence a user can act on. Unknown values give a generic sentence.
constexpr const char* describe(Status status) {
  switch (status) {
    case Status::ok:
      return "No error.";
    case Status::truncated:
      return "The data ends too early; the file was cut short or is still being written. "
             "Re-fetch the complete file (a meshlift stream cut after its header still decodes "
             "to a coarser mesh).";
    case Status::bad_magic:
      return "This is not a meshlift (.mlz) file: it does not start with the bytes 'MLZ' 0x1A. "
             "Check the file name or that the download was not replaced by an error page.";
    case Status::unsupported_version:
      return "The file uses a format version this build of meshlift cannot read; "
             "upgrade meshlift.";
    case Status::corrupt:
      return "The file is damaged: a field holds a value no encoder writes. Re-fetch or re-encode it.";
    case Status::checksum_mismatch:
      return "The file is damaged: a chunk's checksum does not match its contents. "
             "Re-fetch the file; it was altered in storage or transfer.";
    case Status::limit_exceeded:
      return "The file declares more data than the configured limits allow; raise the limits "
             "if you trust the file.";
    case Status::reserved_bits_set:
      return "The file sets reserved bits that must be zero: it was written by a newer or "
             "faulty encoder. Upgrade meshlift or re-encode the file.";
    case Status::io_error:
      return "The file could not be read or written; check the path, permissions and free space.";
  }
  return "Unknown status code; this build of meshlift is older than the code that produced it.";
}

}  // namespace meshlift
