// Geometry image files: a 16-bit RGB PNG (quantized, with its de-normalizing box in a tEXt
// chunk) and a lossless float format (.gim). Formats in docs/CLI.md ("Geometry image files").
//
// PNG: width = height = n, colour type 2 (RGB), bit depth 16, not interlaced. Sample k of pixel
// (r, c) stores Q = round((x_k − lo_k) / (hi_k − lo_k) · 65535) (0 when hi_k = lo_k); reading
// gives x_k = lo_k + Q / 65535 · (hi_k − lo_k), so each coordinate is off by at most
// (hi_k − lo_k) / 131070. tEXt chunk, keyword "meshlift-bbox", text: the six numbers
// "lo_x lo_y lo_z hi_x hi_y hi_z" in decimal (written with 17 significant digits), separated
// by single spaces. A second tEXt chunk, keyword "meshlift-layout", says "octahedral".
//
// .gim (little-endian throughout):
//   offset 0   4 bytes  magic "MGIM"
//   offset 4   u32      version = 1
//   offset 8   u32      n (image side, 2^(L+1) + 1, at most kMaxGeometryImageSize)
//   offset 12  u32      channels = 3
//   offset 16  u32      bytes per sample: 4 (IEEE-754 float32) or 8 (float64)
//   offset 20  n·n·3 samples, row-major, x y z per pixel (pixel (r, c) at index 3 (r n + c))
// and nothing after them.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "meshlift/geometry_image.h"

namespace meshlift {

/// The PNG bytes of `image`. \throw MeshError if the image is empty, its side is not a valid
/// size, or a sample is not finite.
std::vector<std::uint8_t> encode_geometry_image_png(const GeometryImage& image);
/// \throw MeshIOError (mesh_io.h) naming the problem if the bytes are not a 16-bit RGB PNG of a
///        valid side with a well-formed "meshlift-bbox" chunk. Never reads out of bounds.
GeometryImage decode_geometry_image_png(std::span<const std::uint8_t> bytes);

/// The .gim bytes of `image` with float64 (bytes_per_sample 8, lossless) or float32 samples.
std::vector<std::uint8_t> encode_geometry_image_gim(const GeometryImage& image, int bytes_per_sample = 8);
/// \throw MeshIOError naming the problem (bad magic, unsupported version, bad size, truncated,
///        trailing bytes, non-finite sample).
GeometryImage decode_geometry_image_gim(std::span<const std::uint8_t> bytes);

/// Reads / writes by extension (.png or .gim, case-insensitive); writes go to a temporary file
/// renamed into place. \throw MeshIOError naming the file and the problem.
GeometryImage read_geometry_image(const std::string& path);
void write_geometry_image(const std::string& path, const GeometryImage& image);

}  // namespace meshlift
