// Joining the vertices of a mesh that sit at exactly the same place: files whose pieces, or whose
// UV seams, were written with vertices of their own (validate.h counts them as duplicate
// vertices). Without it each side of such a seam is a boundary of its own, and the remesh keeps
// it open.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

struct Welding {
  /// The vertices at distinct positions, in the order of their first occurrence, and the faces
  /// on them, in their order, less the ones below.
  TriangleMesh mesh;
  std::size_t joined_vertices = 0;  ///< vertices joined into an earlier one at the same position
  std::size_t dropped_faces = 0;    ///< faces with two corners at the same position (no area)
  std::size_t duplicate_faces = 0;  ///< faces with the same corners, in the same turn, as an earlier one
};

/// For each vertex of the xyz array `positions`, the lowest index of a vertex at exactly the same
/// position (coordinates equal as numbers: -0 and +0 alike); itself for the first there and for a
/// non-finite position. The one definition of "coincident": validate_mesh() counts the vertices
/// that are not their own (duplicate_vertices), weld_coincident() joins them.
std::vector<std::uint32_t> first_at_same_position(std::span<const double> positions);

/// The vertices that are not their own first_at_same_position(): those that coincide with an
/// earlier one (validate_mesh()'s duplicate_vertices, a recognized remesh's coincident_vertices).
std::size_t coincident_vertex_count(std::span<const double> positions);

/// Joins every vertex into the first one at exactly the same position (coordinates equal as
/// numbers: -0 and +0 alike; non-finite positions are never joined). A face whose corners become
/// the same vertex twice is dropped, and so is a face that becomes a copy of an earlier one (two
/// pieces that both held it); a face and its reverse are both kept, for the validation to name.
/// Vertices no face uses are kept (as in the input).
/// \pre every index of `mesh.triangles` is below its vertex count (read_mesh guarantees it).
Welding weld_coincident(const TriangleMesh& mesh);

}  // namespace meshlift
