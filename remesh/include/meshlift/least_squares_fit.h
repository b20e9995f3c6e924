// The last stage of the decimation remesh (CODEC-NOTES §5): the semi-regular mesh's vertices,
// placed on the input by surface_fit.h, are moved to where the mesh is closest to the input in
// the least-squares sense, both ways, as Hoppe et al.'s mesh optimization fits a mesh of fixed
// connectivity to points ("Mesh optimization", SIGGRAPH 1993, §4: alternate the projection of
// the data points on the mesh with a linear least-squares solve for the vertices).
//
// Why: a mesh whose vertices all lie on a curved surface has all its chord error on one side
// (the triangles cut inside convex parts). Letting the vertices leave the surface by a fraction
// of the sag centres the error. For a chord under a parabolic arc of sag s the distance along the
// chord is s(1 − u²), u ∈ [−1, 1]: its RMS is s·sqrt(8/15) about zero and s·sqrt(8/15 − 4/9)
// about its mean 2s/3, so moving the chord by the mean divides the RMS by ~2.4.
// The symmetric surface distance (metric.h) is what the rate-distortion figures measure.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/closest_point.h"
#include "meshlift/semi_regular.h"

namespace meshlift {

struct LeastSquaresFitOptions {
  /// Rounds of (closest points both ways, then one linear solve); >= 0.
  int iterations = 4;
  /// Input area samples per face of the semi-regular mesh (> 0).
  double samples_per_face = 2;
  /// Weight of the membrane that keeps each edge vector near its value before the round,
  /// relative to the data terms (>= 0): it stops the vertices from sliding along the surface
  /// and keeps the sampling as the fitting stage left it.
  double stiffness = 0.01;
  /// Most a vertex may move per round, as a fraction of the mean length of its edges (> 0).
  double max_step = 0.2;
  /// Seed of the input samples. Deliberately not the metric's (metric.h) seed, so figures
  /// measured by the metric are not fitted to its own sample points.
  std::uint64_t seed = 0x6669742d6c73ULL;
  /// Worker threads for the closest-point queries; 0 = hardware concurrency. Results do not
  /// depend on it.
  unsigned threads = 0;
  /// Per vertex, or empty: 1 where the vertex is pinned as boundary vertices are (on a feature
  /// line, features.h).
  std::span<const std::uint8_t> fixed;
};

/// What each round achieved: the energy's two data terms as RMS distances (the input samples the
/// round uses to the mesh, mesh samples to the input) before the round's solve, and faces whose
/// move was undone because it would have turned them over.
struct LeastSquaresFitReport {
  std::vector<double> input_to_mesh_rms, mesh_to_input_rms;
  std::vector<std::size_t> reverted_faces;
  std::vector<std::size_t> folded_faces;  ///< faces facing away from the input before the round
};

/// Moves every vertex of `mesh` (all levels: the hierarchy keeps its connectivity) but those on
/// its boundary (they stay on the input's boundary curves, where the fitting put them) to minimize
///   E(V) = Σ_s a_s |p_s − B_s V|²  +  Σ_r a_r |B_r V − c_r|²  +  κ Σ_(j,k) |(V_j − V_k) − (V⁰_j − V⁰_k)|²
/// where p_s are area samples of the input with B_s the barycentric row of their closest point
/// on the current mesh, B_r V are points of the current mesh's faces (centroid and three inner
/// points, weight = a quarter of the face's area) with c_r their closest points on the input,
/// and the last term a membrane over the edges around the current positions V⁰ (κ = stiffness ×
/// mean face area). An input sample whose closest face faces the other way is left out (it lies
/// on another sheet of a thin part). Each round solves the normal equations (one sparse SPD
/// matrix, three right-hand sides) by conjugate gradients from V⁰, limits every vertex's move to
/// max_step × its mean edge length, and keeps at V⁰ the corners of any face that faced the
/// input before the round and would face away from it after (find_fold_overs()'s test).
/// \throw std::invalid_argument if an option is out of range.
LeastSquaresFitReport fit_least_squares(SemiRegularMesh& mesh, const SurfaceQuery& surface,
                                        const LeastSquaresFitOptions& options = {});

}  // namespace meshlift
