// Topological and geometric checks of a raw mesh: manifoldness, boundaries, orientation,
// Euler characteristic and genus, degenerate elements. Definitions follow the seed text
// "Meshes" chapter (manifold meshes 8.3.1, boundaries 8.3.1.2, orientation 8.3.1.1/8.3.1.3,
// nonmanifold meshes 8.3.2, orientation by search: exercise 8.6).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// One connected component of faces (faces are connected when they share a vertex).
struct ComponentReport {
  std::uint64_t vertices = 0;        ///< referenced vertices
  std::uint64_t faces = 0;
  std::uint64_t edges = 0;
  std::int64_t euler = 0;            ///< χ = V − E + F of the component
  std::uint64_t boundary_loops = 0;
  bool closed = false;               ///< no boundary edge
  bool manifold = false;             ///< no non-manifold edge or vertex
  bool orientable = false;
  /// g = (2 − χ − b) / 2 for a manifold orientable component, −1 otherwise.
  std::int64_t genus = -1;
  std::uint32_t first_face = kNone;  ///< lowest face index in the component
};

/// Everything validate_mesh() finds. Counts are exact; "first_*" fields name the lowest
/// offending face (kNone if there is none).
///
/// Faces enter the topology (edges, components, boundaries, orientation, χ) only when they are
/// *usable*: at least 3 corners, every index names an existing vertex, no repeated index.
/// Other faces are counted in invalid_index_faces / degenerate_faces and otherwise ignored.
struct MeshReport {
  /// Non-empty when the arrays themselves are inconsistent (positions not a multiple of 3,
  /// face_offsets not starting at 0, decreasing, or not ending at face_indices.size()); the
  /// rest of the report is then empty apart from `vertices`.
  std::string structure_error;

  std::uint64_t vertices = 0;             ///< vertex_count(), including isolated ones
  bool vertex_colours = false;            ///< a colour per vertex (PolygonMesh::colors)
  std::uint64_t faces = 0;                ///< face_count(), including unusable ones
  std::uint64_t non_triangle_faces = 0;   ///< faces whose corner count is not 3
  std::uint32_t first_non_triangle_face = kNone;
  std::uint64_t first_non_triangle_face_corners = 0;
  std::uint64_t invalid_index_faces = 0;  ///< faces with a corner naming a missing vertex
  std::uint64_t invalid_indices = 0;      ///< such corners
  std::uint32_t first_invalid_index_face = kNone;
  std::uint64_t degenerate_faces = 0;     ///< fewer than 3 corners, or a repeated vertex index
  std::uint32_t first_degenerate_face = kNone;
  /// Usable faces of area <= kZeroAreaFactor · bbox_diagonal² (area of a polygon from its
  /// vector area ½|Σ p_i × p_{i+1}|). Faces with a non-finite corner are not counted here.
  std::uint64_t zero_area_faces = 0;

  std::uint64_t edges = 0;                ///< distinct undirected edges of usable faces
  std::uint64_t boundary_edges = 0;       ///< edges with exactly one face
  std::uint64_t non_manifold_edges = 0;   ///< edges with more than two faces
  /// The lowest non-manifold edge (by its vertex pair, smaller first); kNone, kNone if none.
  std::uint32_t first_non_manifold_edge[2] = {kNone, kNone};
  /// Boundary edges grouped into loops by shared vertices (loops that touch at a
  /// non-manifold vertex count as one; such vertices are reported below).
  std::uint64_t boundary_loops = 0;
  /// Vertices whose incident usable faces form more than one fan, fans being joined only across
  /// manifold (two-face) edges through the vertex: pinch points, and the ends of non-manifold edges.
  std::uint64_t non_manifold_vertices = 0;
  std::uint32_t first_non_manifold_vertex = kNone;  ///< the lowest such vertex

  /// A choice of face orientations exists that makes every manifold edge traversed in opposite
  /// directions by its two faces (found by breadth-first propagation, exercise 8.6).
  bool orientable = true;
  /// Every manifold edge already is traversed in opposite directions by its two faces.
  bool consistently_oriented = true;
  std::uint64_t inconsistent_edges = 0;   ///< manifold edges traversed the same way by both faces
  /// The lowest such edge (by its vertex pair, smaller first); kNone, kNone if none.
  std::uint32_t first_inconsistent_edge[2] = {kNone, kNone};

  std::uint64_t referenced_vertices = 0;  ///< vertices used by at least one usable face
  std::uint64_t isolated_vertices = 0;    ///< vertices named by no face corner at all
  std::int64_t euler_characteristic = 0;  ///< referenced_vertices − edges + usable faces
  std::uint64_t connected_components = 0; ///< of usable faces, joined through shared vertices
  /// Components in order of decreasing face count (ties: lower first face first).
  std::vector<ComponentReport> components;

  std::uint64_t duplicate_vertices = 0;   ///< extra copies of exactly equal finite positions
  std::uint64_t non_finite_vertices = 0;  ///< a NaN or infinite coordinate
  std::uint32_t first_non_finite_vertex = kNone;
  double bbox_diagonal = 0.0;             ///< over finite vertices only
  /// Pairs of faces that cut through each other (self_intersection.h); set only by
  /// add_self_intersections(), which `meshlift info` calls (unset: not checked).
  std::optional<std::uint64_t> self_intersecting_pairs;
  std::uint32_t first_self_intersection[2] = {kNone, kNone};  ///< the lowest such pair

  /// No non-manifold edge or vertex.
  bool is_manifold() const { return non_manifold_edges == 0 && non_manifold_vertices == 0; }
  /// At least one face, and no boundary edge.
  bool is_closed() const { return faces > 0 && boundary_edges == 0; }
};

/// Relative threshold for zero_area_faces: area <= kZeroAreaFactor · bbox_diagonal².
/// 1e-14 is the area of a right triangle with legs of about 1.4e-7 · diagonal, i.e. at the
/// resolution of float coordinates (what mesh files and OpenMesh's readers carry).
inline constexpr double kZeroAreaFactor = 1e-14;

/// Whether some face has an area above kZeroAreaFactor · bbox_diagonal² (the complement of
/// "every face has zero area" in validate_mesh's terms), stopping at the first.
/// \pre every index is below the vertex count and the coordinates are finite.
bool has_nonzero_area_face(const TriangleMesh& mesh);

/// Checks `mesh` and reports what it finds. Never throws on bad data and never reads out of
/// bounds: arbitrary arrays (out-of-range indices, broken offsets, NaN) are reported, not trusted.
/// O(n log n) in the number of corners.
MeshReport validate_mesh(const PolygonMesh& mesh);
/// Same for a triangle mesh (a trailing partial triangle is reported as a structure_error).
MeshReport validate_mesh(const TriangleMesh& mesh);

/// Fills report.self_intersecting_pairs and first_self_intersection for a triangle mesh whose
/// report names no problem for the triangle codec (first_problem_for_triangle_codec() empty)
/// and whose coordinates are within ±1e30 (what the BVH's floats hold); otherwise leaves them
/// unset. Not part of validate_mesh(): a BVH query, needed by inspection
/// (`meshlift info`) and the remesher's fold report, not by every reader of a mesh.
void add_self_intersections(const PolygonMesh& mesh, MeshReport& report);

/// "" when the mesh can enter the triangle codec: at least one face, every face a triangle with
/// valid distinct indices, finite coordinates, manifold, orientable and consistently oriented
/// (boundaries, several components, isolated or duplicate vertices and zero-area faces are
/// allowed). Otherwise a one-line message naming the first problem with its count, e.g.
/// "3 non-manifold edges" or "face 17 has 4 corners: triangles required".
std::string first_problem_for_triangle_codec(const MeshReport& report);

/// What to do about the problem first_problem_for_triangle_codec() names (the same one, found in
/// the same order), in one line, e.g. "keep at most two faces on each edge: ..."; "" when there
/// is none or no advice beyond the problem itself. (A caller that can weld or orient, as the CLI
/// can, checks first whether that repairs the mesh.)
std::string how_to_repair(const MeshReport& report);

/// Human-readable report, one aligned "name: value" line per field, then the components
/// (the 10 largest).
std::string to_text(const MeshReport& report);

/// The report as one JSON object with stable keys (the MeshReport field names; first_* fields
/// are null when absent); "components" lists the 100 largest and "components_listed" says how
/// many are listed.
std::string to_json(const MeshReport& report);

}  // namespace meshlift
