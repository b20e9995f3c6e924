// Polygon-mesh subdivision: Catmull-Clark and Doo-Sabin on the flat PolygonMesh, plus the
// half-edge view of a polygon mesh that both (and the limit stencils of limit.h) are built on.
#pragma once

#include <cstdint>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// Most subdivision levels one call accepts (each level multiplies the face count by about 4).
inline constexpr int kMaxSubdivisionLevels = 10;

/// Half-edge view of a PolygonMesh's connectivity, checked for manifoldness when built.
///
/// Half-edge h is corner h of mesh.face_indices: it runs from vertex face_indices[h] to the
/// vertex of the next corner of the same face, and the face lies on its left.
struct PolygonTopology {
  std::vector<std::uint32_t> face;      ///< face of half-edge h
  std::vector<std::uint32_t> next;      ///< next half-edge around the same face
  std::vector<std::uint32_t> prev;      ///< previous half-edge around the same face
  std::vector<std::uint32_t> opposite;  ///< the twin half-edge, kNone on a boundary edge
  std::vector<std::uint32_t> edge;      ///< undirected edge index of half-edge h
  std::vector<std::uint32_t> edge_halfedge;  ///< a half-edge of edge e (the boundary one, if any)
  /// Per vertex: the first outgoing half-edge of its fan (kNone for an isolated vertex). For a
  /// boundary vertex it is the outgoing boundary half-edge, so that walking with rotate()
  /// visits every incident face once, counter-clockwise seen from outside.
  std::vector<std::uint32_t> outgoing;
  std::vector<std::uint32_t> face_count_at;  ///< number of faces around vertex v
  std::vector<std::uint8_t> boundary;        ///< 1 if vertex v lies on a boundary

  std::size_t edge_count() const { return edge_halfedge.size(); }
  /// The next outgoing half-edge counter-clockwise around its origin; kNone past a boundary.
  std::uint32_t rotate(std::uint32_t h) const { return opposite[prev[h]]; }
};

/// Builds the half-edge view of `mesh`.
/// \throw MeshError (one line) if a face has fewer than 3 corners or repeats a vertex, an index
///        names no vertex, an edge has more than two faces or its faces disagree in orientation,
///        or a vertex's faces do not form a single fan (non-manifold vertex).
PolygonTopology build_topology(const PolygonMesh& mesh);

/// How Catmull-Clark moves an old vertex that lies on a boundary. Boundary edge points are the
/// edge midpoints under both rules.
enum class BoundaryVertexRule {
  /// v' = (b1 + 6 v + b2) / 8 over the two boundary neighbours: the boundary curve is a uniform
  /// cubic B-spline (seed 004), whose limit point is (b1 + 4 v + b2) / 6. The default: it is the
  /// rule catmull_clark_limit() (limit.h) assumes.
  cubic_bspline,
  /// v' = (v + m1 + m2) / 3 with m1, m2 the boundary edge midpoints, i.e. (b1 + 4 v + b2) / 6:
  /// what OpenMesh 9's CatmullClarkT does. Its boundary limit point is (b1 + 3 v + b2) / 5.
  openmesh,
};

/// Catmull-Clark subdivision, `levels` times (seed 000 eq. 4; CODEC-NOTES §2).
///
/// Face point: centroid. Interior edge point: (V + E + f_1 + f_2) / 4. Interior vertex point:
/// ((n-2)/n) V + (1/n²) Σ E_i + (1/n²) Σ f_i (E_i the neighbouring vertices, f_i the new face
/// points). Boundary edge point: midpoint; boundary vertex point: see BoundaryVertexRule.
/// Works on any polygon mesh; after one level every face is a quad.
///
/// Output order: the old vertices keep their indices, then one vertex per edge (in the order of
/// PolygonTopology::edge), then one per face. Face f with corners c_0..c_{m-1} becomes the m
/// quads (v_i, edge point of c_i, face point, edge point of c_{i-1}), in face order.
/// Isolated vertices are carried over unchanged.
/// \throw MeshError if levels is outside [0, kMaxSubdivisionLevels], the output would exceed
///        2^31 vertices or 2^32 - 1 corners, or the mesh is not manifold (see build_topology).
PolygonMesh catmull_clark(const PolygonMesh& mesh, int levels,
                          BoundaryVertexRule boundary = BoundaryVertexRule::cubic_bspline);

/// Doo-Sabin subdivision, `levels` times (seed 004).
///
/// Each corner i of a face with n corners v_0..v_{n-1} becomes a new vertex
/// v_i' = Σ_j α_ij v_j, α_ii = (n+5)/(4n), α_ij = (3 + 2 cos(2π(i-j)/n)) / (4n).
/// New faces, in this order: one F-face per old face (its new corners, same orientation), one
/// quad E-face per interior edge, one n-gon V-face per interior vertex of valence n.
/// Boundaries: a boundary edge gets no E-face and a boundary vertex no V-face, so the surface
/// shrinks away from the old boundary (its new boundary is made of F-face and E-face edges);
/// isolated vertices disappear. Output vertex h is the new vertex of old corner h.
/// \throw MeshError as catmull_clark().
PolygonMesh doo_sabin(const PolygonMesh& mesh, int levels);

}  // namespace meshlift
