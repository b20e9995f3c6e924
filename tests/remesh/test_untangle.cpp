// Untangling folded patches of a remesh (untangle.h).
#include <cmath>
#include <stdexcept>

#include "meshlift/surface_fit.h"
#include "meshlift/untangle.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

std::size_t folds(const SemiRegularMesh& mesh, const SurfaceQuery& surface) {
  const FoldOvers f = find_fold_overs(mesh.finest(), surface);
  return f.flipped.size() + f.degenerate.size();
}

}  // namespace

TEST_CASE("Untangling unfolds pleats on a sphere and leaves the vertices on it", "[remesh][untangle]") {
  const SurfaceQuery sphere(test::icosphere(5));
  SemiRegularMesh mesh = test::sphere_refinement(3);
  REQUIRE(folds(mesh, sphere) == 0);
  // Two pleats: a finest-level vertex pushed across its ring onto a neighbour's far side, and
  // two neighbouring vertices swapped.
  const SemiRegularHierarchy& h = mesh.hierarchy;
  const std::vector<std::uint32_t>& t = h.triangles(3);
  auto move_across = [&](std::uint32_t v, std::uint32_t through) {
    for (int c = 0; c < 3; ++c) mesh.positions[3 * v + c] += 1.8 * (mesh.positions[3 * through + c] - mesh.positions[3 * v + c]);
  };
  move_across(t[3 * 100], t[3 * 100 + 1]);
  for (int c = 0; c < 3; ++c) std::swap(mesh.positions[3 * t[3 * 900] + c], mesh.positions[3 * t[3 * 900 + 1] + c]);
  const std::size_t tangled = folds(mesh, sphere);
  REQUIRE(tangled >= 4);

  const UntangleReport report = untangle(mesh, sphere);
  CHECK(report.folded_before == tangled);
  CHECK(report.folded_after == 0);
  CHECK(folds(mesh, sphere) == 0);
  CHECK(report.patches_kept >= 2);
  // Moved vertices were put back on the input (a polyhedron inscribed in the unit sphere, its
  // faces within 1 - cos(edge/2) ≈ 3e-4 of it).
  for (std::size_t v = 0; v < mesh.positions.size() / 3; ++v) {
    const double r = std::sqrt(mesh.positions[3 * v] * mesh.positions[3 * v] + mesh.positions[3 * v + 1] * mesh.positions[3 * v + 1] +
                               mesh.positions[3 * v + 2] * mesh.positions[3 * v + 2]);
    CHECK(std::abs(r - 1) < 1e-3);
  }
}

TEST_CASE("Untangling leaves a mesh without folds as it is", "[remesh][untangle]") {
  const SurfaceQuery sphere(test::icosphere(4));
  SemiRegularMesh mesh = test::sphere_refinement(3);
  const std::vector<double> before = mesh.positions;
  const UntangleReport report = untangle(mesh, sphere);
  CHECK(report.folded_before == 0);
  CHECK(report.patches_tried == 0);
  CHECK(mesh.positions == before);
}

TEST_CASE("Untangling rejects options out of range", "[remesh][untangle]") {
  const SurfaceQuery sphere(test::icosphere(2));
  SemiRegularMesh mesh = test::sphere_refinement(3);
  UntangleOptions options;
  options.first_rings = 0;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
  options = {};
  options.max_rings = 0;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
  options = {};
  options.passes = -1;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
}
