// The codec's fast paths of issue 3's fourth round against the plain computations they replace,
// bit for bit: the local frames' test for an edge along the normal without its square root
// against FORMAT.md §3's formula; the decoder's normals reusing one array across levels.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "../../codec/local_frames.h"
#include "meshlift/codec.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// FORMAT.md §3: the edge is (nearly) along the normal when !(|t1| > 1e-12 |edge|).
bool spec_along_normal(double t1_length, double edge_squared) { return !(t1_length > 1e-12 * std::sqrt(edge_squared)); }

}  // namespace

TEST_CASE("the edge-along-normal test without its square root decides as FORMAT.md's formula", "[frames]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> exponent(-330, 330), unit(0, 1);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double denormal = std::numeric_limits<double>::denorm_min(), largest = std::numeric_limits<double>::max();
  int near = 0, along = 0;
  auto check = [&](double t1_length, double edge_squared) {
    INFO("|t1| " << t1_length << ", edge . edge " << edge_squared);
    const bool expected = spec_along_normal(t1_length, edge_squared);
    REQUIRE(frames::edge_along_normal(t1_length, edge_squared) == expected);
    along += expected;
  };
  // Specials: zeros, denormals, the largest double, infinities, NaN, on both sides.
  for (double t : {0.0, denormal, 1e-300, 1e-162, 1e-12, 1.0, 1e154, largest, inf, nan})
    for (double e : {0.0, denormal, 1e-320, 1e-300, 1e-200, 1e-199, 1.0, 1e300, largest, inf, nan}) check(t, e);
  // At the threshold: |t1| within a few ulps of the spec's 1e-12 * sqrt(edge . edge), where only
  // the exact path decides, over the whole exponent range (the fast path must never answer there).
  for (int i = 0; i < 200000; ++i) {
    const double edge_squared = std::pow(10.0, exponent(rng)) * (1 + unit(rng));
    double t1_length = 1e-12 * std::sqrt(edge_squared);
    const int ulps = static_cast<int>(rng() % 9) - 4;
    for (int k = 0; k < std::abs(ulps); ++k) t1_length = std::nextafter(t1_length, ulps > 0 ? inf : 0.0);
    near += std::abs(ulps) <= 1;
    check(t1_length, edge_squared);
    // Around twice the threshold, where the fast path's own comparison decides.
    check(2 * t1_length, edge_squared);
    check(std::nextafter(2 * t1_length, 0.0), edge_squared);
    check(std::nextafter(2 * t1_length, inf), edge_squared);
  }
  // Ordinary edges of all proportions.
  for (int i = 0; i < 200000; ++i) check(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)));
  REQUIRE(near > 10000);
  REQUIRE(along > 1000);  // both answers were exercised near the threshold
}

TEST_CASE("frames with one normals array reused level after level give the bits of fresh arrays", "[frames]") {
  // Levels of growing and shrinking size in one array: each LevelFrames must start its normals
  // from zero, whatever the array held before.
  const TriangleMesh base = test::icosahedron();
  const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), 3);
  const std::vector<double> values = test::random_values(std::size_t{h.vertex_count(3)} * 4, 3);
  std::vector<frames::Vec3> storage;
  for (int level : {2, 0, 1, 2, 1}) {
    std::vector<double> fresh = values, reused = values;
    frames::rotate_details(h, level, values, fresh, 4, frames::Direction::to_global);
    frames::LevelFrames level_frames(h, level, values, 4, std::move(storage));
    level_frames.rotate(0, level_frames.edge_count(), reused, frames::Direction::to_global);
    storage = std::move(level_frames).release_storage();
    INFO("level " << level);
    REQUIRE(std::memcmp(fresh.data(), reused.data(), fresh.size() * sizeof(double)) == 0);
    REQUIRE(fresh != values);  // the details did turn
  }
}
