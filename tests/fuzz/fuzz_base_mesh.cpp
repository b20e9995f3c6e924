// Fuzz target: the base-mesh connectivity decoder (codec/base_mesh_coder.h) on arbitrary bytes.
// A successful decode must give in-range, non-degenerate faces; when they also form a manifold
// topology, encoding them again and decoding must give the same faces back.
//
// Input layout: u16 vertex count, u16 face count (little-endian), then the coded bytes.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "base_mesh_coder.h"
#include "fuzz_check.h"
#include "meshlift/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace meshlift;
  if (size < 4) return 0;
  const std::uint32_t vertices = data[0] | std::uint32_t{data[1]} << 8;
  const std::uint32_t faces = data[2] | std::uint32_t{data[3]} << 8;
  const std::span<const std::uint8_t> bytes(data + 4, size - 4);
  std::vector<std::uint32_t> triangles;
  if (!base_mesh::decode_faces(bytes, vertices, faces, triangles)) return 0;
  if (triangles.size() != 3 * std::size_t{faces}) fuzz::violated("face count");
  for (std::size_t f = 0; f < faces; ++f) {
    const std::uint32_t a = triangles[3 * f], b = triangles[3 * f + 1], c = triangles[3 * f + 2];
    if (a >= vertices || b >= vertices || c >= vertices) fuzz::violated("vertex index out of range");
    if (a == b || b == c || a == c) fuzz::violated("repeated corner");
  }
  try {
    (void)TriangleTopology::build(vertices, triangles);
  } catch (const MeshError&) {
    return 0;  // decodable but not manifold: decode() reports corrupt for it
  }
  std::vector<std::uint32_t> again;
  if (!base_mesh::decode_faces(base_mesh::encode_faces(triangles, vertices), vertices, faces, again) || again != triangles)
    fuzz::violated("decode(encode(faces)) != faces");
  return 0;
}
