// Closest points on triangles and on triangle meshes: the exact point-to-triangle distance
// (Ericson, Real-Time Collision Detection §5.1.5) and a BVH over a mesh's faces (Embree 3's
// rtcPointQuery) that finds the closest face of a mesh to any point.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>

#include "meshlift/mesh.h"

namespace meshlift {

/// A point on one triangle and its barycentric coordinates.
struct TrianglePoint {
  std::array<double, 3> point;
  std::array<double, 3> barycentric;  ///< weights of a, b, c (non-negative, summing to 1)
};

/// Closest point on triangle abc to p, computed in double precision by Ericson's Voronoi-region
/// test (Real-Time Collision Detection §5.1.5). A degenerate triangle (its corners collinear or
/// coincident) is treated as the union of its three edges, so the answer is still the closest
/// point of the segment or point it has collapsed to.
TrianglePoint closest_point_on_triangle(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                        const std::array<double, 3>& b, const std::array<double, 3>& c);

/// The closest point of a mesh's surface to a query point.
struct SurfacePoint {
  std::array<double, 3> point{};        ///< closest point on the surface
  std::uint32_t face = kNone;           ///< triangle it lies on
  std::array<double, 3> barycentric{};  ///< weights of that face's corners 0, 1, 2
  double distance = 0;                  ///< |p - point|
  /// The corner (0, 1 or 2) of `face` with the largest barycentric weight: the face's corner
  /// nearest `point` in the sense of the weights (ties to the first).
  int heaviest_corner() const {
    return static_cast<int>(std::max_element(barycentric.begin(), barycentric.end()) - barycentric.begin());
  }
};

/// A BVH over a triangle mesh's faces for closest-point queries.
///
/// Embree (rtcPointQuery) traverses its BVH and calls back for every face whose box meets the
/// query sphere; the callback computes the exact double-precision distance with
/// closest_point_on_triangle() on the mesh's double positions and shrinks the sphere.
///
/// Float caveat: Embree stores the vertices, the boxes, the query point and the radius as
/// floats, so its sphere test is made against faces rounded to float. A face moves by at most
/// δ = √3·2^-24·M when its corners are rounded (M the largest coordinate magnitude of the mesh
/// and the query point: each coordinate moves by half an ulp, ≤ 2^-24·M, and every point of the
/// triangle is a convex combination of its corners), and the query point moves by the same
/// bound. The callback therefore never shrinks the radius to the exact best distance d but to
/// (d + 4δ)·(1 + 2^-20), rounded up to a float: every face whose exact distance is ≤ d is then
/// still inside the float sphere, whatever the rounding of the boxes and of Embree's own
/// sphere-box arithmetic. Embree only decides which faces are *visited*; the distance and the
/// winner come from the double computation, so the result equals a brute-force scan over all
/// faces, ties included (the lowest face index wins among equal distances).
class SurfaceQuery {
 public:
  /// Builds the BVH; keeps its own copy of `mesh`.
  /// \throw MeshError if the mesh has no faces, an index names no vertex, or a coordinate is not
  ///        finite or too large for a float (|x| > 1e30).
  explicit SurfaceQuery(const TriangleMesh& mesh);
  ~SurfaceQuery();
  SurfaceQuery(SurfaceQuery&&) noexcept;
  SurfaceQuery& operator=(SurfaceQuery&&) noexcept;
  SurfaceQuery(const SurfaceQuery&) = delete;
  SurfaceQuery& operator=(const SurfaceQuery&) = delete;

  /// The closest point of the surface to `p`. Thread-safe (any number of
  /// concurrent calls on one object); deterministic: among faces at equal distance, the lowest
  /// face index wins. \throw MeshError if `p` is not finite.
  SurfacePoint closest(const std::array<double, 3>& p) const;

  /// The same answer as closest(p), found faster when `hint_face` is near p (e.g. the face found
  /// for the previous of a run of nearby points): the search starts with the radius of that
  /// face's distance instead of infinity. Any face index, or kNone, is a valid hint; the result
  /// does not depend on it.
  SurfacePoint closest(const std::array<double, 3>& p, std::uint32_t hint_face) const;

  /// The first point where the ray origin + t·direction, 0 <= t <= max_distance, meets the
  /// surface (either side of a face), or face = kNone if it meets none. Embree traces the ray in
  /// float precision; the returned point is the hit's barycentric combination of the face's
  /// double corners, and `distance` is t times |direction|. Thread-safe.
  /// \throw MeshError if origin or direction is not finite or direction is zero.
  SurfacePoint first_hit(const std::array<double, 3>& origin, const std::array<double, 3>& direction,
                         double max_distance) const;

  /// The mesh the queries run against (the copy made at construction).
  const TriangleMesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshlift
