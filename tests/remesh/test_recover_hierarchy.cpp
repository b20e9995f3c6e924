// Recognizing subdivision connectivity in any vertex and face order (remesh.h).
#include <algorithm>
#include <array>
#include <numeric>
#include <random>

#include "meshlift/remesh.h"
#include "test_meshes.h"

using namespace meshlift;
using meshlift::test::perturbed;

namespace {

/// The same mesh with vertices renumbered, faces shuffled and each face's corners rotated.
TriangleMesh scrambled(const TriangleMesh& mesh, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> to_new(mesh.vertex_count());
  std::iota(to_new.begin(), to_new.end(), 0u);
  std::shuffle(to_new.begin(), to_new.end(), rng);
  TriangleMesh out;
  out.positions.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k) out.positions[3 * to_new[v] + k] = mesh.positions[3 * v + k];
  std::vector<std::size_t> order(mesh.face_count());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t f : order) {
    const int r = static_cast<int>(rng() % 3);
    for (int i = 0; i < 3; ++i) out.triangles.push_back(to_new[mesh.triangles[3 * f + (i + r) % 3]]);
  }
  return out;
}

/// Faces as triples of corner positions, rotation-normalized and sorted: equal for two meshes
/// that differ only in vertex numbering, face order and corner rotation (positions distinct).
std::vector<std::array<double, 9>> geometric_faces(const TriangleMesh& mesh) {
  std::vector<std::array<double, 9>> faces;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    std::array<std::array<double, 3>, 3> c;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) c[i][k] = mesh.positions[3 * mesh.triangles[3 * f + i] + k];
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces.push_back({c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2]});
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

void check_recovers(const TriangleMesh& base, int levels, unsigned seed, int expected_levels) {
  SemiRegularMesh refined = refine_linear(base, levels);
  // Perturb so that every vertex has a distinct position (the comparison is geometric).
  refined.positions = perturbed(TriangleMesh{refined.positions, {}}, 1e-3, seed).positions;
  const TriangleMesh fine = refined.finest();
  const TriangleMesh input = scrambled(fine, seed);
  const auto recovered = recover_semi_regular(input);
  REQUIRE(recovered.has_value());
  CHECK(recovered->hierarchy.levels() == expected_levels);
  CHECK(recovered->hierarchy.vertex_count(recovered->hierarchy.levels()) == input.vertex_count());
  CHECK(geometric_faces(recovered->finest()) == geometric_faces(input));
  if (expected_levels == levels) {
    CHECK(recovered->hierarchy.vertex_count(0) == base.vertex_count());
    // The recovered base is the original base, up to numbering.
    const TriangleMesh recovered_base = recovered->mesh_at(0, recovered->positions);
    CHECK(geometric_faces(recovered_base) == geometric_faces(refined.mesh_at(0, refined.positions)));
  }
}

}  // namespace

TEST_CASE("A scrambled refinement of a closed mesh recovers its hierarchy exactly", "[remesh][recover]") {
  for (unsigned seed = 1; seed <= 3; ++seed) check_recovers(test::icosahedron(), 3, seed, 3);
  check_recovers(test::bicone(7), 2, 4, 2);
}

TEST_CASE("Recovery works with boundaries and several components", "[remesh][recover]") {
  check_recovers(test::disk(5), 3, 5, 3);
  check_recovers(test::disk(3), 2, 6, 2);
  TriangleMesh two = test::icosahedron();
  const TriangleMesh fan = test::disk(7);
  const auto offset = static_cast<std::uint32_t>(two.vertex_count());
  for (std::size_t v = 0; v < fan.vertex_count(); ++v)
    two.positions.insert(two.positions.end(), {fan.positions[3 * v] + 5, fan.positions[3 * v + 1], fan.positions[3 * v + 2]});
  for (std::uint32_t i : fan.triangles) two.triangles.push_back(i + offset);
  check_recovers(two, 2, 7, 2);
}

TEST_CASE("Recovery on regular meshes without extraordinary vertices", "[remesh][recover]") {
  // torus(4, 4) is no refinement (valence 6 everywhere, 32 faces, but a 2 x 2 torus is not a
  // manifold mesh); refined twice, at least those two levels come back.
  SemiRegularMesh refined = refine_linear(test::torus(4, 4), 2);
  refined.positions = perturbed(TriangleMesh{refined.positions, {}}, 1e-3, 8).positions;
  const TriangleMesh input = scrambled(refined.finest(), 8);
  const auto recovered = recover_semi_regular(input);
  REQUIRE(recovered.has_value());
  CHECK(recovered->hierarchy.levels() >= 2);
  CHECK(geometric_faces(recovered->finest()) == geometric_faces(input));
  // A planar grid of 2^k + 1 vertices a side with uniform diagonals is itself a refinement.
  const auto grid = recover_semi_regular(scrambled(perturbed(test::grid(9), 1e-3, 9), 9));
  REQUIRE(grid.has_value());
  CHECK(grid->hierarchy.levels() == 3);
  CHECK(grid->hierarchy.vertex_count(0) == 4);
}

TEST_CASE("Meshes that are not refinements are not recognized", "[remesh][recover]") {
  CHECK_FALSE(recover_semi_regular(test::icosahedron()).has_value());  // 20 faces, all valence 5
  CHECK_FALSE(recover_semi_regular(test::bicone(8)).has_value());
  // One flipped diagonal breaks the finest split; the coarser levels are still not reachable
  // because recovery undoes splits from the finest one.
  SemiRegularMesh refined = refine_linear(test::icosahedron(), 2);
  TriangleMesh broken = refined.finest();
  const TriangleTopology t = TriangleTopology::build(static_cast<std::uint32_t>(broken.vertex_count()), broken.triangles);
  // Flip edge 0: faces (a, b, c) and (b, a, d) become (c, a, d) and (d, b, c).
  const std::uint32_t f0 = t.edge_faces[0], f1 = t.edge_faces[1];
  const std::uint32_t a = t.edge_vertices[0], b = t.edge_vertices[1];
  const std::uint32_t c = t.opposite_vertex(f0, 0), d = t.opposite_vertex(f1, 0);
  std::copy_n(std::array<std::uint32_t, 3>{c, a, d}.begin(), 3, broken.triangles.begin() + 3 * f0);
  std::copy_n(std::array<std::uint32_t, 3>{d, b, c}.begin(), 3, broken.triangles.begin() + 3 * f1);
  CHECK_FALSE(recover_semi_regular(scrambled(broken, 10)).has_value());
  // An isolated vertex is not part of any refinement.
  TriangleMesh isolated = refined.finest();
  isolated.positions.insert(isolated.positions.end(), {9, 9, 9});
  CHECK_FALSE(recover_semi_regular(scrambled(isolated, 11)).has_value());
}

TEST_CASE("remesh() takes a semi-regular input over as it is", "[remesh][recover]") {
  SemiRegularMesh refined = refine_linear(test::icosahedron(), 2);
  refined.positions = perturbed(TriangleMesh{refined.positions, {}}, 1e-2, 12).positions;
  const TriangleMesh input = scrambled(refined.finest(), 12);
  const RemeshResult result = remesh(input);
  CHECK(result.recognized);
  CHECK(result.base_vertices == 12);
  CHECK(geometric_faces(result.mesh.finest()) == geometric_faces(input));
  CHECK(result.coincident_vertices == 0);
  // Vertices at the same position are counted, whichever route recognizes the mesh: in level
  // order (the count made beside the recovery) or scrambled (the validation's count).
  TriangleMesh pinched = refined.finest();
  const std::uint32_t last = static_cast<std::uint32_t>(pinched.vertex_count() - 1);
  std::copy_n(pinched.positions.begin(), 3, pinched.positions.begin() + 3 * std::ptrdiff_t{last});  // onto vertex 0
  for (const TriangleMesh& m : {pinched, scrambled(pinched, 13)}) {
    const RemeshResult r = remesh(m);
    CHECK(r.recognized);
    CHECK(r.coincident_vertices == 1);
  }
}

TEST_CASE("A level-ordered mesh refined again in another numbering recovers every level", "[remesh][recover]") {
  // A semi-regular mesh in level order (a remesh as `meshlift remesh` writes it), refined once
  // more by a tool that takes it as a plain mesh and numbers the new vertices in its own edge
  // order (`meshlift subdivide`: TriangleTopology::build of the finest faces). Its top split is
  // level-ordered, the ones below are not in that numbering: all must be undone, down to the
  // icosahedron, not just the top one.
  const int levels = GENERATE(1, 2, 3);
  SemiRegularMesh ordered = refine_linear(test::icosahedron(), levels);
  ordered.positions = perturbed(TriangleMesh{ordered.positions, {}}, 1e-3, 13).positions;
  const SemiRegularMesh again = refine_linear(ordered.finest(), 1);
  const TriangleMesh input = again.finest();
  const auto recovered = recover_semi_regular(input);
  REQUIRE(recovered.has_value());
  CHECK(recovered->hierarchy.levels() == levels + 1);
  CHECK(recovered->hierarchy.vertex_count(0) == 12);
  CHECK(geometric_faces(recovered->finest()) == geometric_faces(input));
  CHECK(geometric_faces(recovered->mesh_at(0, recovered->positions)) ==
        geometric_faces(ordered.mesh_at(0, ordered.positions)));
  // And remesh() takes it over as it is, with every level.
  const RemeshResult result = remesh(input);
  CHECK(result.recognized);
  CHECK(result.mesh.hierarchy.levels() == levels + 1);
}

TEST_CASE("remesh() refuses what its level-order route must not take over", "[remesh][recover]") {
  // Two triangles on the same three corners pass TriangleTopology::build, but their refinements'
  // inner edges coincide (four faces on each): refused as non-manifold, as validation says.
  const TriangleMesh dihedron{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 1}};
  const TriangleMesh refined = refine_linear(dihedron, 2).finest();
  CHECK_FALSE(recover_in_level_order(refined).has_value());
  CHECK_THROWS_WITH(remesh(refined), Catch::Contains("non-manifold"));
  // Positions that are not a whole number of vertices: refused as malformed, never read past.
  TriangleMesh extra = refine_linear(test::icosahedron(), 2).finest();
  extra.positions.push_back(0.5);
  extra.positions.shrink_to_fit();
  CHECK_FALSE(recover_in_level_order(extra).has_value());
  CHECK_THROWS_WITH(remesh(extra), Catch::Contains("malformed"));
}
