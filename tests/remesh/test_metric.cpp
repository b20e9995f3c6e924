// The surface metric on cases with known answers (identical, translated, scaled sphere, offset
// plane), its determinism across runs and thread counts, and its errors.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "meshlift/metric.h"
#include "test_meshes.h"

using meshlift::MeshError;
using meshlift::MetricOptions;
using meshlift::SurfaceDistance;
using meshlift::surface_distance;
using meshlift::TriangleMesh;

namespace {


/// Smallest distance from the origin to a face's plane (the polyhedron's inradius).
double inradius(const TriangleMesh& m) {
  double h = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    double p[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) p[i][k] = m.positions[3 * m.triangles[3 * f + i] + k];
    const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    h = std::min(h, std::abs(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]) / length);
  }
  return h;
}

/// Unit cube [0,1]^3, each side an n x n grid of squares split into triangles.
TriangleMesh cube(int n) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const auto base = static_cast<std::uint32_t>(m.vertex_count());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          double p[3];
          p[axis] = side;
          p[(axis + 1) % 3] = double(i) / n;
          p[(axis + 2) % 3] = double(j) / n;
          m.positions.insert(m.positions.end(), {p[0], p[1], p[2]});
        }
      auto id = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (n + 1) + j); };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // Orientation does not matter to the metric; keep it outward anyway.
          if (side == 1) {
            m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
          } else {
            m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i + 1, j)});
            m.triangles.insert(m.triangles.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1)});
          }
        }
    }
  return m;
}

TriangleMesh translated(TriangleMesh m, double dx, double dy, double dz) {
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    m.positions[i] += dx;
    m.positions[i + 1] += dy;
    m.positions[i + 2] += dz;
  }
  return m;
}

void require_identical(const SurfaceDistance& a, const SurfaceDistance& b) {
  REQUIRE(a.reference_to_test.rms == b.reference_to_test.rms);
  REQUIRE(a.reference_to_test.mean == b.reference_to_test.mean);
  REQUIRE(a.reference_to_test.max == b.reference_to_test.max);
  REQUIRE(a.test_to_reference.rms == b.test_to_reference.rms);
  REQUIRE(a.test_to_reference.mean == b.test_to_reference.mean);
  REQUIRE(a.test_to_reference.max == b.test_to_reference.max);
  REQUIRE(a.rms == b.rms);
  REQUIRE(a.hausdorff == b.hausdorff);
}

}  // namespace

TEST_CASE("metric of identical meshes is zero", "[metric]") {
  const TriangleMesh torus = meshlift::test::perturbed(meshlift::test::torus(30, 20), 0.02, 3);
  const SurfaceDistance d = surface_distance(torus, torus, {20000, 2});
  // Every sample lies on the other surface; only the rounding of the closest point remains.
  REQUIRE(d.hausdorff < 1e-14);
  REQUIRE(d.rms < 1e-15);
  REQUIRE(d.psnr_db() > 280);
  REQUIRE(d.reference_to_test.area_samples == 20000);
  REQUIRE(d.reference_to_test.vertex_samples == torus.vertex_count());
  REQUIRE(d.warning.empty());
}

TEST_CASE("metric of a cube translated along an axis has Hausdorff distance d", "[metric]") {
  // The translated cube's face x = 1 + d lies at distance exactly d from the original face x = 1
  // and no point of either surface is farther than d from the other.
  const TriangleMesh original = cube(4);
  for (double d : {0.01, 0.125, 0.3}) {
    const SurfaceDistance r = surface_distance(original, translated(original, d, 0, 0), {30000, 2});
    INFO("d = " << d);
    REQUIRE(std::abs(r.hausdorff - d) < 1e-12);
    REQUIRE(std::abs(r.reference_to_test.max - d) < 1e-12);
    REQUIRE(std::abs(r.test_to_reference.max - d) < 1e-12);
    REQUIRE(r.rms < d);  // the sides parallel to x stay on each other
    REQUIRE(r.rms > d / 3);
    REQUIRE(r.diagonal == Approx(std::sqrt(3.0)).epsilon(1e-15));
    REQUIRE(std::abs(r.hausdorff_relative() - d / std::sqrt(3.0)) < 1e-12);
  }
}

TEST_CASE("metric of a unit sphere mesh scaled by 1.01 is 0.01 within its polygonal approximation", "[metric]") {
  // Both polyhedra are convex. A point s·x of the scaled surface (x on face f) is 0.01·h_f from
  // f's plane, and no farther than 0.01 from x itself; a point inside is at least 0.01·h from the
  // scaled polyhedron's planes. So every distance lies in [0.01·h_min, 0.01], h_min the inradius
  // (0.9948 for 3 levels: the tolerance is the polygonal approximation's 0.5 %).
  const TriangleMesh sphere = meshlift::test::icosphere(3);
  TriangleMesh scaled = sphere;
  for (double& x : scaled.positions) x *= 1.01;
  const double h = inradius(sphere);
  REQUIRE(h > 0.99);
  const SurfaceDistance r = surface_distance(sphere, scaled, {50000, 2});
  for (double value : {r.rms, r.mean, r.hausdorff, r.reference_to_test.rms, r.test_to_reference.rms,
                       r.reference_to_test.mean, r.test_to_reference.max}) {
    REQUIRE(value >= 0.01 * h - 1e-12);
    REQUIRE(value <= 0.01 + 1e-12);
  }
  // The vertices of the scaled mesh are exactly 0.01 from the original ones' sphere points.
  REQUIRE(r.hausdorff == Approx(0.01).epsilon(1e-9));
}

TEST_CASE("metric of a plane offset along its normal is the offset everywhere", "[metric]") {
  const TriangleMesh plane = meshlift::test::grid(9);
  for (double offset : {1e-4, 0.05, 0.2}) {
    const SurfaceDistance r = surface_distance(plane, translated(plane, 0, 0, offset), {20000, 2});
    INFO("offset " << offset);
    for (double value : {r.rms, r.mean, r.hausdorff, r.reference_to_test.rms, r.test_to_reference.rms,
                         r.reference_to_test.mean, r.test_to_reference.mean}) {
      REQUIRE(std::abs(value - offset) < 1e-12);
    }
    REQUIRE(r.psnr_db() == Approx(20 * std::log10(std::sqrt(2.0) / offset)).epsilon(1e-10));
  }
}

TEST_CASE("metric results are identical across runs and thread counts", "[metric]") {
  const TriangleMesh a = meshlift::test::perturbed(meshlift::test::torus(40, 30), 0.01, 4);
  const TriangleMesh b = meshlift::test::perturbed(meshlift::test::torus(25, 18), 0.03, 5);
  const SurfaceDistance one = surface_distance(a, b, {40000, 1});
  REQUIRE(one.rms > 0.001);  // a real difference, so the sums have something to reorder
  for (unsigned threads : {1u, 2u, 4u, 7u}) {
    INFO(threads << " threads");
    require_identical(one, surface_distance(a, b, {40000, threads}));
  }
  // A different seed gives different samples but (nearly) the same estimate.
  const SurfaceDistance other_seed = surface_distance(a, b, {40000, 2, 12345});
  REQUIRE(other_seed.reference_to_test.rms != one.reference_to_test.rms);
  REQUIRE(other_seed.rms == Approx(one.rms).epsilon(0.01));
}

TEST_CASE("metric without its vertices: the same RMS, mean and PSNR, the maxima over the area samples", "[metric]") {
  const TriangleMesh a = meshlift::test::perturbed(meshlift::test::torus(40, 30), 0.01, 4);
  const TriangleMesh b = meshlift::test::perturbed(meshlift::test::torus(25, 18), 0.03, 5);
  MetricOptions options{20000, 2};
  const SurfaceDistance with = surface_distance(a, b, options);
  options.vertices = false;
  const SurfaceDistance without = surface_distance(a, b, options);
  CHECK(without.rms == with.rms);
  CHECK(without.mean == with.mean);
  CHECK(without.psnr_db() == with.psnr_db());
  CHECK(without.diagonal == with.diagonal);
  CHECK(without.reference_to_test.vertex_samples == 0);
  CHECK(with.reference_to_test.vertex_samples == a.vertex_count());
  CHECK(without.hausdorff <= with.hausdorff);
  // A mesh without area has its vertices as its only points either way.
  TriangleMesh flat = meshlift::test::grid(3);
  for (std::size_t v = 0; v < flat.vertex_count(); ++v) flat.positions[3 * v + 1] = 0;  // every face on a line
  const SurfaceDistance line = surface_distance(flat, a, options);
  CHECK(line.reference_to_test.vertex_samples == flat.vertex_count());
  CHECK(line.reference_to_test.rms > 0);
}

TEST_CASE("metric estimate converges to the exact L2 distance of a tilted plane", "[metric]") {
  // Reference z = 0 over [0,1]^2, test z = s·x on the same grid: the test→reference distance of a
  // point is s·x / 1 (its height), integrated over the tilted surface: mean = s/2, rms = s/sqrt(3).
  const TriangleMesh plane = meshlift::test::grid(11);
  TriangleMesh tilted = plane;
  const double s = 0.1;
  for (std::size_t i = 0; i < tilted.positions.size(); i += 3) tilted.positions[i + 2] = s * tilted.positions[i];
  const SurfaceDistance r = surface_distance(plane, tilted, {200000, 2});
  REQUIRE(r.test_to_reference.mean == Approx(s / 2).epsilon(1e-3));
  REQUIRE(r.test_to_reference.rms == Approx(s / std::sqrt(3.0)).epsilon(1e-3));
  REQUIRE(r.test_to_reference.max == Approx(s).epsilon(1e-12));
}

TEST_CASE("metric rejects empty meshes and warns on wildly different scales", "[metric]") {
  const TriangleMesh sphere = meshlift::test::icosphere(1);
  REQUIRE_THROWS_WITH(surface_distance(TriangleMesh{}, sphere), Catch::Contains("reference mesh has no faces"));
  REQUIRE_THROWS_WITH(surface_distance(sphere, TriangleMesh{}), Catch::Contains("test mesh has no faces"));
  TriangleMesh broken = sphere;
  broken.positions[0] = std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_WITH(surface_distance(sphere, broken, {1000, 1}), Catch::Contains("test mesh"));

  TriangleMesh huge = sphere;
  for (double& x : huge.positions) x *= 1000;
  const SurfaceDistance r = surface_distance(sphere, huge, {5000, 2});
  REQUIRE_THAT(r.warning, Catch::Contains("100x"));
  REQUIRE(r.hausdorff > 900);  // still computed
  TriangleMesh slightly = sphere;
  for (double& x : slightly.positions) x *= 50;
  REQUIRE(surface_distance(sphere, slightly, {5000, 2}).warning.empty());
}

TEST_CASE("metric against a reference sampled once gives the two-mesh values", "[metric]") {
  const TriangleMesh a = meshlift::test::perturbed(meshlift::test::torus(40, 30), 0.01, 4);
  for (const TriangleMesh& b : {meshlift::test::perturbed(meshlift::test::torus(25, 18), 0.03, 5),
                                meshlift::test::perturbed(meshlift::test::torus(30, 20), 0.02, 6)})
    for (const bool vertices : {true, false}) {
      MetricOptions options{20000, 2};
      options.vertices = vertices;
      const meshlift::SampledSurface reference(a, options.samples, options.seed, options.threads, options.vertices);
      require_identical(surface_distance(a, b, options), surface_distance(reference, b, options));
    }
}
