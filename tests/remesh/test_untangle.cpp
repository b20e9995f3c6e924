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

/// A sphere's remesh (3 levels) with a finest vertex pushed `times` the way to its neighbour:
/// past it for times > 1, so that its faces fold.
SemiRegularMesh sphere_with_vertex_pushed(double times) {
  SemiRegularMesh mesh = test::sphere_refinement(3);
  const std::vector<std::uint32_t>& t = mesh.hierarchy.triangles(3);
  const std::uint32_t v = t[3 * 100], through = t[3 * 100 + 1];
  for (int c = 0; c < 3; ++c) mesh.positions[3 * v + c] += times * (mesh.positions[3 * through + c] - mesh.positions[3 * v + c]);
  return mesh;
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
  SemiRegularMesh mesh = sphere_with_vertex_pushed(1.8);
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

TEST_CASE("Untangling moves the corners of a face of tiny but nonzero area, as find_fold_overs counts it", "[remesh][untangle]") {
  // A finest vertex moved almost onto the opposite edge of one of its faces: that face keeps its
  // orientation and an area of ~1e-14, nonzero but below find_fold_overs()'s 1e-14 of the squared
  // diagonal (mannequin-devil's ~16x remesh had such a face, three corners on one input crease).
  const SurfaceQuery sphere(test::icosphere(5));
  SemiRegularMesh mesh = test::sphere_refinement(3);
  const std::vector<std::uint32_t>& t = mesh.hierarchy.triangles(3);
  const std::uint32_t a = t[3 * 100], b = t[3 * 100 + 1], c = t[3 * 100 + 2];
  double toward_a[3], length = 0;
  for (int k = 0; k < 3; ++k) {
    toward_a[k] = mesh.positions[3 * a + k] - 0.5 * (mesh.positions[3 * b + k] + mesh.positions[3 * c + k]);
    length += toward_a[k] * toward_a[k];
  }
  length = std::sqrt(length);
  for (int k = 0; k < 3; ++k)
    mesh.positions[3 * a + k] = 0.5 * (mesh.positions[3 * b + k] + mesh.positions[3 * c + k]) + 1e-13 * toward_a[k] / length;
  const FoldOvers before = find_fold_overs(mesh.finest(), sphere);
  REQUIRE(before.flipped.empty());
  REQUIRE(before.degenerate.size() == 1);
  // Not of zero area: the cross product of its edges is not 0.
  const double* p[3] = {&mesh.positions[3 * a], &mesh.positions[3 * b], &mesh.positions[3 * c]};
  const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  const double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  REQUIRE((u[1] * w[2] - u[2] * w[1] != 0 || u[2] * w[0] - u[0] * w[2] != 0 || u[0] * w[1] - u[1] * w[0] != 0));

  const UntangleReport report = untangle(mesh, sphere);
  CHECK(report.folded_before == 1);
  CHECK(report.folded_after == 0);
  CHECK(folds(mesh, sphere) == 0);
}

TEST_CASE("A patch that cannot be untangled is not tried again while nothing around it moves", "[remesh][untangle]") {
  // A pleat that untangles, and on the far side of the sphere a cap of input faces turned
  // inside out under remesh vertices that all stay (`fixed`): the remesh faces there face away
  // from the input whatever the untangling does, so every try on their patch fails. Pass 1 keeps
  // the pleat's patch and fails the cap's, so a pass 2 runs; in it the cap's patch, whose region
  // is far from the pleat, must be skipped: its tries are counted once, as when it is alone.
  SemiRegularMesh pleated = test::sphere_refinement(3);
  const std::vector<std::uint32_t>& t = pleated.hierarchy.triangles(3);
  const std::uint32_t v = t[3 * 100], through = t[3 * 100 + 1];
  double far[3];
  for (int c = 0; c < 3; ++c) far[c] = -pleated.positions[3 * v + c];
  auto along_far = [&](const std::vector<double>& x, std::uint32_t u) {
    return far[0] * x[3 * u] + far[1] * x[3 * u + 1] + far[2] * x[3 * u + 2];
  };
  const SemiRegularMesh smooth = pleated;
  for (int c = 0; c < 3; ++c) pleated.positions[3 * v + c] += 1.8 * (pleated.positions[3 * through + c] - pleated.positions[3 * v + c]);

  TriangleMesh capped = test::icosphere(5);
  std::size_t turned = 0;
  for (std::size_t f = 0; f < capped.face_count(); ++f) {
    const std::uint32_t* corners = &capped.triangles[3 * f];
    if (along_far(capped.positions, corners[0]) + along_far(capped.positions, corners[1]) + along_far(capped.positions, corners[2]) > 3 * 0.97)
      std::swap(capped.triangles[3 * f + 1], capped.triangles[3 * f + 2]), ++turned;
  }
  REQUIRE(turned >= 10);
  const SurfaceQuery sphere(test::icosphere(5)), cap(std::move(capped));
  std::vector<std::uint8_t> fixed(pleated.positions.size() / 3, 0);
  for (std::uint32_t u = 0; u < fixed.size(); ++u) fixed[u] = along_far(smooth.positions, u) > 0.9;

  UntangleOptions options;
  options.vertex_passes = 0;
  options.rounds = 1;
  options.fixed = fixed;
  SemiRegularMesh mesh = pleated;
  const UntangleReport pleat_alone = untangle(mesh, sphere, options);
  REQUIRE(pleat_alone.folded_before >= 2);
  REQUIRE(pleat_alone.folded_after == 0);
  mesh = smooth;
  const UntangleReport cap_alone = untangle(mesh, cap, options);
  REQUIRE(cap_alone.folded_before >= 4);
  REQUIRE(cap_alone.folded_after == cap_alone.folded_before);
  REQUIRE(cap_alone.patches_kept == 0);
  REQUIRE(cap_alone.patches_tried >= 2);

  mesh = pleated;
  const UntangleReport both = untangle(mesh, cap, options);
  CHECK(both.folded_before == pleat_alone.folded_before + cap_alone.folded_before);
  CHECK(both.folded_after == cap_alone.folded_before);
  CHECK(both.patches_kept == pleat_alone.patches_kept);
  CHECK(both.patches_tried == pleat_alone.patches_tried + cap_alone.patches_tried);  // was + 2 x cap_alone's
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
  options = {};
  options.relaxation_steps = -1;
  CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
  for (double budget : {0.0, -1.0, std::nan("")}) {
    options = {};
    options.max_patch_queries_per_face = budget;
    CHECK_THROWS_AS(untangle(mesh, sphere, options), std::invalid_argument);
  }
}

TEST_CASE("The patch passes stop at their budget of queries per face, and the vertex passes still run",
          "[remesh][untangle]") {
  // Two pleats, as above: the default budget (16 queries a face) is far from spent on them, and
  // the patches alone untangle them. A budget that the first patch already spends stops the
  // patch passes after it (the check is made before each patch), so at most one patch is tried
  // in all; the vertex passes still run, and what they leave is not more than before.
  const SurfaceQuery sphere(test::icosphere(5));
  SemiRegularMesh pleated = test::sphere_refinement(3);
  const std::vector<std::uint32_t>& t = pleated.hierarchy.triangles(3);
  for (int c = 0; c < 3; ++c) {
    pleated.positions[3 * t[3 * 100] + c] += 1.8 * (pleated.positions[3 * t[3 * 100 + 1] + c] - pleated.positions[3 * t[3 * 100] + c]);
    std::swap(pleated.positions[3 * t[3 * 900] + c], pleated.positions[3 * t[3 * 900 + 1] + c]);
  }
  UntangleOptions patches_only;
  patches_only.vertex_passes = 0;
  SemiRegularMesh mesh = pleated;
  const UntangleReport plenty = untangle(mesh, sphere, patches_only);
  CHECK_FALSE(plenty.patch_budget_spent);
  CHECK(plenty.folded_after == 0);
  CHECK(plenty.patches_kept >= 2);

  UntangleOptions tight = patches_only;
  tight.max_patch_queries_per_face = 1e-6;  // spent by the first patch's first fold tests
  mesh = pleated;
  const UntangleReport stopped = untangle(mesh, sphere, tight);
  CHECK(stopped.patch_budget_spent);
  CHECK(stopped.patches_tried <= 35);  // one patch: 5 region sizes of 7 tries at most
  CHECK(stopped.folded_after > 0);   // the other pleat's patch never tried

  tight.vertex_passes = UntangleOptions{}.vertex_passes;
  mesh = pleated;
  const UntangleReport with_vertices = untangle(mesh, sphere, tight);
  CHECK(with_vertices.patch_budget_spent);
  CHECK(with_vertices.folded_after <= stopped.folded_after);
  CHECK(folds(mesh, sphere) == with_vertices.folded_after);
}

TEST_CASE("search_unfolded unfolds a face by moving the vertices around it, in floats, the same every time", "[remesh][untangle]") {
  const SurfaceQuery sphere(test::icosphere(5));
  SemiRegularMesh mesh = sphere_with_vertex_pushed(1.3);  // a third of an edge past its neighbour
  const std::vector<std::uint32_t>& t = mesh.hierarchy.triangles(3);
  const std::vector<double> tangled = mesh.positions;
  const FoldOvers before = find_fold_overs(mesh.finest(), sphere);
  std::vector<std::uint32_t> faces = before.flipped;
  faces.insert(faces.end(), before.degenerate.begin(), before.degenerate.end());
  REQUIRE(faces.size() >= 2);

  const FoldSearchReport report = search_unfolded(mesh, sphere, faces);
  CHECK(report.tried >= 1);
  CHECK(report.mended == report.tried);
  CHECK(folds(mesh, sphere) == 0);
  // Moved: only vertices within max_rings rings of a folded face's corners, each to a float position.
  std::vector<std::uint8_t> near(mesh.positions.size() / 3, 0);
  for (const std::uint32_t f : faces)
    for (int i = 0; i < 3; ++i) near[t[3 * f + i]] = 1;
  for (int ring = 0; ring < FoldSearchOptions{}.max_rings; ++ring) {
    std::vector<std::uint8_t> next = near;
    for (std::size_t f = 0; f < t.size() / 3; ++f)
      if (near[t[3 * f]] || near[t[3 * f + 1]] || near[t[3 * f + 2]])
        for (int i = 0; i < 3; ++i) next[t[3 * f + i]] = 1;
    near = std::move(next);
  }
  std::size_t moved = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (mesh.positions[i] != tangled[i]) {
      ++moved;
      CHECK(near[i / 3] == 1);
      CHECK(mesh.positions[i] == static_cast<double>(static_cast<float>(mesh.positions[i])));
    }
  CHECK(moved >= 1);
  // The same moves from the same start.
  const std::vector<double> first = mesh.positions;
  mesh.positions = tangled;
  search_unfolded(mesh, sphere, faces);
  CHECK(mesh.positions == first);

  // A search that cannot reach far enough puts every vertex back; none searches with 0 moves.
  mesh.positions = tangled;
  FoldSearchOptions options;
  options.reach = 1e-3;
  const FoldSearchReport short_reach = search_unfolded(mesh, sphere, faces, options);
  CHECK(short_reach.tried >= 1);
  CHECK(short_reach.mended == 0);
  CHECK(mesh.positions == tangled);
  options = {};
  options.evaluations = 0;
  CHECK(search_unfolded(mesh, sphere, faces, options).tried == 0);
  CHECK(mesh.positions == tangled);
  // Options out of range, each alone: out_of_range() names them and search_unfolded() throws.
  const auto first_rings = [](FoldSearchOptions& o) { o.first_rings = 0; };
  const auto max_rings = [](FoldSearchOptions& o) { o.max_rings = 0; };
  const auto reach = [](FoldSearchOptions& o) { o.reach = 0; };
  const auto attempts = [](FoldSearchOptions& o) { o.attempts = 0; };
  const auto evaluations = [](FoldSearchOptions& o) { o.evaluations = -1; };
  CHECK(out_of_range(FoldSearchOptions{}).empty());
  for (void (*spoil)(FoldSearchOptions&) : {+first_rings, +max_rings, +reach, +attempts, +evaluations}) {
    options = {};
    spoil(options);
    CHECK_FALSE(out_of_range(options).empty());
    CHECK_THROWS_AS(search_unfolded(mesh, sphere, faces, options), std::invalid_argument);
  }
}
