// Byte files for the CLI: whole-file reads, and writes that go to a temporary file in the same
// directory and are renamed into place, so a failed or interrupted run never leaves a partial file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace meshlift::cli {

/// Reads a whole file; returns false and sets `error` (one line) on failure.
bool read_bytes(const std::string& path, std::vector<std::uint8_t>& bytes, std::string& error);
/// Writes atomically (temporary file + rename); returns false and sets `error` on failure.
bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes, std::string& error);

}  // namespace meshlift::cli
