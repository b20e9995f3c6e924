// Interpolation by iterated limit differences (progressive iterative approximation; seed 000
// eq. 1-3, CODEC-NOTES §5): find control points whose Loop or Catmull-Clark limit surface passes
// through given points, by local O(V) updates instead of a global solve.
#pragma once

#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// When interpolation stops. Defaults suit meshes of up to some 10^5 vertices; see FitResult.
struct FitOptions {
  /// Most updates C_k -> C_{k+1}; 0 only measures the residual of C_0 = P. Must be >= 0.
  int max_iterations = 200;
  /// Stop once max_v |P_v - (A C_k)_v| <= tolerance x bounding-box diagonal of P. Must be finite
  /// and >= 0 (0 runs all max_iterations unless the residual is exactly 0).
  double tolerance = 1e-10;
};

/// The fitted control mesh and how the iteration went.
struct FitResult {
  /// The control mesh C_k: same connectivity as the interpolated points P (for Catmull-Clark on
  /// a mesh with non-quad faces, that of catmull_clark(targets, 1)), new positions.
  PolygonMesh control;
  /// residuals[k] = max over vertices of the Euclidean distance |P_v - (A C_k)_v| (absolute, in
  /// the units of the input), for k = 0 (C_0 = P) up to the returned control, which is
  /// C_{residuals.size() - 1}. So residuals.back() is the residual of `control`.
  std::vector<double> residuals;
  /// Bounding-box diagonal of P: the scale that FitOptions::tolerance is relative to.
  double diagonal = 0;
  /// residuals.back() <= tolerance x diagonal. If false, `control` is still the last iterate
  /// (usually much closer than P itself) and residuals show how far it got.
  bool converged = false;
  /// Catmull-Clark only: the input had a non-quad face, so one catmull_clark step was applied
  /// first and P is the vertices of that all-quad mesh, not the input's (their limit surface is
  /// then a different surface from the one through the input's vertices alone).
  bool subdivided_first = false;

  /// Number of updates performed.
  int iterations() const { return static_cast<int>(residuals.size()) - 1; }
};

/// A control mesh with the connectivity of `targets` whose Loop limit points are the target
/// vertices: C_0 = P, C_{k+1} = C_k + (P - A C_k) with A = loop_limit_stencil(targets)
/// (seed 000 eq. 1; its sum of differences, eq. 3, is C = A^-1 P). One stencil build, then each
/// iteration is one sparse product, O(V).
///
/// Converges when every eigenvalue λ of A satisfies |1 - λ| < 1, at the rate max |1 - λ|. On a
/// regular interior region A's smallest eigenvalue is 1/4, so the rate is up to 3/4 per iteration
/// and 1e-10 takes about 80 iterations (measured: 84 on a perturbed bicone with valence 5, 27 on
/// a valence-7 disk; tests/remesh/test_interpolate.cpp).
/// \throw MeshError if the mesh is not manifold (loop_limit_stencil) or a position is not finite.
/// \throw std::invalid_argument if an option is out of range.
FitResult fit_loop(const TriangleMesh& targets, const FitOptions& options = {});

/// A control mesh whose Catmull-Clark limit points are the vertices of `targets`, as fit_loop()
/// with A = catmull_clark_limit_stencil (seed 000, after eq. 4; boundary: cubic B-spline, see
/// BoundaryVertexRule::cubic_bspline).
///
/// The limit formula holds on all-quad meshes only. If some face is not a quad, one
/// catmull_clark(targets, 1) step is applied first and the vertices of that all-quad mesh
/// (input vertices first, then edge and face points) are interpolated; `subdivided_first` says so.
///
/// Convergence: seed 000's appendix shows the eigenvalues of A lie in (0, 1] when some vertex
/// has valence > 3. Without one, A can be singular: on the cube (all valence 3) the
/// checkerboard pattern ±1 on alternate corners has eigenvalue 0, so that component of P is
/// never reached and the result reports converged = false (the unperturbed unit cube has no
/// such component and converges at rate 1/2). Otherwise the rate is max |1 - λ|: up to 8/9 per
/// iteration on regular quad regions (A's smallest eigenvalue there is 1/9), and about 0.92 on
/// catmull_clark(pentagonal pyramid, 1), whose many valence-3 vertices (face points of
/// triangles) give a near-checkerboard mode: 1e-10 then takes some 240 iterations, more than the
/// default 200 (the result says converged = false; raise max_iterations).
/// \throw MeshError if the mesh is not manifold or a position is not finite.
/// \throw std::invalid_argument if an option is out of range.
FitResult fit_catmull_clark(const PolygonMesh& targets, const FitOptions& options = {});

}  // namespace meshlift
