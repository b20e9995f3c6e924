// Spherical parametrization of a closed genus-0 triangle mesh (seed 003 §5.1.3, CODEC-NOTES §6),
// after Praun & Hoppe, "Spherical parametrization and remeshing", SIGGRAPH 2003, §4: simplify the
// mesh to a tetrahedron by halfedge collapses (a progressive mesh), map the tetrahedron onto the
// sphere, then undo the collapses coarse to fine, placing each re-inserted vertex inside the
// spherical kernel of its 1-ring and moving vertices to lower the stretch with a line search
// that never accepts a flipped or degenerate spherical triangle.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// "" when `mesh` can be parametrized on the sphere: triangles only, valid indices, finite
/// coordinates, closed, manifold, consistently oriented, one component, genus 0 (isolated
/// vertices are allowed and ignored). Otherwise one line naming what is wrong, e.g.
/// "not closed (12 boundary edges in 1 loops): the sphere remesher needs a closed, manifold,
/// genus-0 surface in one piece; use --remesh decimate" (several problems are joined by "; ").
std::string sphere_parametrization_problem(const TriangleMesh& mesh);

struct SphericalParametrizationOptions {
  /// Each vertex split moves the new vertex twice and its ring once; in addition a sweep over all
  /// present vertices runs whenever the vertex count has grown by this factor since the last one
  /// (optimization at geometrically spaced levels of the progressive mesh).
  double sweep_growth = 1.25;
  /// Sweeps over all vertices once every vertex is back.
  int final_sweeps = 6;
  /// Line searches per vertex and sweep (fewer when a search lowers the vertex's stretch by less
  /// than 1e-4 of it).
  int line_searches = 1;
  /// Called with a fraction in [0, 1] as work progresses; may be empty.
  std::function<void(double)> progress;
};

/// Bijectivity facts of a map of a mesh's vertices onto the unit sphere. A spherical triangle is
/// taken as its chord triangle (the flat triangle through its three corners), as the sampler
/// interpolates on it; its signed volume det(a, b, c) is > 0 when it is counter-clockwise seen
/// from outside.
struct SphereMapCheck {
  std::size_t flipped_triangles = 0;     ///< det(a, b, c) < 0
  std::size_t degenerate_triangles = 0;  ///< |det(a, b, c)| <= kSphereDegenerateDet · max edge² (or a corner off the sphere)
  /// Sum over faces of the signed spherical-triangle area (Van Oosterom & Strackee's solid angle)
  /// divided by 4π: 1 for a map that covers the sphere once. With no flipped or degenerate
  /// triangle and coverage 1, the map is a bijection (a covering of degree 1).
  double coverage = 0;
  bool bijective() const { return flipped_triangles == 0 && degenerate_triangles == 0 && coverage > 0.999999 && coverage < 1.000001; }
};

/// A triangle whose |det(a, b, c)| (= twice the chord triangle's area times its distance to
/// the origin, ~ its area for small triangles) is below this times its longest edge squared is
/// called degenerate: its smallest angle is below about 1e-12 rad.
inline constexpr double kSphereDegenerateDet = 1e-12;

/// Checks `sphere` (xyz per vertex of `mesh`, unit length) as above. Unreferenced vertices are ignored.
SphereMapCheck check_sphere_map(const TriangleMesh& mesh, std::span<const double> sphere);

/// Sander et al.'s L2 stretch of the map from the sphere onto the surface, normalized so that a
/// similarity scores 1 (Praun & Hoppe §3, Sander et al. 2001 §3):
///   L2²(T) = (Γ² + γ²)/2 = Σ_i ((p_j − p_i)·(p_k − p_i)) |q_j − q_k|² / (8 A_p(T)²)
///     (Γ, γ the singular values of the affine map from the flat triangle p to the surface
///      triangle q; the sum runs over the corners i with j, k the other two: the cotangent
///      form of the map's Dirichlet energy divided by its area). The flat triangle p is the
///      spherical triangle's gnomonic projection onto the plane tangent at its centre direction
///      c: p_i / (p_i · c) (a spherical sliver stays a sliver, which its chord triangle need not).
///   L2(M) = sqrt( Σ_T A_q(T) L2²(T) / Σ_T A_q(T) ) · sqrt( 4π / Σ_T A_q(T) ).
/// Infinite when a triangle has zero area on the sphere or spans more than about a hemisphere.
/// parametrize_sphere() minimizes Σ_T (A_q(T) + ε) L2²(T), ε = 1e-3 × the mean face area (so
/// that faces of zero surface area still resist collapsing on the sphere).
double spherical_stretch(const TriangleMesh& mesh, std::span<const double> sphere);

struct SphericalParametrization {
  /// Unit vectors, 3 per input vertex (isolated vertices get (0, 0, 1)).
  std::vector<double> sphere;
  double stretch = 0;           ///< spherical_stretch() of the result
  SphereMapCheck check;         ///< check_sphere_map() of the result
  std::size_t base_vertices = 0;  ///< vertices left by the simplification (4: a tetrahedron)
  std::size_t collapses = 0;
};

/// Parametrizes `mesh` on the unit sphere, minimizing the (area-weighted) L2 stretch above by
/// coarse-to-fine vertex moves. Every accepted vertex position keeps all triangles around it
/// counter-clockwise and non-degenerate, so the result is bijective by construction;
/// `check` re-verifies it. Deterministic.
/// \throw MeshError with sphere_parametrization_problem()'s message when the mesh is unsuitable,
///        or when the simplification could not reach a tetrahedron (then naming how far it got).
SphericalParametrization parametrize_sphere(const TriangleMesh& mesh, const SphericalParametrizationOptions& options = {});

}  // namespace meshlift
