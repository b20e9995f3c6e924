// Ten and more levels of subdivision converge to the limit positions (issue: "subdividing 10+
// levels converges to the limit masks"). Loop through the codec's own flat stencil tables
// (synthesis with zero details), Catmull-Clark through remesh's subdivider, each against the
// closed-form limit points of limit.h. Tolerances: the error of an original vertex falls like
// the subdominant eigenvalue to the power of the level count, (3/8 + cos(2 pi / n) / 4)^2 for
// Loop at valence n (9/64 at n = 4, 1/16 at n = 3), 1/4 for the boundary curve, at most
// about 0.42 per level for Catmull-Clark at valence 3; after 10 levels that is below 1e-3 of
// the initial offset everywhere, and the test asks for 1e-6 of the bounding-box diagonal.
#include <catch2/catch.hpp>
#include <cmath>

#include "meshlift/lifting.h"
#include "meshlift/limit.h"
#include "meshlift/polygon_subdivision.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {
double max_distance(const std::vector<double>& a, const std::vector<double>& b, std::size_t vertices) {
  double worst = 0;
  for (std::size_t v = 0; v < vertices; ++v)
    worst = std::max(worst, std::hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]));
  return worst;
}
}  // namespace

TEST_CASE("10 levels of Loop synthesis reach the Loop limit points", "[remesh][limit][deep]") {
  for (const auto& [name, base] : {std::pair{"bicone3 (closed)", test::bicone(3)}, std::pair{"disk5 (boundary)", test::disk(5)}}) {
    INFO(name);
    constexpr int levels = 10;
    SemiRegularMesh mesh = refine_linear(base, levels);
    std::fill(mesh.positions.begin() + static_cast<std::ptrdiff_t>(base.positions.size()), mesh.positions.end(), 0.0);
    WaveletTransform(mesh.hierarchy, {Scheme::loop, false}).synthesize(mesh.positions);
    const TriangleMesh limit = loop_limit(base);
    const double error = max_distance(mesh.positions, limit.positions, base.vertex_count());
    const double diagonal = bounding_box_diagonal(base.positions);
    std::printf("Loop, %s, %d levels (%u vertices): max distance to the limit points %.2e x diagonal\n", name, levels,
                mesh.hierarchy.vertex_count(levels), error / diagonal);
    CHECK(error <= 1e-6 * diagonal);
  }
}

TEST_CASE("10 levels of Catmull-Clark reach the Catmull-Clark limit points", "[remesh][limit][deep]") {
  const PolygonMesh cube = test::cube_quads();
  constexpr int levels = 10;
  const PolygonMesh fine = catmull_clark(cube, levels);
  const PolygonMesh limit = catmull_clark_limit(cube);
  const double error = max_distance(fine.positions, limit.positions, cube.vertex_count());
  const double diagonal = bounding_box_diagonal(cube.positions);
  std::printf("Catmull-Clark, cube, %d levels (%zu vertices): max distance to the limit points %.2e x diagonal\n", levels,
              fine.vertex_count(), error / diagonal);
  CHECK(error <= 1e-6 * diagonal);
}
