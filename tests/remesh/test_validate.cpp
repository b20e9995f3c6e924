// validate_mesh on procedural meshes with known topology (χ = V − E + F = 2 − 2g − b), and on
// every kind of defect it must report rather than trust.
#include <catch2/catch.hpp>

#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "meshlift/validate.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// Boundary surface of a set of unit voxels, each exposed face split into two triangles,
/// oriented outward: corners base, base+e_u, base+e_u+e_v, base+e_v with e_u × e_v = e_d.
TriangleMesh voxel_surface(const std::set<std::tuple<int, int, int>>& cells) {
  TriangleMesh m;
  std::map<std::tuple<int, int, int>, std::uint32_t> ids;
  const auto vertex = [&](int p[3]) {
    const auto key = std::make_tuple(p[0], p[1], p[2]);
    const auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const auto id = static_cast<std::uint32_t>(ids.size());
    ids.emplace(key, id);
    m.positions.insert(m.positions.end(), {double(p[0]), double(p[1]), double(p[2])});
    return id;
  };
  for (const auto& [x, y, z] : cells)
    for (int d = 0; d < 3; ++d)
      for (int s = -1; s <= 1; s += 2) {
        int n[3] = {x, y, z};
        n[d] += s;
        if (cells.count({n[0], n[1], n[2]})) continue;
        const int u = (d + 1) % 3, v = (d + 2) % 3;
        int c[4][3];
        for (auto& corner : c) {
          corner[0] = x, corner[1] = y, corner[2] = z;
          corner[d] += s > 0 ? 1 : 0;
        }
        c[1][u] += 1;
        c[2][u] += 1, c[2][v] += 1;
        c[3][v] += 1;
        std::uint32_t q[4];
        for (int k = 0; k < 4; ++k) q[k] = vertex(c[k]);
        if (s < 0) std::swap(q[1], q[3]);
        m.triangles.insert(m.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
      }
  return m;
}

/// A one-voxel-thick 3 x (2h+1) slab with h square holes: a closed surface of genus h.
TriangleMesh slab_with_holes(int holes) {
  std::set<std::tuple<int, int, int>> cells;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2 * holes + 1; ++j)
      if (!(i == 1 && j % 2 == 1)) cells.insert({i, j, 0});
  return voxel_surface(cells);
}

/// Outward-oriented tetrahedron with vertices offset by `first`.
void append_tetrahedron(TriangleMesh& m, double shift, std::uint32_t apex = kNone) {
  const auto base = static_cast<std::uint32_t>(m.vertex_count());
  std::uint32_t id[4];
  for (int k = 0; k < 4; ++k) {
    if (k == 0 && apex != kNone) {
      id[0] = apex;
      continue;
    }
    const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    id[k] = static_cast<std::uint32_t>(m.vertex_count());
    m.positions.insert(m.positions.end(), {p[k][0] + shift, p[k][1] + shift, p[k][2] + shift});
  }
  (void)base;
  m.triangles.insert(m.triangles.end(), {id[0], id[2], id[1], id[0], id[1], id[3], id[0], id[3], id[2], id[1], id[2], id[3]});
}

/// Möbius strip of n quads (each split in two): the last quad joins column n−1 to column 0
/// with top and bottom swapped.
TriangleMesh mobius(int n) {
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    for (const double w : {-0.3, 0.3}) {
      const double r = 1 + w * std::cos(a / 2);
      m.positions.insert(m.positions.end(), {r * std::cos(a), r * std::sin(a), w * std::sin(a / 2)});
    }
  }
  const auto top = [](int i) { return std::uint32_t(2 * i); };
  const auto bottom = [](int i) { return std::uint32_t(2 * i + 1); };
  for (int i = 0; i < n; ++i) {
    std::uint32_t q[4] = {top(i), bottom(i), bottom(i + 1), top(i + 1)};
    if (i == n - 1) q[2] = top(0), q[3] = bottom(0);
    m.triangles.insert(m.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  }
  return m;
}

void require_closed_genus(const MeshReport& r, std::int64_t genus) {
  REQUIRE(r.structure_error.empty());
  REQUIRE(r.is_manifold());
  REQUIRE(r.is_closed());
  REQUIRE(r.orientable);
  REQUIRE(r.consistently_oriented);
  REQUIRE(r.boundary_loops == 0);
  REQUIRE(r.connected_components == 1);
  REQUIRE(r.euler_characteristic == 2 - 2 * genus);
  REQUIRE(r.components.at(0).genus == genus);
  REQUIRE(r.components.at(0).closed);
  REQUIRE(first_problem_for_triangle_codec(r).empty());
}

/// Minimal JSON syntax check (objects, arrays, strings, numbers, literals).
class JsonChecker {
 public:
  explicit JsonChecker(const std::string& text) : s_(text) {}
  bool valid() {
    skip();
    if (!value()) return false;
    skip();
    return at_ == s_.size();
  }

 private:
  void skip() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
  }
  bool literal(const std::string& word) {
    if (s_.compare(at_, word.size(), word) != 0) return false;
    at_ += word.size();
    return true;
  }
  bool string() {
    if (s_[at_] != '"') return false;
    for (++at_; at_ < s_.size(); ++at_) {
      if (s_[at_] == '\\') ++at_;
      else if (s_[at_] == '"') return ++at_, true;
      else if (static_cast<unsigned char>(s_[at_]) < 0x20) return false;
    }
    return false;
  }
  bool number() {
    const std::size_t start = at_;
    if (s_[at_] == '-') ++at_;
    while (at_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[at_])) || std::string(".eE+-").find(s_[at_]) != std::string::npos)) ++at_;
    return at_ > start && std::isdigit(static_cast<unsigned char>(s_[at_ - 1]));
  }
  bool value() {
    skip();
    if (at_ >= s_.size()) return false;
    const char c = s_[at_];
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++at_;
      skip();
      if (s_[at_] == close) return ++at_, true;
      for (;;) {
        skip();
        if (c == '{') {
          if (!string()) return false;
          skip();
          if (s_[at_++] != ':') return false;
        }
        if (!value()) return false;
        skip();
        if (s_[at_] == ',') {
          ++at_;
          continue;
        }
        return s_[at_++] == close;
      }
    }
    if (c == '"') return string();
    if (c == 't') return literal("true");
    if (c == 'f') return literal("false");
    if (c == 'n') return literal("null");
    return number();
  }
  const std::string& s_;
  std::size_t at_ = 0;
};

}  // namespace

TEST_CASE("closed surfaces: icosahedron - bicone - torus - genus 2 and 3 voxel slabs", "[validate]") {
  const MeshReport ico = validate_mesh(test::icosahedron());
  require_closed_genus(ico, 0);
  REQUIRE(ico.vertices == 12);
  REQUIRE(ico.edges == 30);
  REQUIRE(ico.faces == 20);
  require_closed_genus(validate_mesh(test::bicone(7)), 0);
  const MeshReport torus = validate_mesh(test::torus());
  require_closed_genus(torus, 1);
  REQUIRE(torus.edges == 3 * 8 * 6);
  require_closed_genus(validate_mesh(slab_with_holes(1)), 1);
  require_closed_genus(validate_mesh(slab_with_holes(2)), 2);
  require_closed_genus(validate_mesh(slab_with_holes(3)), 3);
  const MeshReport cube = validate_mesh(test::cube_quads());
  REQUIRE(cube.euler_characteristic == 2);
  REQUIRE(cube.components.at(0).genus == 0);
  REQUIRE(cube.non_triangle_faces == 6);
  REQUIRE(first_problem_for_triangle_codec(cube) == "face 0 has 4 corners: triangles required (6 non-triangle faces)");
}

TEST_CASE("open surfaces: grid and disk have one boundary loop", "[validate]") {
  const MeshReport grid = validate_mesh(test::grid(5));
  REQUIRE(grid.is_manifold());
  REQUIRE_FALSE(grid.is_closed());
  REQUIRE(grid.boundary_edges == 16);
  REQUIRE(grid.boundary_loops == 1);
  REQUIRE(grid.euler_characteristic == 1);
  REQUIRE(grid.components.at(0).genus == 0);
  REQUIRE(grid.components.at(0).boundary_loops == 1);
  REQUIRE(grid.consistently_oriented);
  REQUIRE(first_problem_for_triangle_codec(grid).empty());

  // A grid with one interior face removed: an annulus, two loops, still genus 0.
  TriangleMesh annulus = test::grid(5);
  annulus.triangles.erase(annulus.triangles.begin() + 3 * 10, annulus.triangles.begin() + 3 * 11);
  const MeshReport a = validate_mesh(annulus);
  REQUIRE(a.boundary_loops == 2);
  REQUIRE(a.euler_characteristic == 0);
  REQUIRE(a.components.at(0).genus == 0);
}

TEST_CASE("two disjoint tetrahedra are two genus-0 components", "[validate]") {
  TriangleMesh m;
  append_tetrahedron(m, 0.0);
  append_tetrahedron(m, 5.0);
  const MeshReport r = validate_mesh(m);
  REQUIRE(r.connected_components == 2);
  REQUIRE(r.euler_characteristic == 4);
  REQUIRE(r.is_closed());
  REQUIRE(r.consistently_oriented);
  for (const ComponentReport& c : r.components) {
    REQUIRE(c.vertices == 4);
    REQUIRE(c.faces == 4);
    REQUIRE(c.edges == 6);
    REQUIRE(c.euler == 2);
    REQUIRE(c.genus == 0);
  }
  REQUIRE(r.components[0].first_face == 0);
  REQUIRE(r.components[1].first_face == 4);
}

TEST_CASE("three triangles on one edge: a non-manifold edge", "[validate]") {
  TriangleMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  m.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const MeshReport r = validate_mesh(m);
  REQUIRE(r.non_manifold_edges == 1);
  REQUIRE(r.non_manifold_vertices == 2);  // both ends see three separate fans
  REQUIRE(r.edges == 7);
  REQUIRE(r.boundary_edges == 6);
  REQUIRE_FALSE(r.is_manifold());
  REQUIRE(r.components.at(0).genus == -1);
  REQUIRE(first_problem_for_triangle_codec(r) == "1 non-manifold edge (first: edge 0-1, on more than two faces)");
}

TEST_CASE("two tetrahedra sharing one vertex: a pinched - non-manifold vertex", "[validate]") {
  TriangleMesh m;
  append_tetrahedron(m, 0.0);
  append_tetrahedron(m, -1.0, 0);  // second tetrahedron's first corner is vertex 0
  const MeshReport r = validate_mesh(m);
  REQUIRE(r.non_manifold_edges == 0);
  REQUIRE(r.non_manifold_vertices == 1);
  REQUIRE(r.connected_components == 1);
  REQUIRE(r.is_closed());
  REQUIRE(r.euler_characteristic == 7 - 12 + 8);
  REQUIRE(r.components.at(0).genus == -1);
  REQUIRE(first_problem_for_triangle_codec(r) == "1 non-manifold vertex (first: vertex 0, where separate fans of faces meet)");
}

TEST_CASE("a flipped face is orientable but not consistently oriented", "[validate]") {
  TriangleMesh m = test::icosahedron();
  std::swap(m.triangles[1], m.triangles[2]);
  const MeshReport r = validate_mesh(m);
  REQUIRE(r.is_manifold());
  REQUIRE(r.orientable);
  REQUIRE_FALSE(r.consistently_oriented);
  REQUIRE(r.inconsistent_edges == 3);
  REQUIRE(r.components.at(0).genus == 0);  // genus needs orientability, not the current orientation
  REQUIRE(first_problem_for_triangle_codec(r) ==
          "3 edges are traversed in the same direction by both faces: orientation is inconsistent (first: edge 0-5)");
}

TEST_CASE("a hub vertex of 100,000 faces: its half-edges sorted as any vertex's, one face turned found", "[validate]") {
  // A disk of n triangles (0, i, i + 1) around vertex 0, the smaller vertex of its 2n spokes'
  // half-edges: the edge pass sorts that one vertex's half-edges by a comparison sort (an
  // ordinary vertex's by insertion), which must group every spoke's two half-edges.
  constexpr std::uint32_t n = 100000;
  TriangleMesh m;
  m.positions = {0, 0, 0};
  for (std::uint32_t i = 0; i < n; ++i) {
    const double angle = 2 * std::acos(-1.0) * i / n;
    m.positions.insert(m.positions.end(), {std::cos(angle), std::sin(angle), 0});
  }
  for (std::uint32_t i = 1; i <= n; ++i) m.triangles.insert(m.triangles.end(), {0, i, i % n + 1});
  MeshReport r = validate_mesh(m);
  CHECK(r.is_manifold());
  CHECK(r.consistently_oriented);
  CHECK(r.edges == 2 * n);
  CHECK(r.boundary_edges == n);
  CHECK(r.boundary_loops == 1);
  CHECK(r.euler_characteristic == 1);
  // Face k turned: its two spokes (0, k + 1) and (0, k + 2) are run the same way by both faces.
  const std::uint32_t k = 54321;
  std::swap(m.triangles[3 * k + 1], m.triangles[3 * k + 2]);
  r = validate_mesh(m);
  CHECK(r.orientable);
  CHECK(r.inconsistent_edges == 2);
  CHECK(r.first_inconsistent_edge[0] == 0);
  CHECK(r.first_inconsistent_edge[1] == k + 1);
}

TEST_CASE("a Möbius strip is not orientable", "[validate]") {
  const MeshReport r = validate_mesh(mobius(8));
  REQUIRE(r.is_manifold());
  REQUIRE_FALSE(r.orientable);
  REQUIRE_FALSE(r.consistently_oriented);
  REQUIRE(r.boundary_loops == 1);  // the Möbius strip has a single boundary curve
  REQUIRE(r.euler_characteristic == 0);
  REQUIRE_FALSE(r.components.at(0).orientable);
  REQUIRE(r.components.at(0).genus == -1);
  REQUIRE(first_problem_for_triangle_codec(r) == "mesh is not orientable");
  // The untwisted band (a cylinder) of the same size is orientable with two loops.
  TriangleMesh band = mobius(8);
  // Last quad (t7, b7, t0, b0) = triangles {14,15,0, 14,0,1} becomes (t7, b7, b0, t0).
  band.triangles[band.triangles.size() - 4] = 1;
  band.triangles[band.triangles.size() - 2] = 1;
  band.triangles[band.triangles.size() - 1] = 0;
  const MeshReport cylinder = validate_mesh(band);
  REQUIRE(cylinder.orientable);
  REQUIRE(cylinder.consistently_oriented);
  REQUIRE(cylinder.boundary_loops == 2);
  REQUIRE(cylinder.components.at(0).genus == 0);
}

TEST_CASE("vertex defects: NaN - duplicates - isolated", "[validate]") {
  TriangleMesh nan = test::icosahedron();
  nan.positions[4] = std::numeric_limits<double>::quiet_NaN();
  nan.positions[9] = std::numeric_limits<double>::infinity();
  const MeshReport r = validate_mesh(nan);
  REQUIRE(r.non_finite_vertices == 2);
  REQUIRE(std::isfinite(r.bbox_diagonal));
  REQUIRE(first_problem_for_triangle_codec(r) == "2 vertices have non-finite coordinates (first: vertex 1)");

  TriangleMesh extra = test::icosahedron();
  extra.positions.insert(extra.positions.end(), {extra.positions[9], extra.positions[10], extra.positions[11]});
  extra.positions.insert(extra.positions.end(), {7, 7, 7});
  const MeshReport d = validate_mesh(extra);
  REQUIRE(d.duplicate_vertices == 1);
  REQUIRE(d.isolated_vertices == 2);
  REQUIRE(d.vertices == 14);
  REQUIRE(d.referenced_vertices == 12);
  REQUIRE(d.euler_characteristic == 2);
  REQUIRE(d.components.at(0).genus == 0);
  REQUIRE(first_problem_for_triangle_codec(d).empty());  // harmless for the codec
}

TEST_CASE("face defects: repeated index - zero area - out-of-range index", "[validate]") {
  TriangleMesh m = test::icosahedron();
  m.triangles.insert(m.triangles.end(), {0, 0, 1});
  const MeshReport degenerate = validate_mesh(m);
  REQUIRE(degenerate.degenerate_faces == 1);
  REQUIRE(degenerate.first_degenerate_face == 20);
  REQUIRE(degenerate.euler_characteristic == 2);  // unusable faces stay out of the topology
  REQUIRE(first_problem_for_triangle_codec(degenerate) == "1 degenerate face (repeated vertex; first: face 20)");

  TriangleMesh flat;
  flat.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
  flat.triangles = {0, 1, 2, 0, 1, 3};
  const MeshReport zero = validate_mesh(flat);
  REQUIRE(zero.zero_area_faces == 1);
  REQUIRE(zero.degenerate_faces == 0);

  TriangleMesh range = test::icosahedron();
  range.triangles[7] = 12;
  range.triangles[8] = kNone;
  const MeshReport bad = validate_mesh(range);
  REQUIRE(bad.invalid_index_faces == 1);
  REQUIRE(bad.invalid_indices == 2);
  REQUIRE(bad.first_invalid_index_face == 2);
  REQUIRE(bad.boundary_loops == 1);  // the face is left out, leaving a hole
  REQUIRE_THAT(first_problem_for_triangle_codec(bad), Catch::StartsWith("2 face corners reference vertices"));
}

TEST_CASE("empty and malformed arrays are reported - not trusted", "[validate]") {
  const MeshReport empty = validate_mesh(PolygonMesh{});
  REQUIRE(empty.vertices == 0);
  REQUIRE(empty.faces == 0);
  REQUIRE(empty.connected_components == 0);
  REQUIRE_FALSE(empty.is_closed());
  REQUIRE(first_problem_for_triangle_codec(empty) == "mesh is empty");
  REQUIRE(JsonChecker(to_json(empty)).valid());

  PolygonMesh points;
  points.positions = {0, 0, 0, 1, 1, 1};
  REQUIRE(first_problem_for_triangle_codec(validate_mesh(points)) == "mesh has no faces");
  REQUIRE(validate_mesh(points).isolated_vertices == 2);

  PolygonMesh broken = test::cube_quads();
  broken.face_offsets[3] = 100;
  REQUIRE_FALSE(validate_mesh(broken).structure_error.empty());
  broken = test::cube_quads();
  broken.face_offsets.clear();
  REQUIRE_FALSE(validate_mesh(broken).structure_error.empty());
  broken = test::cube_quads();
  broken.positions.pop_back();
  REQUIRE_THAT(first_problem_for_triangle_codec(validate_mesh(broken)), Catch::StartsWith("malformed mesh arrays"));
  TriangleMesh partial = test::icosahedron();
  partial.triangles.pop_back();
  REQUIRE_FALSE(validate_mesh(partial).structure_error.empty());

  // Random arrays: any combination must be reported without reading out of bounds.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 300; ++trial) {
    PolygonMesh g;
    const std::size_t vertices = rng() % 12;
    for (std::size_t i = 0; i < 3 * vertices; ++i) g.positions.push_back(double(rng() % 3));
    const std::size_t faces = rng() % 30;
    for (std::size_t f = 0; f < faces; ++f) {
      const std::size_t corners = rng() % 6;
      for (std::size_t c = 0; c < corners; ++c) g.face_indices.push_back(static_cast<std::uint32_t>(rng() % (vertices + 2)));
      g.face_offsets.push_back(static_cast<std::uint32_t>(g.face_indices.size()));
    }
    const MeshReport r = validate_mesh(g);
    REQUIRE(r.faces == faces);
    REQUIRE(r.euler_characteristic ==
            std::int64_t(r.referenced_vertices) - std::int64_t(r.edges) +
                std::int64_t(r.faces - r.degenerate_faces - r.invalid_index_faces));
    REQUIRE(JsonChecker(to_json(r)).valid());
    to_text(r);
  }
}

TEST_CASE("text and JSON reports", "[validate]") {
  const MeshReport r = validate_mesh(test::torus());
  const std::string text = to_text(r);
  REQUIRE_THAT(text, Catch::Contains("euler characteristic:    0"));
  REQUIRE_THAT(text, Catch::Contains("genus 1"));
  REQUIRE_THAT(text, Catch::Contains("triangle codec:          ok"));
  const std::string json = to_json(r);
  REQUIRE(JsonChecker(json).valid());
  REQUIRE_THAT(json, Catch::Contains("\"euler_characteristic\": 0,"));
  REQUIRE_THAT(json, Catch::Contains("\"genus\": 1"));
  REQUIRE_THAT(json, Catch::Contains("\"triangle_codec_problem\": null"));
  REQUIRE_FALSE(JsonChecker("{\"a\": 1,}").valid());

  MeshReport broken;
  broken.structure_error = "quote \" and newline \n";
  REQUIRE(JsonChecker(to_json(broken)).valid());
}

TEST_CASE("how_to_repair answers the problem first_problem_for_triangle_codec names, and nothing for a good mesh", "[validate]") {
  CHECK(how_to_repair(validate_mesh(test::icosahedron())).empty());
  MeshReport r = validate_mesh(test::icosahedron());
  r.consistently_oriented = false;
  CHECK_THAT(how_to_repair(r), Catch::Contains("every edge is run both ways"));
  r.orientable = false;  // comes first, as in first_problem_for_triangle_codec
  CHECK_THAT(how_to_repair(r), Catch::Contains("one-sided"));
  r.non_manifold_vertices = 1;
  CHECK_THAT(how_to_repair(r), Catch::Contains("its own copy of the vertex"));
  r.non_manifold_edges = 1;
  CHECK_THAT(how_to_repair(r), Catch::Contains("at most two faces on each edge"));
  r.faces = 0;
  CHECK_THAT(how_to_repair(r), Catch::Contains("point cloud"));
  r.vertices = 0;
  CHECK(how_to_repair(r).empty());  // an empty mesh: nothing to say beyond "mesh is empty"
}
