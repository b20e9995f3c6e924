// Small xyz helpers shared by remesh/'s sources (not installed).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>

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
/// v / |v|, or v itself when it is zero.
inline Vec3 unit(Vec3 v) {
  const double length = std::sqrt(dot(v, v));
  if (length > 0)
    for (double& c : v) c /= length;
  return v;
}

}  // namespace meshlift::vec3
