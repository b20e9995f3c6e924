// Faces that cut through each other (self_intersection.h), against a brute-force oracle.
#include <cmath>
#include <set>

#include "meshlift/self_intersection.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

using P = std::array<double, 3>;

P corner(const TriangleMesh& m, std::uint32_t f, int i) {
  const std::uint32_t v = m.triangles[3 * std::size_t{f} + static_cast<std::size_t>(i)];
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

/// Oracle in another form than the library's signed volumes: Möller-Trumbore, the segment
/// p + t (q - p) meets the triangle at barycentrics (u, v) with 0 < t < 1, u, v > 0, u + v < 1.
bool segment_hits(const P& p, const P& q, const P& a, const P& b, const P& c) {
  const P d{q[0] - p[0], q[1] - p[1], q[2] - p[2]}, e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]},
      e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const P h{d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
  const double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
  if (std::abs(det) < 1e-300) return false;
  const P s{p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
  const P k{s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
  const double v = (d[0] * k[0] + d[1] * k[1] + d[2] * k[2]) / det;
  const double t = (e2[0] * k[0] + e2[1] * k[1] + e2[2] * k[2]) / det;
  return u > 0 && v > 0 && u + v < 1 && t > 0 && t < 1;
}

/// Every pair of faces by brute force, with the library's rule for shared corners.
std::set<std::array<std::uint32_t, 2>> brute_force(const TriangleMesh& m) {
  std::set<std::array<std::uint32_t, 2>> out;
  for (std::uint32_t f = 0; f < m.face_count(); ++f)
    for (std::uint32_t g = f + 1; g < m.face_count(); ++g) {
      int shared = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += m.triangles[3 * f + i] == m.triangles[3 * g + j];
      if (shared >= 2) continue;
      bool hit = false;
      for (int i = 0; i < 3 && !hit; ++i) {
        const std::uint32_t a = m.triangles[3 * f + i], b = m.triangles[3 * f + (i + 1) % 3];
        const std::uint32_t c = m.triangles[3 * g + i], d = m.triangles[3 * g + (i + 1) % 3];
        // With a shared corner only the edges without it can cross.
        auto on = [&](std::uint32_t v, std::uint32_t h) {
          for (int k = 0; k < 3; ++k)
            if (m.triangles[3 * h + k] == v) return true;
          return false;
        };
        if (!on(a, g) && !on(b, g))
          hit = segment_hits(corner(m, f, i), corner(m, f, (i + 1) % 3), corner(m, g, 0), corner(m, g, 1), corner(m, g, 2));
        if (!hit && !on(c, f) && !on(d, f))
          hit = segment_hits(corner(m, g, i), corner(m, g, (i + 1) % 3), corner(m, f, 0), corner(m, f, 1), corner(m, f, 2));
      }
      if (hit) out.insert({f, g});
    }
  return out;
}

/// Two copies of `m` in one mesh, the second moved by `offset` along a direction that is parallel
/// to no face of the icospheres (along x, the faces parallel to x would stay coplanar with their
/// copies: touching, where the two tests may differ).
TriangleMesh two_of(const TriangleMesh& m, double offset) {
  TriangleMesh both = m;
  const auto n = static_cast<std::uint32_t>(m.vertex_count());
  for (std::size_t v = 0; v < m.vertex_count(); ++v)
    both.positions.insert(both.positions.end(), {m.positions[3 * v] + offset, m.positions[3 * v + 1] + 0.19 * offset,
                                                 m.positions[3 * v + 2] + 0.07 * offset});
  for (const std::uint32_t i : m.triangles) both.triangles.push_back(i + n);
  return both;
}

}  // namespace

TEST_CASE("A surface that does not pass through itself has no self-intersection", "[remesh][self_intersection]") {
  CHECK(self_intersections(test::icosphere(3)).empty());
  CHECK(self_intersections(test::torus()).empty());
  CHECK(self_intersections(test::grid(6)).empty());
  CHECK(self_intersections(two_of(test::icosphere(2), 2.5)).empty());  // apart
}

TEST_CASE("Self-intersections are the crossing pairs a brute-force search finds", "[remesh][self_intersection]") {
  SECTION("two overlapping spheres: each pair has a face of each") {
    const TriangleMesh m = two_of(test::icosphere(2), 0.7);
    const auto found = self_intersections(m);
    REQUIRE(!found.empty());
    const std::set<std::array<std::uint32_t, 2>> expected = brute_force(m);
    const std::set<std::array<std::uint32_t, 2>> got(found.begin(), found.end());
    CHECK(got == expected);
    const auto half = static_cast<std::uint32_t>(m.face_count() / 2);
    for (const auto& [f, g] : found) CHECK((f < half && g >= half));
  }
  SECTION("a sphere crumpled by noise, with shared corners") {
    const TriangleMesh m = test::perturbed(test::icosphere(2), 0.15, 7);
    const std::set<std::array<std::uint32_t, 2>> expected = brute_force(m);
    REQUIRE(!expected.empty());
    const auto found = self_intersections(m);
    CHECK(std::set<std::array<std::uint32_t, 2>>(found.begin(), found.end()) == expected);
    // At most N pairs, the lowest, and the total.
    std::size_t total = 0;
    const auto first = self_intersections(m, 1, &total);
    CHECK(total == expected.size());
    REQUIRE(first.size() == 1);
    CHECK(first[0] == *expected.begin());
  }
  SECTION("two triangles with one common corner, one piercing the other") {
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0,      // flat triangle 0
                   0.3, 0.3, -0.5, 0.3, 0.3, 0.5};  // the edge 3-4 goes through it
    m.triangles = {0, 1, 2, 0, 3, 4};
    CHECK(self_intersections(m).size() == 1);
    m.positions[11] = 0.2;  // both ends above the flat one: touching only at the common corner
    CHECK(self_intersections(m).empty());
  }
}

TEST_CASE("Self-intersections reject coordinates and indices they cannot trust", "[remesh][self_intersection]") {
  TriangleMesh m = test::icosahedron();
  m.positions[4] = std::nan("");
  CHECK_THROWS_AS(self_intersections(m), MeshError);
  m = test::icosahedron();
  m.triangles[5] = 1000;
  CHECK_THROWS_AS(self_intersections(m), MeshError);
}

TEST_CASE("faces_near_marked finds the faces within k rings of the marked ones, as a brute-force search does", "[remesh][self_intersection]") {
  const TriangleMesh grid = test::grid(12);
  const std::size_t F = grid.face_count();
  std::vector<std::uint8_t> marked(F, 0);
  marked[F / 2] = marked[F / 2 + 7] = marked[0] = 1;  // two inside, one at a corner of the grid
  // Brute force: ring k + 1 holds the faces sharing a corner with a face of rings 0..k.
  std::vector<int> ring(F, -1);
  for (std::size_t f = 0; f < F; ++f)
    if (marked[f]) ring[f] = 0;
  auto share_corner = [&](std::size_t f, std::size_t g) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (grid.triangles[3 * f + i] == grid.triangles[3 * g + j]) return true;
    return false;
  };
  for (int k = 0; k < 3; ++k)
    for (std::size_t f = 0; f < F; ++f)
      if (ring[f] == k)
        for (std::size_t g = 0; g < F; ++g)
          if (ring[g] < 0 && share_corner(f, g)) ring[g] = k + 1;
  for (const int rings : {0, 1, 2, 3}) {
    INFO(rings << " rings");
    const std::vector<std::uint8_t> near = faces_near_marked(grid, marked, rings);
    REQUIRE(near.size() == F);
    std::size_t count = 0;
    for (std::size_t f = 0; f < F; ++f) {
      CHECK((near[f] != 0) == (ring[f] >= 1 && ring[f] <= rings));
      count += near[f] != 0;
    }
    if (rings > 0) CHECK(count > 0);
  }
}
