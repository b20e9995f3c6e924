// Flat mesh types shared by every module: contiguous xyz positions and index arrays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace meshlift {

/// Marks a missing index (a boundary edge's absent face, a base vertex's absent parent).
inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Triangle mesh as plain arrays: positions[3*v+k] is coordinate k of vertex v,
/// triangles[3*f+i] is corner i of face f (counter-clockwise seen from outside).
struct TriangleMesh {
  std::vector<double> positions;
  std::vector<std::uint32_t> triangles;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return triangles.size() / 3; }
};

/// Polygon mesh (quads for Catmull-Clark, any n-gons): face f has corners
/// face_indices[face_offsets[f] .. face_offsets[f+1]). face_offsets has face_count()+1 entries.
struct PolygonMesh {
  std::vector<double> positions;
  std::vector<std::uint32_t> face_offsets{0};
  std::vector<std::uint32_t> face_indices;
  /// Per-vertex colours, if the file had them: red, green, blue of each vertex in [0, 1]
  /// (3 per vertex), else empty.
  std::vector<double> colors;
  /// What else the file held, which the mesh does not carry (mesh_io.h: read_mesh), one entry per
  /// kind, e.g. "texture coordinates (OBJ vt)" or "PLY vertex properties nx, ny, nz"; empty when
  /// nothing was left out.
  std::vector<std::string> not_read;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  std::size_t face_size(std::size_t f) const { return face_offsets[f + 1] - face_offsets[f]; }
  bool is_triangle_mesh() const;
};

/// A caller handed a mesh that breaks a documented precondition (non-manifold, not triangles, ...).
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The triangles of a polygon mesh; throws MeshError if a face is not a triangle.
TriangleMesh to_triangle_mesh(const PolygonMesh& mesh);
/// The same, taking over the mesh's arrays instead of copying them (a 3.3 M-vertex mesh: 160 MB
/// not copied); `mesh` is left empty. On a MeshError it is left as it was.
TriangleMesh to_triangle_mesh(PolygonMesh&& mesh);
/// A triangle mesh viewed as a polygon mesh.
PolygonMesh to_polygon_mesh(const TriangleMesh& mesh);

/// Length of the bounding-box diagonal (0 for an empty mesh).
double bounding_box_diagonal(const std::vector<double>& positions);

}  // namespace meshlift
