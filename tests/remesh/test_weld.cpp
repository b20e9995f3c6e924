// Joining coincident vertices (weld.h).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "meshlift/validate.h"
#include "meshlift/weld.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// The cube's six faces as pieces of their own: four vertices and two triangles each.
TriangleMesh unwelded_cube() {
  const double corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  TriangleMesh m;
  for (const auto& q : quads) {
    const std::uint32_t first = static_cast<std::uint32_t>(m.vertex_count());
    for (int c : q) m.positions.insert(m.positions.end(), corners[c], corners[c] + 3);
    m.triangles.insert(m.triangles.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
  }
  return m;
}

}  // namespace

TEST_CASE("weld: a cube of unwelded faces becomes one closed surface", "[weld]") {
  const TriangleMesh pieces = unwelded_cube();
  const MeshReport before = validate_mesh(pieces);
  REQUIRE(before.connected_components == 6);
  REQUIRE(before.duplicate_vertices == 16);
  const Welding w = weld_coincident(pieces);
  CHECK(w.joined_vertices == 16);
  CHECK(w.dropped_faces == 0);
  CHECK(w.duplicate_faces == 0);
  CHECK(w.mesh.vertex_count() == 8);
  CHECK(w.mesh.face_count() == 12);
  const MeshReport after = validate_mesh(w.mesh);
  CHECK(after.connected_components == 1);
  CHECK(after.duplicate_vertices == 0);
  REQUIRE(after.components.size() == 1);
  CHECK(after.components[0].closed);
  CHECK(after.components[0].manifold);
  CHECK(after.components[0].genus == 0);
  // Every face keeps its corners' positions, in its turn.
  for (std::size_t f = 0; f < 12; ++f)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        CHECK(w.mesh.positions[3 * w.mesh.triangles[3 * f + i] + k] == pieces.positions[3 * pieces.triangles[3 * f + i] + k]);
  // A welded mesh comes back as it is.
  const Welding again = weld_coincident(w.mesh);
  CHECK(again.joined_vertices == 0);
  CHECK(again.mesh.positions == w.mesh.positions);
  CHECK(again.mesh.triangles == w.mesh.triangles);
}

TEST_CASE("weld: -0 and +0 meet, NaN never does, and faces left without area or copied are dropped", "[weld]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  TriangleMesh m;
  m.positions = {0, 0, 0,  1, 0, 0,  0, 1, 0,  -0.0, 0, 0,  1, 0, 0,  nan, 0, 0,  nan, 0, 0,  0, 1, 0};
  // 0 1 2; its copy on the joined vertices 3 4 7; its reverse; a face whose corners 0 and 3 meet.
  m.triangles = {0, 1, 2,  3, 4, 7,  2, 1, 0,  0, 3, 1,  5, 6, 0};
  const Welding w = weld_coincident(m);
  CHECK(w.joined_vertices == 3);  // 3 into 0, 4 into 1, 7 into 2; the NaNs stay apart
  CHECK(w.mesh.vertex_count() == 5);
  CHECK(w.dropped_faces == 1);    // 0 3 1
  CHECK(w.duplicate_faces == 1);  // 3 4 7, the same as 0 1 2
  // Kept: 0 1 2, its reverse (for the validation to name), and the face on the NaN vertices.
  CHECK(w.mesh.triangles == std::vector<std::uint32_t>{0, 1, 2, 2, 1, 0, 3, 4, 0});
}

TEST_CASE("first_at_same_position: the lowest index at each exact position, as a search over all pairs finds it", "[weld]") {
  // Positions drawn from a few values (so that many coincide), with -0 and +0, NaN and infinities
  // among them; against the quadratic definition, at sizes that make the hash table probe far.
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const double values[] = {0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, nan, inf, -inf, 3.0};
  for (const std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{300}, std::size_t{3000}}) {
    std::mt19937 rng(static_cast<unsigned>(n));
    std::vector<double> p(3 * n);
    for (double& x : p) x = values[rng() % (n < 100 ? 10 : 4 + rng() % 6)];
    const std::vector<std::uint32_t> first = first_at_same_position(p);
    REQUIRE(first.size() == n);
    for (std::size_t v = 0; v < n; ++v) {
      std::uint32_t expected = static_cast<std::uint32_t>(v);
      const bool finite = std::isfinite(p[3 * v]) && std::isfinite(p[3 * v + 1]) && std::isfinite(p[3 * v + 2]);
      for (std::size_t u = 0; finite && u < v; ++u)
        if (p[3 * u] == p[3 * v] && p[3 * u + 1] == p[3 * v + 1] && p[3 * u + 2] == p[3 * v + 2]) {
          expected = static_cast<std::uint32_t>(u);
          break;
        }
      REQUIRE(first[v] == expected);
    }
  }
}
