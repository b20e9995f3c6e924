// Small xyz helpers shared by remesh/'s sources (not installed).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>

namespace meshlift::vec3 {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& u, const Vec3& v) { return {u[0] - v[0], u[1] - v[1], u[2] - v[2]}; }
inline double dot(const Vec3& u, const Vec3& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
inline Vec3 cross(const Vec3& u, const Vec3& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
/// Vertex v of a flat xyz array.
inline Vec3 at(std::span<const double> xyz, std::uint32_t v) {
  return {xyz[3 * std::size_t{v}], xyz[3 * std::size_t{v} + 1], xyz[3 * std::size_t{v} + 2]};
}
/// (b − a) × (c − a) of the triangle t = (a, b, c) of a flat xyz array: its normal, of length
/// twice its area.
inline Vec3 face_normal(std::span<const double> xyz, const std::uint32_t* t) {
  const Vec3 a = at(xyz, t[0]);
  return cross(sub(at(xyz, t[1]), a), sub(at(xyz, t[2]), a));
}
/// Area of the triangle abc: |(b − a) × (c − a)| / 2.
inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(sub(b, a), sub(c, a));
  return 0.5 * std::sqrt(dot(n, n));
}
/// Closest point of segment [s, e] to p: s + t·(e − s), t = clamp((p − s)·(e − s) / |e − s|², 0, 1).
/// Returns t (0 for a zero-length segment).
inline double closest_on_segment(const Vec3& p, const Vec3& s, const Vec3& e) {
  const Vec3 se = sub(e, s);
  const double length2 = dot(se, se);
  if (!(length2 > 0)) return 0;
  return std::clamp(dot(sub(p, s), se) / length2, 0.0, 1.0);
}
/// Four points of a triangle in barycentric weights, a quarter of its area each: the centroid
/// and (2/3, 1/6, 1/6) with its rotations (a rule exact for linear functions). The remesher's
/// fitting and snapping sample a remesh face with them.
inline constexpr double kFourPoints[4][3] = {
    {1.0 / 3, 1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 2.0 / 3, 1.0 / 6}, {1.0 / 6, 1.0 / 6, 2.0 / 3}};
/// v / |v|, or v itself when it is zero.
inline Vec3 unit(Vec3 v) {
  const double length = std::sqrt(dot(v, v));
  if (length > 0)
    for (double& c : v) c /= length;
  return v;
}

/// Two unit tangents (e1, e2) of the plane with unit normal n, (e1, e2, n) right-handed: e1
/// across n from the x axis, or from the y axis where n is near x.
inline std::pair<Vec3, Vec3> tangent_basis(const Vec3& n) {
  const Vec3 e1 = unit(std::abs(n[0]) < 0.6 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
  return {e1, cross(n, e1)};
}

}  // namespace meshlift::vec3
