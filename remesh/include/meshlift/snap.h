// Snapping a fitted remesh onto the input's corners and creases. A coarse polyhedral input (a
// few thousand vertices: cow, elephant, knot1) is a surface whose curvature sits entirely in
// its vertices and edges; a remesh whose vertices lie near but not on them cuts every crease
// and corner by a chord, however dense it is (knot1 at ~16x: 84.1 dB). Here each remesh vertex
// near an input vertex (each the other's nearest) or near an input crease edge is tried on it,
// and kept there where that lowers the local two-way distance between the surfaces.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "meshlift/closest_point.h"
#include "meshlift/semi_regular.h"

namespace meshlift {

struct SnapOptions {
  /// A target is tried when it is within this fraction of the vertex's mean edge length (> 0).
  /// Measured at ~16x (L = 3): 0.5 / 0.7 / 1.0 give knot1 85.9 / 86.3 / 86.3 dB, elephant 86.2 /
  /// 86.9 / 86.9, cow 85.4 / 86.1 / 86.3 (one pass).
  double reach = 0.7;
  /// Input edges between two faces whose normals differ by more than this many degrees are
  /// creases (in [0, 180)).
  /// (2 / 5 / 10: knot1 86.0 / 85.9 / 85.5 dB at reach 0.5.)
  double crease_degrees = 5;
  /// Passes over all vertices (>= 0); each finds the nearest vertices anew. A second pass moves
  /// a tenth as many vertices as the first and adds 0.2-0.4 dB; a third adds nothing.
  int passes = 2;
  /// Per remesh vertex, or empty: 1 where the vertex must not move (on a feature line, as the
  /// other stages read it). Boundary vertices never move.
  std::span<const std::uint8_t> fixed;
  /// Worker threads; 0 = hardware concurrency. Results do not depend on it.
  unsigned threads = 0;
};

struct SnapReport {
  std::size_t tried = 0;             ///< vertices with a target within reach in some pass (moved or not)
  std::size_t onto_vertices = 0;     ///< vertices whose last move was onto an input vertex
  std::size_t onto_creases = 0;      ///< vertices whose last move was onto an input crease edge
};

/// Moves vertices of `mesh`'s finest level (all levels share its positions) onto the input's
/// vertices and crease edges where that lowers the local error. Vertices that share no face are
/// tried together (a greedy colouring in vertex order, colour by colour). The local error
/// of a vertex v is the area-weighted sum of squared distances of
///   - 4 points of each face around v (its centroid and the points (2/3, 1/6, 1/6)) to the input,
///   - 7 points of each input face closest to those (corners, edge midpoints, centroid, weights
///     1/12, 1/6 and 1/4 of its area: a quadrature exact for linear functions) to the faces
///     around v, those within one mean edge length of them before the move;
/// a move is kept if that sum falls and no face around v turns away from the input's normal at
/// the closest point of its centroid (find_fold_overs()'s test) unless it did before.
/// `surface` is the input's query structure.
/// \throw std::invalid_argument if an option is out of range or `fixed` has another size.
/// \throw MeshError if the surface's mesh is not a manifold, consistently oriented triangle mesh
///        (TriangleTopology::build(): its creases are read off its edges).
SnapReport snap_to_input(SemiRegularMesh& mesh, const SurfaceQuery& surface, const SnapOptions& options = {});

}  // namespace meshlift
