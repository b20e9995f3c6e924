#include "meshlift/mesh.h"

#include <algorithm>
#include <cmath>

namespace meshlift {

bool PolygonMesh::is_triangle_mesh() const {
  for (std::size_t f = 0; f < face_count(); ++f)
    if (face_size(f) != 3) return false;
  return true;
}

TriangleMesh to_triangle_mesh(const PolygonMesh& mesh) {
  TriangleMesh out;
  out.positions = mesh.positions;
  out.triangles.reserve(mesh.face_indices.size());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    if (mesh.face_size(f) != 3)
      throw MeshError("face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                      " corners; a triangle mesh is required");
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c)
      out.triangles.push_back(mesh.face_indices[c]);
  }
  return out;
}

PolygonMesh to_polygon_mesh(const TriangleMesh& mesh) {
  PolygonMesh out;
  out.positions = mesh.positions;
  out.face_indices = mesh.triangles;
  out.face_offsets.resize(mesh.face_count() + 1);
  for (std::size_t f = 0; f <= mesh.face_count(); ++f) out.face_offsets[f] = static_cast<std::uint32_t>(3 * f);
  return out;
}

double bounding_box_diagonal(const std::vector<double>& positions) {
  if (positions.size() < 3) return 0.0;
  double lo[3] = {positions[0], positions[1], positions[2]};
  double hi[3] = {lo[0], lo[1], lo[2]};
  for (std::size_t i = 0; i < positions.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], positions[i + k]);
      hi[k] = std::max(hi[k], positions[i + k]);
    }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

}  // namespace meshlift
