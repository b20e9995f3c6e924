#include "meshlift/mesh.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace meshlift {

bool PolygonMesh::is_triangle_mesh() const {
  for (std::size_t f = 0; f < face_count(); ++f)
    if (face_size(f) != 3) return false;
  return true;
}

namespace {

/// Throws MeshError naming the first face that is not a triangle. When there is none, the faces'
/// corners are the 3 F indices from face_indices[face_offsets[0]] on, triangle by triangle.
/// Returns that first index.
std::size_t require_triangles(const PolygonMesh& mesh) {
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    if (mesh.face_size(f) != 3)
      throw MeshError("face " + std::to_string(f) + " has " + std::to_string(mesh.face_size(f)) +
                      " corners; a triangle mesh is required");
  return mesh.face_count() > 0 ? mesh.face_offsets[0] : 0;
}

}  // namespace

TriangleMesh to_triangle_mesh(const PolygonMesh& mesh) {
  const auto first = static_cast<std::ptrdiff_t>(require_triangles(mesh));
  TriangleMesh out;
  out.positions = mesh.positions;
  out.triangles.assign(mesh.face_indices.begin() + first,
                       mesh.face_indices.begin() + first + 3 * static_cast<std::ptrdiff_t>(mesh.face_count()));
  return out;
}

TriangleMesh to_triangle_mesh(PolygonMesh&& mesh) {
  if (require_triangles(mesh) != 0) {  // faces that do not start at index 0: copied
    TriangleMesh out = to_triangle_mesh(std::as_const(mesh));
    mesh = PolygonMesh{};
    return out;
  }
  TriangleMesh out;
  out.positions = std::move(mesh.positions);
  out.triangles = std::move(mesh.face_indices);
  out.triangles.resize(3 * std::size_t{mesh.face_count()});
  mesh = PolygonMesh{};
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
