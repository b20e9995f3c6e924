// Hand-written .mlz streams for the hostile-input tests (codec and CLI alike).
#pragma once

#include <cstdint>
#include <vector>

#include "meshlift/byte_io.h"
#include "meshlift/container.h"

namespace meshlift::test {

/// A stream whose HEAD (FORMAT.md §3) claims `base_vertices`, `base_faces` and `levels` and stops
/// after the counts, with nothing else: 24 bytes for small counts, 34 for two 6-byte varints.
inline std::vector<std::uint8_t> claiming(std::uint64_t base_vertices, std::uint64_t base_faces, std::uint8_t levels) {
  meshlift::ByteWriter head;
  // scheme Loop, no flags, levels, top_plane + 1 = 1, base_plane = 1 (no base part)
  for (std::uint8_t b : {std::uint8_t{2}, std::uint8_t{0}, levels, std::uint8_t{1}, std::uint8_t{1}}) head.u8(b);
  head.varint(base_vertices);
  head.varint(base_faces);
  meshlift::ContainerWriter writer;
  writer.add_chunk(meshlift::kTagHeader, head.data());
  return writer.finish();
}

}  // namespace meshlift::test
