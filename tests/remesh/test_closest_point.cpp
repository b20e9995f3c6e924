// closest_point_on_triangle against dense sampling of the triangle in all 7 Voronoi regions;
// SurfaceQuery (Embree BVH) against a brute-force scan of every face.
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <thread>
#include <utility>

#include "meshlift/closest_point.h"
#include "meshlift/transfer.h"
#include "test_meshes.h"

using meshlift::closest_point_on_triangle;
using meshlift::MeshError;
using meshlift::SurfacePoint;
using meshlift::SurfaceQuery;
using meshlift::TriangleMesh;
using Vec3 = std::array<double, 3>;

namespace {

Vec3 add(const Vec3& u, const Vec3& v, double s = 1) { return {u[0] + s * v[0], u[1] + s * v[1], u[2] + s * v[2]}; }
Vec3 sub(const Vec3& u, const Vec3& v) { return {u[0] - v[0], u[1] - v[1], u[2] - v[2]}; }
double dot(const Vec3& u, const Vec3& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
Vec3 cross(const Vec3& u, const Vec3& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
Vec3 normalized(const Vec3& u) {
  const double n = std::sqrt(dot(u, u));
  return {u[0] / n, u[1] / n, u[2] / n};
}
double distance(const Vec3& u, const Vec3& v) { return std::sqrt(dot(sub(u, v), sub(u, v))); }

/// Smallest distance from p to (n+1)(n+2)/2 points of a barycentric grid on abc, and the largest
/// distance between a point of the triangle and its nearest grid point (the longest edge / n).
std::pair<double, double> sampled_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double v = double(i) / n, w = double(j) / n;
      const Vec3 q = add(add(a, sub(b, a), v), sub(c, a), w);
      best = std::min(best, distance(p, q));
    }
  const double longest = std::max({distance(a, b), distance(b, c), distance(c, a)});
  return {best, longest / n};
}

Vec3 vertex(const TriangleMesh& mesh, std::uint32_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

/// Brute force: every face, exact distance, ties to the lowest face index.
SurfacePoint brute_force_closest(const TriangleMesh& mesh, const Vec3& p) {
  SurfacePoint best;
  double best_distance2 = std::numeric_limits<double>::infinity();
  for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
    const auto t = closest_point_on_triangle(p, vertex(mesh, mesh.triangles[3 * f]),
                                             vertex(mesh, mesh.triangles[3 * f + 1]),
                                             vertex(mesh, mesh.triangles[3 * f + 2]));
    const Vec3 d = sub(p, t.point);
    const double d2 = dot(d, d);
    if (d2 < best_distance2) {  // strict: among equal distances the first (lowest) face stays
      best_distance2 = d2;
      best = {t.point, f, t.barycentric, std::sqrt(d2)};
    }
  }
  return best;
}


void check_against_brute_force(const TriangleMesh& mesh, int count, unsigned seed) {
  const SurfaceQuery query(mesh);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> box(-2.0, 2.0), near(-0.02, 0.02);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(mesh.vertex_count() - 1));
  for (int i = 0; i < count; ++i) {
    Vec3 p;
    switch (i % 4) {
      case 0: p = {box(rng), box(rng), box(rng)}; break;
      case 1: p = add(vertex(mesh, pick(rng)), {near(rng), near(rng), near(rng)}); break;  // near the surface
      case 2: p = vertex(mesh, pick(rng)); break;  // on a vertex: a tie between its faces
      default: p = {10 * box(rng), 10 * box(rng), 10 * box(rng)}; break;  // far away
    }
    const SurfacePoint expected = brute_force_closest(mesh, p);
    const SurfacePoint got = query.closest(p);
    INFO("point " << i << " at " << p[0] << " " << p[1] << " " << p[2]);
    REQUIRE(got.face == expected.face);
    REQUIRE(got.distance == expected.distance);
    REQUIRE(std::abs(got.distance - distance(p, got.point)) <= 1e-12);
    for (int k = 0; k < 3; ++k) REQUIRE(got.point[k] == expected.point[k]);
    // A hint (here any face, near or far, or none) never changes the answer.
    const std::uint32_t hint = i % 5 == 0 ? meshlift::kNone : static_cast<std::uint32_t>(rng() % mesh.face_count());
    const SurfacePoint hinted = query.closest(p, hint);
    REQUIRE(hinted.face == expected.face);
    REQUIRE(hinted.distance == expected.distance);
  }
}

}  // namespace

TEST_CASE("closest point on a triangle matches dense sampling in all 7 Voronoi regions", "[closest_point]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), positive(0.05, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 a = {u(rng), u(rng), u(rng)}, b = {u(rng), u(rng), u(rng)}, c = {u(rng), u(rng), u(rng)};
    const Vec3 normal = normalized(cross(sub(b, a), sub(c, a)));
    const Vec3 corners[3] = {a, b, c};
    for (int region = 0; region < 7; ++region) {
      // Regions 0-2: beyond corner i along the outward bisector; 3-5: beyond edge (i, i+1) along
      // its outward in-plane normal; 6: above the face. Each point is lifted off the plane.
      Vec3 p;
      std::array<double, 3> expected_zero_pattern{};  // 1 where the barycentric weight must be 0
      if (region < 3) {
        const Vec3& q = corners[region];
        const Vec3 e1 = normalized(sub(corners[(region + 1) % 3], q)), e2 = normalized(sub(corners[(region + 2) % 3], q));
        p = add(q, normalized(add(e1, e2)), -positive(rng));
        expected_zero_pattern = {1, 1, 1};
        expected_zero_pattern[region] = 0;
      } else if (region < 6) {
        const int i = region - 3, j = (i + 1) % 3, k = (i + 2) % 3;
        const Vec3 edge = sub(corners[j], corners[i]);
        Vec3 outward = normalized(cross(edge, normal));
        if (dot(outward, sub(corners[k], corners[i])) > 0) outward = {-outward[0], -outward[1], -outward[2]};
        const double t = 0.25 + 0.5 * (u(rng) + 1) / 2;
        p = add(add(corners[i], edge, t), outward, positive(rng));
        expected_zero_pattern[k] = 1;
      } else {
        const double v = 0.1 + 0.175 * (u(rng) + 1), w = 0.1 + 0.175 * (u(rng) + 1);  // v + w <= 0.9
        p = add(add(a, sub(b, a), v), sub(c, a), w);
      }
      p = add(p, normal, u(rng));
      const auto result = closest_point_on_triangle(p, a, b, c);
      INFO("trial " << trial << " region " << region);
      // The answer is a point of the triangle given by its own barycentrics.
      REQUIRE(std::abs(result.barycentric[0] + result.barycentric[1] + result.barycentric[2] - 1) < 1e-12);
      for (int k = 0; k < 3; ++k) {
        REQUIRE(result.barycentric[k] >= 0);
        if (expected_zero_pattern[k] == 1) REQUIRE(result.barycentric[k] == 0);
        if (expected_zero_pattern[k] == 0 && region != 6 && region >= 3) REQUIRE(result.barycentric[k] > 0);
      }
      if (region == 6) for (int k = 0; k < 3; ++k) REQUIRE(result.barycentric[k] > 0);
      const Vec3 rebuilt = add(add(add(Vec3{0, 0, 0}, a, result.barycentric[0]), b, result.barycentric[1]), c,
                               result.barycentric[2]);
      REQUIRE(distance(rebuilt, result.point) < 1e-12);
      // No sample is closer, and the best sample is within one grid step of the answer.
      const auto [sampled, step] = sampled_distance(p, a, b, c, 300);
      const double exact = distance(p, result.point);
      REQUIRE(exact <= sampled + 1e-12);
      REQUIRE(sampled - exact <= step);
    }
  }
}

TEST_CASE("closest point on a degenerate triangle is the closest point of its segment", "[closest_point]") {
  const Vec3 a = {0, 0, 0}, b = {2, 0, 0};
  // Collinear corners: the triangle is the segment [a, b] (c in the middle).
  auto r = closest_point_on_triangle({1.5, 1, 0}, a, b, {1, 0, 0});
  REQUIRE(distance(r.point, {1.5, 0, 0}) < 1e-15);
  // Two coincident corners: the segment [a, c].
  r = closest_point_on_triangle({0.5, 3, -4}, a, a, b);
  REQUIRE(distance(r.point, {0.5, 0, 0}) < 1e-15);
  REQUIRE(r.barycentric[0] + r.barycentric[1] == Approx(0.75));
  REQUIRE(r.barycentric[2] == Approx(0.25));
  // All three coincident: the point itself.
  r = closest_point_on_triangle({1, 1, 1}, b, b, b);
  REQUIRE(r.point == b);
}

TEST_CASE("SurfaceQuery equals brute force on a perturbed icosphere", "[closest_point]") {
  const TriangleMesh sphere = meshlift::test::perturbed(meshlift::test::icosphere(3), 0.01, 11);  // 1280 faces
  check_against_brute_force(sphere, 3000, 1);
}

TEST_CASE("SurfaceQuery equals brute force on a perturbed torus", "[closest_point]") {
  const TriangleMesh torus = meshlift::test::perturbed(meshlift::test::torus(40, 24), 0.01, 12);  // 1920 faces
  check_against_brute_force(torus, 3000, 2);
}

TEST_CASE("SurfaceQuery is exact far from the origin where float rounding is coarse", "[closest_point]") {
  // Translated by 1e4: a float ulp is ~1e-3 there, far above the perturbation's scale of detail.
  TriangleMesh mesh = meshlift::test::perturbed(meshlift::test::icosphere(2), 0.001, 13);
  for (std::size_t i = 0; i < mesh.positions.size(); i += 3) mesh.positions[i] += 1e4;
  const SurfaceQuery query(mesh);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = {1e4 + u(rng), u(rng), u(rng)};
    const SurfacePoint expected = brute_force_closest(mesh, p);
    const SurfacePoint got = query.closest(p);
    REQUIRE(got.face == expected.face);
    REQUIRE(got.distance == expected.distance);
  }
}

TEST_CASE("SurfaceQuery gives the same answers from concurrent threads", "[closest_point]") {
  const TriangleMesh torus = meshlift::test::perturbed(meshlift::test::torus(30, 20), 0.02, 5);
  const SurfaceQuery query(torus);
  const std::vector<double> points = meshlift::test::random_values(3 * 4000, 9);
  std::vector<SurfacePoint> serial(4000), parallel(4000);
  for (std::size_t i = 0; i < 4000; ++i) serial[i] = query.closest({2 * points[3 * i], 2 * points[3 * i + 1], points[3 * i + 2]});
  auto work = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      parallel[i] = query.closest({2 * points[3 * i], 2 * points[3 * i + 1], points[3 * i + 2]});
  };
  std::thread t1(work, 0, 2000), t2(work, 2000, 4000);
  t1.join();
  t2.join();
  for (std::size_t i = 0; i < 4000; ++i) {
    REQUIRE(parallel[i].face == serial[i].face);
    REQUIRE(parallel[i].distance == serial[i].distance);
  }
}

TEST_CASE("SurfaceQuery rejects meshes without faces or with bad coordinates", "[closest_point]") {
  TriangleMesh empty;
  REQUIRE_THROWS_AS(SurfaceQuery(empty), MeshError);
  TriangleMesh nan_mesh = meshlift::test::icosahedron();
  nan_mesh.positions[4] = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_AS(SurfaceQuery(nan_mesh), MeshError);
  TriangleMesh bad_index = meshlift::test::icosahedron();
  bad_index.triangles[5] = 12;
  REQUIRE_THROWS_AS(SurfaceQuery(bad_index), MeshError);
  const SurfaceQuery query(meshlift::test::icosahedron());
  REQUIRE_THROWS_AS(query.closest({0, std::numeric_limits<double>::infinity(), 0}), MeshError);
  // Moving keeps the BVH working.
  SurfaceQuery moved = SurfaceQuery(meshlift::test::icosahedron());
  REQUIRE(moved.closest({0, 0, 0}).distance > 0.7);
  REQUIRE(moved.mesh().face_count() == 20);
}

TEST_CASE("values carried by closest points: exact at the vertices, blended between them", "[closest_point][transfer]") {
  using namespace meshlift;
  const TriangleMesh mesh = test::torus(12, 9);
  const SurfaceQuery surface(mesh);
  const std::size_t V = mesh.vertex_count();
  std::vector<double> values(2 * V);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::sin(0.7 * static_cast<double>(i)) + 2;
  // At the vertices themselves: their own values, bit for bit, on any thread count.
  for (const unsigned threads : {1u, 2u}) REQUIRE(transfer_vertex_values(surface, values, 2, mesh.positions, threads) == values);
  // At an edge's midpoint (its own closest point): the mean of the edge's ends' values.
  std::vector<double> points;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> ends;
  for (std::size_t f = 0; f < mesh.face_count(); f += 7) {
    const std::uint32_t a = mesh.triangles[3 * f], b = mesh.triangles[3 * f + 1];
    for (int k = 0; k < 3; ++k) points.push_back(0.5 * (mesh.positions[3 * a + k] + mesh.positions[3 * b + k]));
    ends.emplace_back(a, b);
  }
  const std::vector<double> at = transfer_vertex_values(surface, values, 2, points);
  REQUIRE(at.size() == 2 * ends.size());
  for (std::size_t i = 0; i < ends.size(); ++i)
    for (std::size_t k = 0; k < 2; ++k)
      REQUIRE(at[2 * i + k] == Approx(0.5 * (values[2 * ends[i].first + k] + values[2 * ends[i].second + k])).epsilon(1e-12));
  values.pop_back();
  REQUIRE_THROWS_AS(transfer_vertex_values(surface, values, 2, points), MeshError);
}
