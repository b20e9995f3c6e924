#include "local_frames.h"

#include <cmath>
#include <vector>

namespace meshlift::frames {
namespace {

struct Vec {
  double x, y, z;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

}  // namespace

void rotate_details(const SemiRegularHierarchy& h, int level, std::span<const double> coarse, std::span<double> details,
                    int stride, Direction direction) {
  const TriangleTopology& t = h.topology(level);
  const std::size_t s = static_cast<std::size_t>(stride);
  auto position = [&](std::uint32_t v) { return Vec{coarse[s * v], coarse[s * v + 1], coarse[s * v + 2]}; };

  // Area-weighted vertex normals of the level-j mesh (the cross product's length is twice the
  // face's area, its direction the face normal).
  std::vector<Vec> normal(t.vertex_count, Vec{0, 0, 0});
  for (std::size_t f = 0; f < t.face_count(); ++f) {
    const std::uint32_t a = t.triangles[3 * f], b = t.triangles[3 * f + 1], c = t.triangles[3 * f + 2];
    const Vec p = position(a);
    const Vec n = cross(position(b) - p, position(c) - p);
    normal[a] = normal[a] + n;
    normal[b] = normal[b] + n;
    normal[c] = normal[c] + n;
  }

  for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
    const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
    double* d = &details[s * h.odd_vertex(level, e)];
    Vec n = normal[a] + normal[b];
    const double length = std::sqrt(dot(n, n));
    if (!(length > 0) || !std::isfinite(length)) continue;  // identity frame: leave (x, y, z) as is
    n = (1 / length) * n;
    const Vec edge = position(b) - position(a);
    Vec t1 = edge - dot(edge, n) * n;
    double t1_length = std::sqrt(dot(t1, t1));
    if (!(t1_length > 1e-12 * std::sqrt(dot(edge, edge)))) {
      // The edge is (nearly) along the normal, or has no length: use the axis least aligned with n.
      const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
      const Vec axis = ax <= ay && ax <= az ? Vec{1, 0, 0} : (ay <= az ? Vec{0, 1, 0} : Vec{0, 0, 1});
      t1 = axis - dot(axis, n) * n;
      t1_length = std::sqrt(dot(t1, t1));
    }
    t1 = (1 / t1_length) * t1;
    const Vec t2 = cross(n, t1);
    const Vec v{d[0], d[1], d[2]};
    if (direction == Direction::to_local) {
      d[0] = dot(n, v);
      d[1] = dot(t1, v);
      d[2] = dot(t2, v);
    } else {
      const Vec g = v.x * n + v.y * t1 + v.z * t2;  // v holds (n, t1, t2) components here
      d[0] = g.x;
      d[1] = g.y;
      d[2] = g.z;
    }
  }
}

}  // namespace meshlift::frames
