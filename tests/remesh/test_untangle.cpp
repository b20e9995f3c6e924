// Untangling folded patches and vertices of a remesh (untangle.h).
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

TEST_CASE("Vertex by vertex untangling alone unfolds a vertex pushed across its ring", "[remesh][untangle]") {
  const SurfaceQuery sphere(test::icosphere(5));
  SemiRegularMesh mesh = test::sphere_refinement(3);
  const std::vector<std::uint32_t>& t = mesh.hierarchy.triangles(3);
  const std::uint32_t v = t[3 * 100], through = t[3 * 100 + 1];
  for (int c = 0; c < 3; ++c) mesh.positions[3 * v + c] += 1.8 * (mesh.positions[3 * through + c] - mesh.positions[3 * v + c]);
  const std::vector<double> tangled_positions = mesh.positions;
  const std::size_t tangled = folds(mesh, sphere);
  REQUIRE(tangled >= 2);

  UntangleOptions options;
  options.passes = 0;  // no patches: only the per-vertex linear program
  const UntangleReport report = untangle(mesh, sphere, options);
  CHECK(report.patches_tried == 0);
  CHECK(report.vertices_moved >= 1);
  CHECK(report.folded_after == 0);
  CHECK(folds(mesh, sphere) == 0);
  // Only vertices of folded faces moved.
  std::size_t moved = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); i += 3) moved += mesh.positions[i] != tangled_positions[i];
  CHECK(moved >= 1);
  CHECK(moved <= 7);

  // Without vertex passes and patches nothing happens.
  mesh.positions = tangled_positions;
  options.vertex_passes = 0;
  CHECK(untangle(mesh, sphere, options).folded_after == tangled);
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
  options = {};
  options.vertex_passes = -1;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
  options = {};
  options.rounds = 0;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
}
