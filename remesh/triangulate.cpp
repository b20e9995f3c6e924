// Polygon meshes -> triangle meshes by ear clipping. See triangulate.h.
#include "meshlift/triangulate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include "vec3.h"

namespace meshlift {
namespace {

using vec3::Vec3;
using vec3::cross;
using vec3::dot;
using vec3::sub;

/// The smallest angle of triangle (a, b, c) as its cosine's complement: 1 − cos, larger for a
/// larger smallest angle (monotone, no acos).
double smallest_angle_key(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3* p[3] = {&a, &b, &c};
  double largest_cos = -1;
  for (int i = 0; i < 3; ++i) {
    const Vec3 u = sub(*p[(i + 1) % 3], *p[i]), v = sub(*p[(i + 2) % 3], *p[i]);
    const double length = std::sqrt(dot(u, u) * dot(v, v));
    largest_cos = std::max(largest_cos, length > 0 ? dot(u, v) / length : 1.0);
  }
  return 1 - largest_cos;
}

/// Faces with more corners are split as a fan (ear clipping is cubic in the corners here).
constexpr std::size_t kMaxClipped = 64;

/// Splits the face with corners `corners` (indices into positions) into triangles appended to
/// `out`; returns false if it had to fall back to a fan.
bool clip_ears(const std::vector<double>& positions, std::vector<std::uint32_t> corners, std::vector<std::uint32_t>& out) {
  auto at = [&](std::uint32_t v) { return vec3::at(positions, v); };
  // Newell's normal: Σ (p_i × p_{i+1}) / 2 is the vector area of the polygon, planar or not;
  // taken about corner 0 (the same sum) so that a face far from the origin keeps its digits.
  const Vec3 origin = at(corners[0]);
  Vec3 normal{0, 0, 0};
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3 c = cross(sub(at(corners[i]), origin), sub(at(corners[(i + 1) % corners.size()]), origin));
    for (int k = 0; k < 3; ++k) normal[k] += c[k];
  }
  // Signed area of (a, b, c) along the normal: > 0 where the corner turns the polygon's way.
  auto turn = [&](const Vec3& a, const Vec3& b, const Vec3& c) { return dot(cross(sub(b, a), sub(c, a)), normal); };
  auto inside = [&](const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    return turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0;
  };
  bool clean = dot(normal, normal) > 0;
  const bool clip = corners.size() <= kMaxClipped;
  if (!clip) {
    // Ear clipping costs O(n³) here: the fan below instead, exact where every corner turns the
    // polygon's way (the caps of a CAD cylinder), else reported as a fan.
    const std::size_t n = corners.size();
    for (std::size_t i = 0; i < n && clean; ++i)
      clean = turn(at(corners[i]), at(corners[(i + 1) % n]), at(corners[(i + 2) % n])) > 0;
  }
  while (clip && clean && corners.size() > 3) {
    const std::size_t n = corners.size();
    std::size_t best = n;
    double best_key = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t u = corners[(i + n - 1) % n], v = corners[i], w = corners[(i + 1) % n];
      const Vec3 a = at(u), b = at(v), c = at(w);
      if (!(turn(a, b, c) > 0)) continue;  // reflex or flat corner: no ear
      bool empty = true;
      for (std::size_t k = 0; k < n && empty; ++k) {
        const std::uint32_t x = corners[k];
        if (x == u || x == v || x == w) continue;
        empty = !inside(at(x), a, b, c);
      }
      if (!empty) continue;
      if (const double key = smallest_angle_key(a, b, c); key > best_key) best = i, best_key = key;
    }
    if (best == n) {
      clean = false;
      break;
    }
    out.insert(out.end(), {corners[(best + n - 1) % n], corners[best], corners[(best + 1) % n]});
    corners.erase(corners.begin() + static_cast<std::ptrdiff_t>(best));
  }
  // The last triangle, or a fan over what is left where no ear was found.
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) out.insert(out.end(), {corners[0], corners[i], corners[i + 1]});
  return clean;
}

/// The simple loops of a face's corner cycle: corners repeated in a row merged first (a triangle
/// written as a quad, "a b c c", or "a b c a"), then the cycle cut at each corner it comes back
/// to ("a b c a d e" -> "a b c", "a d e"): the standard split of a closed walk into simple
/// cycles. Sets `merged` and `pinched` when the face had such repeats.
std::vector<std::vector<std::uint32_t>> simple_loops(std::span<const std::uint32_t> face, bool& merged, bool& pinched) {
  std::vector<std::uint32_t> cycle;
  for (const std::uint32_t v : face)
    if (cycle.empty() || cycle.back() != v) cycle.push_back(v);
  while (cycle.size() > 1 && cycle.back() == cycle.front()) cycle.pop_back();
  merged = cycle.size() != face.size();
  std::vector<std::vector<std::uint32_t>> loops;
  std::vector<std::uint32_t> path;
  for (const std::uint32_t v : cycle) {
    const auto again = std::find(path.begin(), path.end(), v);
    if (again != path.end()) {  // the walk is back at v: what it went round since is a loop
      loops.emplace_back(again, path.end());
      path.erase(again + 1, path.end());
    } else {
      path.push_back(v);
    }
  }
  pinched = !loops.empty();
  loops.push_back(std::move(path));
  return loops;
}

}  // namespace

Triangulation triangulate(const PolygonMesh& mesh) {
  for (const std::uint32_t v : mesh.face_indices)
    if (v >= mesh.vertex_count())
      throw MeshError("triangulate: a face names vertex " + std::to_string(v) + " of " +
                      std::to_string(mesh.vertex_count()));
  Triangulation result;
  result.mesh.positions = mesh.positions;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::size_t n = mesh.face_size(f);
    if (n < 3) {
      ++result.dropped;
      continue;
    }
    const auto first = mesh.face_indices.begin() + mesh.face_offsets[f];
    if (n == 3) {
      result.mesh.triangles.insert(result.mesh.triangles.end(), first, first + 3);
      continue;
    }
    n == 4 ? ++result.quads : ++result.polygons;
    bool merged = false, pinched = false, fan = false;
    const std::size_t before = result.mesh.triangles.size();
    for (std::vector<std::uint32_t>& loop :
         simple_loops(std::span(&*first, n), merged, pinched)) {
      if (loop.size() < 3) continue;  // a corner or an edge gone over twice: no area
      fan |= !clip_ears(mesh.positions, std::move(loop), result.mesh.triangles);
    }
    result.repeated_corners += merged;
    result.pinched += pinched;
    result.fans += fan;
    const std::size_t made = (result.mesh.triangles.size() - before) / 3;
    result.split_triangles += made;
    result.dropped += made == 0;
  }
  return result;
}

}  // namespace meshlift
