// Per-vertex values carried onto another mesh by closest points. See transfer.h.
#include "meshlift/transfer.h"

#include <string>

#include "parallel.h"

namespace meshlift {

std::vector<double> transfer_vertex_values(const SurfaceQuery& surface, std::span<const double> values, int components,
                                           std::span<const double> points, unsigned threads) {
  const TriangleMesh& source = surface.mesh();
  const auto m = static_cast<std::size_t>(components);
  if (components < 1 || values.size() != m * source.vertex_count())
    throw MeshError("transfer_vertex_values: " + std::to_string(values.size()) + " values for " +
                    std::to_string(source.vertex_count()) + " vertices of " + std::to_string(components) + " components");
  const std::size_t n = points.size() / 3;
  std::vector<double> out(n * m);
  parallel_blocks(n, threads, [&](std::size_t begin, std::size_t end) {
    std::uint32_t hint = kNone;  // the previous point's face: neighbours in a mesh's order are near
    for (std::size_t i = begin; i < end; ++i) {
      const SurfacePoint s = surface.closest({points[3 * i], points[3 * i + 1], points[3 * i + 2]}, hint);
      hint = s.face;
      const std::uint32_t* corners = &source.triangles[3 * std::size_t{s.face}];
      for (std::size_t k = 0; k < m; ++k) {
        double value = 0;
        for (int c = 0; c < 3; ++c) value += s.barycentric[static_cast<std::size_t>(c)] * values[m * corners[c] + k];
        out[m * i + k] = value;
      }
    }
  });
  return out;
}

}  // namespace meshlift
