// Limit positions of subdivision surfaces (CODEC-NOTES §5): where each control vertex ends up
// after infinitely many Loop or Catmull-Clark steps, as a sparse operator that interpolation
// (C_{k+1} = C_k + (P - A C_k), seed 000 eq. 1-3) can apply many times.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// The limit-point operator A of a subdivision scheme on one connectivity, as compressed rows:
/// limit vertex v = Σ weights[r] · control vertex indices[r] for r in [row_offsets[v], row_offsets[v+1]).
/// Each row's weights sum to 1; the summation order is fixed, so apply() is deterministic.
struct LimitStencil {
  std::vector<std::uint32_t> row_offsets{0};
  std::vector<std::uint32_t> indices;
  std::vector<double> weights;

  std::size_t vertex_count() const { return row_offsets.size() - 1; }

  /// limit = A · control, on xyz triples (both spans hold 3 · vertex_count() doubles).
  /// \pre   `control` and `limit` do not overlap.
  /// \throw std::invalid_argument if a span has the wrong size.
  void apply(std::span<const double> control, std::span<double> limit) const;
};

/// The Loop limit operator of a triangle mesh (seed 004 with the correction of CODEC-NOTES §5):
/// interior vertex of valence n: v∞ = (3 v + 8β_n Σ v_i) / (3 + 8nβ_n),
/// β_n = (1/n)(5/8 − (3/8 + ¼ cos(2π/n))²); boundary vertex: (b1 + 4 v + b2) / 6 over its two
/// boundary neighbours (the limit of the cubic B-spline boundary rule (1, 6, 1)/8, which is also
/// what OpenMesh's LoopT uses); isolated vertex: itself.
/// \throw MeshError if the mesh is not manifold (see build_topology in polygon_subdivision.h).
LimitStencil loop_limit_stencil(const TriangleMesh& mesh);

/// The Catmull-Clark limit operator of an all-quad mesh (seed 000, after eq. 4):
/// interior vertex of valence n: v∞ = (n² v + 4 Σ e_i + Σ f_i) / (n(n+5)), e_i the edge
/// neighbours, f_i the diagonal corners of the n quads around v; boundary vertex:
/// (b1 + 4 v + b2) / 6, the limit of BoundaryVertexRule::cubic_bspline; isolated vertex: itself.
/// \throw MeshError if a face is not a quad or the mesh is not manifold.
LimitStencil catmull_clark_limit_stencil(const PolygonMesh& quad_mesh);

/// `mesh` with every position replaced by its Loop limit point.
/// \throw MeshError as loop_limit_stencil().
TriangleMesh loop_limit(const TriangleMesh& mesh);

/// `mesh` with every position replaced by its Catmull-Clark limit point. If some face is not a
/// quad, the limit formula does not apply to the mesh itself: one Catmull-Clark step
/// (catmull_clark(mesh, 1), cubic B-spline boundary) is applied first and the limit of that
/// all-quad mesh is returned, so the result then has that mesh's connectivity.
/// \throw MeshError if the mesh is not manifold.
PolygonMesh catmull_clark_limit(const PolygonMesh& mesh);

/// limit = Loop limit points of the control positions on `connectivity` (its positions are
/// ignored). Builds the stencil each call: keep a LimitStencil to iterate.
/// \throw MeshError as loop_limit_stencil(); std::invalid_argument on a span of the wrong size.
void apply_loop_limit(const TriangleMesh& connectivity, std::span<const double> control, std::span<double> limit);

/// limit = Catmull-Clark limit points of the control positions on the all-quad `connectivity`.
/// \throw MeshError as catmull_clark_limit_stencil(); std::invalid_argument on a wrong span size.
void apply_catmull_clark_limit(const PolygonMesh& connectivity, std::span<const double> control,
                               std::span<double> limit);

}  // namespace meshlift
