// Catmull-Clark against OpenMesh's CatmullClarkT; Doo-Sabin against hand-computed stencils.
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <vector>

#include "meshlift/polygon_subdivision.h"
#include "test_meshes.h"
#include "test_openmesh.h"

namespace {

using namespace meshlift;

using test::OpenMeshPoly;



PolygonMesh openmesh_catmull_clark(const PolygonMesh& mesh, int levels) {
  OpenMeshPoly om = test::to_openmesh<OpenMeshPoly>(mesh);
  OpenMesh::Subdivider::Uniform::CatmullClarkT<OpenMeshPoly, double> subdivider;
  REQUIRE(subdivider(om, static_cast<std::size_t>(levels)));
  return test::from_openmesh(om);
}

double distance(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Rotates a face so its smallest index comes first (orientation kept).
std::vector<std::uint32_t> canonical_face(std::vector<std::uint32_t> face) {
  std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
  return face;
}

// `ours` and `theirs` are the same mesh up to a vertex permutation: every vertex of ours has a
// vertex of theirs within `tolerance` (nearest match, used once), and the faces agree as oriented
// cycles under that matching.
void require_same_mesh(const PolygonMesh& ours, const PolygonMesh& theirs, double tolerance) {
  REQUIRE(ours.vertex_count() == theirs.vertex_count());
  REQUIRE(ours.face_count() == theirs.face_count());
  std::vector<std::uint32_t> match(ours.vertex_count());
  std::vector<char> used(theirs.vertex_count(), 0);
  double worst = 0;
  for (std::size_t v = 0; v < ours.vertex_count(); ++v) {
    double best = INFINITY;
    std::size_t best_w = 0;
    for (std::size_t w = 0; w < theirs.vertex_count(); ++w) {
      const double d = distance(&ours.positions[3 * v], &theirs.positions[3 * w]);
      if (d < best) best = d, best_w = w;
    }
    REQUIRE_FALSE(used[best_w]);
    used[best_w] = 1;
    match[v] = static_cast<std::uint32_t>(best_w);
    worst = std::max(worst, best);
  }
  CHECK(worst <= tolerance);
  std::multiset<std::vector<std::uint32_t>> our_faces, their_faces;
  for (std::size_t f = 0; f < ours.face_count(); ++f) {
    std::vector<std::uint32_t> face;
    for (std::uint32_t c = ours.face_offsets[f]; c < ours.face_offsets[f + 1]; ++c)
      face.push_back(match[ours.face_indices[c]]);
    our_faces.insert(canonical_face(face));
  }
  for (std::size_t f = 0; f < theirs.face_count(); ++f) {
    std::vector<std::uint32_t> face(theirs.face_indices.begin() + theirs.face_offsets[f],
                                    theirs.face_indices.begin() + theirs.face_offsets[f + 1]);
    their_faces.insert(canonical_face(face));
  }
  CHECK(our_faces == their_faces);
}



// Open fan of four quads and one triangle around a centre of valence 5 (boundary, mixed faces).
PolygonMesh open_mixed_fan() {
  PolygonMesh m;
  m.positions = {0, 0, 0.3};
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * M_PI * i / 5, b = a + M_PI / 5;
    m.positions.insert(m.positions.end(), {std::cos(a), std::sin(a), 0.1 * i});
    m.positions.insert(m.positions.end(), {1.6 * std::cos(b), 1.6 * std::sin(b), -0.2 + 0.05 * i * i});
  }
  // ring vertex i at 1 + 2i, outer vertex i at 2 + 2i
  for (std::uint32_t i = 0; i < 5; ++i) {
    const std::uint32_t r0 = 1 + 2 * i, outer = 2 + 2 * i, r1 = 1 + 2 * ((i + 1) % 5);
    if (i == 4)
      m.face_indices.insert(m.face_indices.end(), {0, r0, r1});
    else
      m.face_indices.insert(m.face_indices.end(), {0, r0, outer, r1});
    m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_indices.size()));
  }
  m.positions.resize(3 * 10);  // outer vertex 4 (index 10) is unused by the triangle: drop it
  return m;
}

bool has_boundary(const PolygonMesh& mesh) {
  const PolygonTopology topology = build_topology(mesh);
  return std::any_of(topology.boundary.begin(), topology.boundary.end(), [](auto b) { return b != 0; });
}

}  // namespace

TEST_CASE("catmull_clark equals OpenMesh CatmullClarkT", "[remesh][catmull_clark]") {
  const std::vector<std::pair<const char*, PolygonMesh>> meshes = {
      {"cube", test::cube_quads()},
      {"open 4x4 quad grid", test::open_quad_grid(4)},
      {"pentagonal pyramid (valence 5, triangles + pentagon)", test::pentagonal_pyramid()},
      {"open mixed fan (valence 5, quads + triangle, boundary)", open_mixed_fan()},
  };
  for (const auto& [name, mesh] : meshes) {
    // OpenMesh 9 moves a boundary vertex to (b1 + 4v + b2)/6, not the cubic B-spline (b1 + 6v + b2)/8;
    // on open meshes we compare against our BoundaryVertexRule::openmesh (interior rules are shared).
    const auto rule = has_boundary(mesh) ? BoundaryVertexRule::openmesh : BoundaryVertexRule::cubic_bspline;
    for (int levels = 1; levels <= 3; ++levels) {
      INFO(name << ", " << levels << " level(s)");
      const PolygonMesh ours = catmull_clark(mesh, levels, rule);
      const PolygonMesh theirs = openmesh_catmull_clark(mesh, levels);
      require_same_mesh(ours, theirs, 1e-12 * bounding_box_diagonal(mesh.positions));
      for (std::size_t f = 0; f < ours.face_count(); ++f) REQUIRE(ours.face_size(f) == 4);
    }
  }
}

TEST_CASE("catmull_clark cubic B-spline boundary rule", "[remesh][catmull_clark]") {
  // On an open grid the two boundary rules agree everywhere except at old boundary vertices,
  // which the default rule moves to (b1 + 6v + b2)/8 (seed 004); boundary edge points are midpoints.
  const PolygonMesh grid = test::open_quad_grid(3);
  const PolygonMesh bspline = catmull_clark(grid, 1);
  const PolygonMesh openmesh = catmull_clark(grid, 1, BoundaryVertexRule::openmesh);
  REQUIRE(bspline.vertex_count() == openmesh.vertex_count());
  REQUIRE(bspline.face_indices == openmesh.face_indices);
  const int n = 3;
  auto p = [&](int i, int j, int k) { return grid.positions[3 * (i * (n + 1) + j) + k]; };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const std::size_t v = i * (n + 1) + j;
      const bool on_boundary = i == 0 || j == 0 || i == n || j == n;
      for (int k = 0; k < 3; ++k) {
        if (!on_boundary) {
          CHECK(bspline.positions[3 * v + k] == Approx(openmesh.positions[3 * v + k]).margin(1e-15));
          continue;
        }
        // boundary neighbours: walk along the boundary square (corners bend)
        int i1 = i, j1 = j, i2 = i, j2 = j;
        if (i == 0 || i == n) {
          j1 = j - 1, j2 = j + 1;
          if (j == 0) j1 = 0, i1 = i == 0 ? 1 : n - 1;
          if (j == n) j2 = n, i2 = i == 0 ? 1 : n - 1;
        } else {
          i1 = i - 1, i2 = i + 1;
        }
        const double expected = (p(i1, j1, k) + 6 * p(i, j, k) + p(i2, j2, k)) / 8;
        CHECK(bspline.positions[3 * v + k] == Approx(expected).margin(1e-15));
      }
    }
  // Edge points of boundary edges are midpoints: the new vertex between grid vertices 0 and 1.
  const double mid[3] = {(p(0, 0, 0) + p(0, 1, 0)) / 2, (p(0, 0, 1) + p(0, 1, 1)) / 2, (p(0, 0, 2) + p(0, 1, 2)) / 2};
  bool found = false;
  for (std::size_t v = grid.vertex_count(); v < bspline.vertex_count(); ++v)
    found = found || distance(&bspline.positions[3 * v], mid) < 1e-15;
  CHECK(found);
}

TEST_CASE("catmull_clark keeps isolated vertices and rejects bad input", "[remesh][catmull_clark]") {
  PolygonMesh cube = test::cube_quads();
  cube.positions.insert(cube.positions.end(), {5, 6, 7});
  const PolygonMesh once = catmull_clark(cube, 1);
  CHECK(once.positions[3 * 8] == 5);
  CHECK(once.positions[3 * 8 + 2] == 7);
  CHECK(catmull_clark(cube, 0).positions == cube.positions);

  CHECK_THROWS_AS(catmull_clark(cube, -1), MeshError);
  CHECK_THROWS_AS(catmull_clark(cube, kMaxSubdivisionLevels + 1), MeshError);
  CHECK_THROWS_AS(doo_sabin(cube, -1), MeshError);

  PolygonMesh three_faces_on_an_edge;
  three_faces_on_an_edge.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  three_faces_on_an_edge.face_indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  three_faces_on_an_edge.face_offsets = {0, 3, 6, 9};
  CHECK_THROWS_AS(catmull_clark(three_faces_on_an_edge, 1), MeshError);

  PolygonMesh flipped = test::cube_quads();
  std::reverse(flipped.face_indices.begin(), flipped.face_indices.begin() + 4);
  CHECK_THROWS_AS(doo_sabin(flipped, 1), MeshError);

  PolygonMesh bow_tie;  // two triangles sharing only a vertex
  bow_tie.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0};
  bow_tie.face_indices = {0, 1, 2, 0, 3, 4};
  bow_tie.face_offsets = {0, 3, 6};
  CHECK_THROWS_AS(catmull_clark(bow_tie, 1), MeshError);

  PolygonMesh bad_index = test::cube_quads();
  bad_index.face_indices[5] = 99;
  CHECK_THROWS_AS(catmull_clark(bad_index, 1), MeshError);

  PolygonMesh repeated = test::cube_quads();
  repeated.face_indices[1] = repeated.face_indices[0];
  CHECK_THROWS_AS(catmull_clark(repeated, 1), MeshError);
}

TEST_CASE("doo_sabin on a single quad matches (9 3 3 1)/16", "[remesh][doo_sabin]") {
  PolygonMesh quad;
  quad.positions = {0, 0, 0.1, 1.3, 0, -0.2, 1.1, 0.9, 0.4, -0.2, 1.2, 0};
  quad.face_indices = {0, 1, 2, 3};
  quad.face_offsets = {0, 4};
  const PolygonMesh out = doo_sabin(quad, 1);
  REQUIRE(out.vertex_count() == 4);
  REQUIRE(out.face_count() == 1);  // no interior edge or vertex: only the F-face
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) {
      auto x = [&](int j) { return quad.positions[3 * ((j + 4) % 4) + k]; };
      const double expected = (9 * x(i) + 3 * x(i - 1) + 3 * x(i + 1) + x(i + 2)) / 16;
      CHECK(out.positions[3 * i + k] == Approx(expected).margin(1e-15));
    }
}

TEST_CASE("doo_sabin on a pentagon uses the seed 004 weights", "[remesh][doo_sabin]") {
  PolygonMesh pentagon;
  for (int i = 0; i < 5; ++i)
    pentagon.positions.insert(pentagon.positions.end(), {std::cos(1.1 * i) + 0.1 * i, std::sin(1.3 * i), 0.2 * i * i});
  pentagon.face_indices = {0, 1, 2, 3, 4};
  pentagon.face_offsets = {0, 5};
  const PolygonMesh out = doo_sabin(pentagon, 1);
  // α_ii = 10/20 = 1/2; neighbours (3 + 2cos 72°)/20; the two across (3 + 2cos 144°)/20.
  const double near = (3 + 2 * std::cos(2 * M_PI / 5)) / 20, far = (3 + 2 * std::cos(4 * M_PI / 5)) / 20;
  CHECK(0.5 + 2 * near + 2 * far == Approx(1.0).margin(1e-15));
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 3; ++k) {
      auto x = [&](int j) { return pentagon.positions[3 * ((j + 5) % 5) + k]; };
      const double expected = 0.5 * x(i) + near * (x(i - 1) + x(i + 1)) + far * (x(i - 2) + x(i + 2));
      CHECK(out.positions[3 * i + k] == Approx(expected).margin(1e-15));
    }
}

TEST_CASE("doo_sabin large faces use the factorised rule consistently", "[remesh][doo_sabin]") {
  // A 70-gon (over the direct-sum cut-off) against the direct formula computed here.
  const int n = 70;
  PolygonMesh polygon;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    polygon.positions.insert(polygon.positions.end(), {std::cos(a), std::sin(a), 0.1 * std::sin(5 * a)});
    polygon.face_indices.push_back(static_cast<std::uint32_t>(i));
  }
  polygon.face_offsets = {0, n};
  const PolygonMesh out = doo_sabin(polygon, 1);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      double expected = 0;
      for (int j = 0; j < n; ++j) {
        const double alpha = i == j ? (n + 5.0) / (4.0 * n) : (3 + 2 * std::cos(2 * M_PI * (i - j) / n)) / (4.0 * n);
        expected += alpha * polygon.positions[3 * j + k];
      }
      CHECK(out.positions[3 * i + k] == Approx(expected).margin(1e-13));
    }
}

TEST_CASE("doo_sabin counts and face sizes on the cube", "[remesh][doo_sabin]") {
  const PolygonMesh cube = test::cube_quads();
  const PolygonMesh out = doo_sabin(cube, 1);
  CHECK(out.vertex_count() == 24);                 // Σ face sizes
  REQUIRE(out.face_count() == 6 + 12 + 8);         // F + E + V
  for (std::size_t f = 0; f < 18; ++f) CHECK(out.face_size(f) == 4);   // F- and E-faces
  for (std::size_t f = 18; f < 26; ++f) CHECK(out.face_size(f) == 3);  // V-faces of valence-3 vertices
  // The result is a closed manifold with consistent orientation (build_topology would throw).
  const PolygonTopology topology = build_topology(out);
  CHECK(std::none_of(topology.boundary.begin(), topology.boundary.end(), [](auto b) { return b != 0; }));
  // Euler characteristic of a sphere: V - E + F = 2.
  CHECK(24 - static_cast<long>(topology.edge_count()) + 26 == 2);
}

TEST_CASE("doo_sabin keeps a planar mesh planar", "[remesh][doo_sabin]") {
  // Mixed polygons on the tilted plane z = 0.3x - 0.2y + 1: every output vertex stays on it.
  PolygonMesh planar = open_mixed_fan();
  for (std::size_t v = 0; v < planar.vertex_count(); ++v)
    planar.positions[3 * v + 2] = 0.3 * planar.positions[3 * v] - 0.2 * planar.positions[3 * v + 1] + 1;
  const PolygonMesh out = doo_sabin(planar, 3);
  REQUIRE(out.vertex_count() > planar.vertex_count());
  for (std::size_t v = 0; v < out.vertex_count(); ++v)
    CHECK(out.positions[3 * v + 2] ==
          Approx(0.3 * out.positions[3 * v] - 0.2 * out.positions[3 * v + 1] + 1).margin(1e-14));
}

TEST_CASE("doo_sabin converges on a closed mesh", "[remesh][doo_sabin]") {
  // Distance between consecutive levels: each new vertex against the old vertex of its corner.
  // It must shrink geometrically (roughly halving with the edge length).
  PolygonMesh mesh = test::cube_quads();
  std::vector<double> step_distance;
  for (int level = 0; level < 7; ++level) {
    const PolygonMesh next = doo_sabin(mesh, 1);
    double worst = 0;
    for (std::size_t h = 0; h < mesh.face_indices.size(); ++h)
      worst = std::max(worst, distance(&next.positions[3 * h], &mesh.positions[3 * mesh.face_indices[h]]));
    step_distance.push_back(worst);
    mesh = next;
  }
  for (std::size_t k = 1; k < step_distance.size(); ++k) {
    INFO("level " << k << ": " << step_distance[k] << " after " << step_distance[k - 1]);
    CHECK(step_distance[k] < 0.6 * step_distance[k - 1]);
  }
  CHECK(step_distance.back() < 0.02 * step_distance.front());
}
