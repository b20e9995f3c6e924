#include <catch2/catch.hpp>
#include <set>

#include "meshlift/semi_regular.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {
SemiRegularHierarchy hierarchy_of(const TriangleMesh& m, int levels) {
  return SemiRegularHierarchy(TriangleTopology::build(static_cast<std::uint32_t>(m.vertex_count()), m.triangles), levels);
}

// Euler characteristic V - E + F of a topology.
long euler(const TriangleTopology& t) {
  return static_cast<long>(t.vertex_count) - static_cast<long>(t.edge_count()) + static_cast<long>(t.face_count());
}
}  // namespace

TEST_CASE("topology rejects what is not a manifold - consistently oriented triangle mesh", "[topology]") {
  const std::vector<std::uint32_t> fin = {0, 1, 2, 1, 0, 3, 0, 1, 4};  // three faces on edge (0,1)
  CHECK_THROWS_WITH(TriangleTopology::build(5, fin), Catch::Contains("non-manifold edge (0, 1)"));
  const std::vector<std::uint32_t> flipped = {0, 1, 2, 0, 1, 3};  // both run 0 -> 1
  CHECK_THROWS_WITH(TriangleTopology::build(4, flipped), Catch::Contains("inconsistent orientation"));
  // Two fans meeting at vertex 0 (bowtie).
  const std::vector<std::uint32_t> bowtie = {0, 1, 2, 0, 3, 4};
  CHECK_THROWS_WITH(TriangleTopology::build(5, bowtie), Catch::Contains("non-manifold vertex 0"));
  // Two closed cones sharing their apex: each fan is closed, still pinched.
  TriangleMesh a = test::bicone(4);
  std::vector<std::uint32_t> two = a.triangles;
  for (std::uint32_t i : a.triangles) two.push_back(i == 0 ? 0 : i + 6);
  CHECK_THROWS_WITH(TriangleTopology::build(12, two), Catch::Contains("non-manifold vertex 0"));
  const std::vector<std::uint32_t> repeated = {0, 1, 1};
  CHECK_THROWS_WITH(TriangleTopology::build(3, repeated), Catch::Contains("repeats a vertex"));
  const std::vector<std::uint32_t> out_of_range = {0, 1, 7};
  CHECK_THROWS_WITH(TriangleTopology::build(3, out_of_range), Catch::Contains("does not exist"));
}

TEST_CASE("refinement keeps topology and numbers vertices level by level", "[hierarchy]") {
  for (const auto& [name, mesh] : {std::pair{"icosahedron", test::icosahedron()}, std::pair{"torus", test::torus()},
                                   std::pair{"grid", test::grid(4)}, std::pair{"disk7", test::disk(7)}}) {
    INFO(name);
    const auto h = hierarchy_of(mesh, 4);
    for (int j = 0; j < 4; ++j) {
      const auto& c = h.topology(j);
      const TriangleTopology f = c.refined();
      // The hierarchy stores the same faces (its finest level keeps only those).
      CHECK(h.triangles(j + 1) == f.triangles);
      CHECK(c.refined_triangles() == f.triangles);
      if (j + 1 < 4) CHECK(h.topology(j + 1).edge_vertices == f.edge_vertices);
      // V_{j+1} = V_j + E_j, F_{j+1} = 4 F_j, Euler characteristic unchanged.
      CHECK(f.vertex_count == c.vertex_count + c.edge_count());
      CHECK(f.face_count() == 4 * c.face_count());
      CHECK(euler(f) == euler(c));
      // The refined topology is exactly what a fresh build from its triangles gives (orientation
      // consistent, manifold), and its edge count agrees.
      const auto rebuilt = TriangleTopology::build(f.vertex_count, f.triangles);
      CHECK(rebuilt.edge_count() == f.edge_count());
      // Edge/face incidences are mutually consistent.
      for (std::uint32_t e = 0; e < f.edge_count(); ++e)
        for (int s = 0; s < 2; ++s) {
          const std::uint32_t face = f.edge_faces[2 * e + s];
          if (face == kNone) continue;
          const auto* fe = &f.face_edges[3 * face];
          CHECK((fe[0] == e || fe[1] == e || fe[2] == e));
        }
      // Odd vertices of level j+1 have valence 6 inside, 4 on the boundary.
      const VertexEdges ve(f);
      for (std::uint32_t v = c.vertex_count; v < f.vertex_count; ++v) CHECK(ve.valence(v) == (ve.boundary[v] ? 4u : 6u));
    }
  }
}

TEST_CASE("coefficient tree: 4 children per interior odd vertex - 3 on the boundary - partition of each level", "[hierarchy]") {
  const auto h = hierarchy_of(test::grid(3), 3);
  for (int j = 1; j < 3; ++j) {
    std::set<std::uint32_t> seen;
    const auto& t = h.topology(j - 1);
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
      const std::uint32_t v = h.odd_vertex(j - 1, e);
      const auto kids = h.children(v);
      CHECK(kids.size() == (t.is_boundary_edge(e) ? 3u : 4u));
      for (std::uint32_t k : kids) {
        CHECK(h.parent(k) == v);
        CHECK(h.level_of(k) == j + 1);
        CHECK(seen.insert(k).second);
      }
    }
    CHECK(seen.size() == h.vertex_count(j + 1) - h.vertex_count(j));  // every odd vertex has one parent
  }
  // Roots: base vertices and level-1 odd vertices.
  for (std::uint32_t v = 0; v < h.vertex_count(1); ++v) CHECK(h.parent(v) == kNone);
  // Geometrically: children lie on the halves of the parent's edge or on the parallel inner edges,
  // i.e. within the two faces adjacent to the parent edge: distance to parent <= coarse edge length.
  const auto m = refine_linear(test::grid(3), 3);
  for (std::uint32_t v = m.hierarchy.vertex_count(2); v < m.hierarchy.vertex_count(3); ++v) {
    const std::uint32_t p = m.hierarchy.parent(v);
    double d = 0;
    for (int k = 0; k < 3; ++k) d += std::pow(m.positions[3 * v + k] - m.positions[3 * p + k], 2);
    CHECK(std::sqrt(d) <= 0.5 / 4 * std::sqrt(2.0) + 1e-12);
  }
}

TEST_CASE("hierarchy rejects absurd level counts before allocating", "[hierarchy]") {
  const auto base = test::icosahedron();
  const auto t = TriangleTopology::build(12, base.triangles);
  CHECK_THROWS_AS(SemiRegularHierarchy(t, -1), MeshError);
  CHECK_THROWS_AS(SemiRegularHierarchy(t, kMaxLevels + 1), MeshError);
  TriangleMesh big = test::grid(200);  // 79,202 faces: 12 levels would overflow 32-bit indices
  CHECK_THROWS_WITH(SemiRegularHierarchy(TriangleTopology::build(40000, big.triangles), 12), Catch::Contains("2^32"));
}

TEST_CASE("hierarchy without the finest faces makes the same faces on demand", "[hierarchy]") {
  for (const TriangleMesh& base : {test::icosahedron(), test::grid(4), test::torus(), test::disk(5)}) {
    const TriangleTopology topology = TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles);
    const SemiRegularHierarchy full(topology, 3);
    SemiRegularHierarchy lean(topology, 3, false);
    for (int j = 0; j <= 3; ++j) CHECK(lean.copy_triangles(j) == full.triangles(j));
    for (std::uint32_t v = 0; v < full.vertex_count(3); ++v) {
      REQUIRE(lean.parent(v) == full.parent(v));
      const auto a = lean.children(v), b = full.children(v);
      REQUIRE(std::vector<std::uint32_t>(a.begin(), a.end()) == std::vector<std::uint32_t>(b.begin(), b.end()));
    }
    CHECK(std::move(lean).release_finest_triangles() == full.triangles(3));
    SemiRegularHierarchy kept(topology, 2);
    CHECK(std::move(kept).release_finest_triangles() == full.triangles(2));
  }
}

TEST_CASE("to_triangle_mesh: copied or taken over, the same triangles, and a polygon refused with the mesh kept", "[mesh]") {
  PolygonMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  m.face_offsets = {0, 3, 6};
  m.face_indices = {0, 1, 2, 2, 1, 3};
  const TriangleMesh copied = to_triangle_mesh(m);
  CHECK(copied.positions == m.positions);
  CHECK(copied.triangles == std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3});
  PolygonMesh moved_from = m;
  const TriangleMesh taken = to_triangle_mesh(std::move(moved_from));
  CHECK(taken.positions == copied.positions);
  CHECK(taken.triangles == copied.triangles);
  CHECK(moved_from.vertex_count() == 0);
  CHECK(moved_from.face_count() == 0);
  // Faces that do not start at index 0 of face_indices (a caller's layout): their own corners.
  PolygonMesh offset = m;
  offset.face_offsets = {1, 4, 7};
  offset.face_indices.insert(offset.face_indices.begin(), 3);
  CHECK(to_triangle_mesh(offset).triangles == copied.triangles);
  CHECK(to_triangle_mesh(std::move(offset)).triangles == copied.triangles);
  // A quad: refused by both, naming it; the mesh handed over is left as it was.
  PolygonMesh quad = m;
  quad.face_offsets = {0, 3, 7};
  quad.face_indices = {0, 1, 2, 0, 1, 3, 2};
  CHECK_THROWS_WITH(to_triangle_mesh(quad), Catch::Contains("face 1 has 4 corners"));
  CHECK_THROWS_WITH(to_triangle_mesh(std::move(quad)), Catch::Contains("face 1 has 4 corners"));
  CHECK(quad.face_indices.size() == 7);  // NOLINT(bugprone-use-after-move): kept on a refusal, as documented
  CHECK(quad.positions == m.positions);
}
