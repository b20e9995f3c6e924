// Polygon faces split into triangles (triangulate.h).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "meshlift/triangulate.h"
#include "meshlift/validate.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// One face in the z = 0 plane from (x, y) corners.
PolygonMesh planar_face(const std::vector<std::pair<double, double>>& corners) {
  PolygonMesh m;
  for (const auto& [x, y] : corners) m.positions.insert(m.positions.end(), {x, y, 0});
  for (std::uint32_t i = 0; i < corners.size(); ++i) m.face_indices.push_back(i);
  m.face_offsets.push_back(static_cast<std::uint32_t>(corners.size()));
  return m;
}

/// Signed area along +z of every triangle of a planar result.
std::vector<double> signed_areas(const TriangleMesh& m) {
  std::vector<double> areas;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const double* a = &m.positions[3 * m.triangles[3 * f]];
    const double* b = &m.positions[3 * m.triangles[3 * f + 1]];
    const double* c = &m.positions[3 * m.triangles[3 * f + 2]];
    areas.push_back(0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])));
  }
  return areas;
}

/// Every triangle turns the face's way and together they cover exactly its area (no overlap,
/// nothing outside: with all areas positive, a triangle outside would add to the sum).
void check_covers(const Triangulation& t, double area) {
  const std::vector<double> areas = signed_areas(t.mesh);
  double sum = 0;
  for (const double a : areas) {
    CHECK(a > 0);
    sum += a;
  }
  CHECK(sum == Approx(area).epsilon(1e-12));
}

}  // namespace

TEST_CASE("triangulate: triangles pass through, other faces become n - 2 triangles turning their way", "[triangulate]") {
  const PolygonMesh cube = test::cube_quads();
  const Triangulation t = triangulate(cube);
  CHECK(t.quads == 6);
  CHECK(t.polygons == 0);
  CHECK(t.fans == 0);
  CHECK(t.split_triangles == 12);
  REQUIRE(t.mesh.face_count() == 12);
  CHECK(t.mesh.positions == cube.positions);
  // Face by face, in the faces' order: triangles 2f and 2f + 1 hold quad f's corners.
  for (std::size_t f = 0; f < 6; ++f)
    for (std::size_t i = 0; i < 6; ++i) {
      const auto begin = cube.face_indices.begin() + cube.face_offsets[f], end = cube.face_indices.begin() + cube.face_offsets[f + 1];
      CHECK(std::find(begin, end, t.mesh.triangles[6 * f + i]) != end);
    }
  // A closed, consistently oriented triangle mesh: the quads' orientation is kept.
  CHECK(first_problem_for_triangle_codec(validate_mesh(t.mesh)).empty());

  const PolygonMesh pyramid = test::pentagonal_pyramid();
  const Triangulation p = triangulate(pyramid);
  CHECK(p.polygons == 1);
  CHECK(p.mesh.face_count() == 5 + 3);
  CHECK(first_problem_for_triangle_codec(validate_mesh(p.mesh)).empty());

  // Triangles as they are, faces of fewer than 3 corners left out.
  PolygonMesh mixed = planar_face({{0, 0}, {1, 0}, {0, 1}});
  mixed.face_indices.insert(mixed.face_indices.end(), {0, 1});
  mixed.face_offsets.push_back(5);
  const Triangulation m = triangulate(mixed);
  CHECK(m.mesh.triangles == std::vector<std::uint32_t>{0, 1, 2});
  CHECK(m.dropped == 1);
  // A face naming a vertex that does not exist.
  mixed.face_indices.back() = 7;
  CHECK_THROWS_AS(triangulate(mixed), MeshError);
}

TEST_CASE("triangulate: a quad is split along the diagonal that gives the better-shaped pair", "[triangulate]") {
  // A rhombus 4 wide and 2 high: the short diagonal gives angles of 53-63 degrees, the long one
  // a 27-degree angle.
  const Triangulation t = triangulate(planar_face({{-2, 0}, {0, -1}, {2, 0}, {0, 1}}));
  REQUIRE(t.mesh.face_count() == 2);
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t f = 0; f < 2; ++f)
    for (int i = 0; i < 3; ++i) edges.insert(std::minmax(t.mesh.triangles[3 * f + i], t.mesh.triangles[3 * f + (i + 1) % 3]));
  CHECK(edges.count({1, 3}) == 1);  // (0, -1) to (0, 1)
  CHECK(edges.count({0, 2}) == 0);
  check_covers(t, 4);
}

TEST_CASE("triangulate: non-convex faces are clipped inside, where a fan would fold", "[triangulate]") {
  // An L-shaped hexagon of area 3 listed from a corner that does not see the whole face: a fan
  // from it would turn a triangle over.
  const Triangulation l = triangulate(planar_face({{2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}}));
  CHECK(l.fans == 0);
  REQUIRE(l.mesh.face_count() == 4);
  check_covers(l, 3);
  // The same face a billion units from the origin: the same triangles (the normal is summed about
  // a corner, not the origin, where products of 1e9-sized coordinates lose the face's area).
  PolygonMesh far = planar_face({{2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}});
  for (std::size_t i = 0; i < far.positions.size(); i += 3) far.positions[i] += 1e9, far.positions[i + 1] += 1e9;
  const Triangulation f = triangulate(far);
  CHECK(f.fans == 0);
  CHECK(f.mesh.triangles == l.mesh.triangles);
  // A five-pointed star (10 corners, 5 of them reflex).
  std::vector<std::pair<double, double>> star;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 == 0 ? 1.0 : 0.4, angle = M_PI / 2 + 2 * M_PI * i / 10;
    star.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  double star_area = 0;
  for (std::size_t i = 0; i < star.size(); ++i) {
    const auto& [x0, y0] = star[i];
    const auto& [x1, y1] = star[(i + 1) % star.size()];
    star_area += 0.5 * (x0 * y1 - x1 * y0);
  }
  const Triangulation s = triangulate(planar_face(star));
  CHECK(s.fans == 0);
  CHECK(s.mesh.face_count() == 8);
  check_covers(s, star_area);
}

TEST_CASE("triangulate: faces with no ear, and very large faces, become fans and are counted", "[triangulate]") {
  // A bow tie: its two halves cancel, no plane to clip in.
  const Triangulation bow = triangulate(planar_face({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));
  CHECK(bow.fans == 1);
  CHECK(bow.mesh.face_count() == 2);
  // 100 corners on a circle: a fan, exact for a convex face, not counted.
  std::vector<std::pair<double, double>> circle, wavy;
  for (int i = 0; i < 100; ++i) {
    const double angle = 2 * M_PI * i / 100;
    circle.emplace_back(std::cos(angle), std::sin(angle));
    const double r = i % 2 == 0 ? 1.0 : 0.9;
    wavy.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  const Triangulation c = triangulate(planar_face(circle));
  CHECK(c.fans == 0);
  CHECK(c.mesh.face_count() == 98);
  check_covers(c, 50 * std::sin(2 * M_PI / 100));
  const Triangulation w = triangulate(planar_face(wavy));
  CHECK(w.fans == 1);
  CHECK(w.mesh.face_count() == 98);
}

TEST_CASE("triangulate: corners repeated in a row are merged, a face that comes back to a corner is cut there",
          "[triangulate]") {
  // A triangle written as a quad, as some exporters do, at the end and across the wrap: one
  // triangle, not one and a degenerate one (which the validation would refuse).
  for (const std::vector<std::uint32_t>& face : {std::vector<std::uint32_t>{0, 1, 2, 2}, {0, 1, 2, 0}, {0, 0, 1, 2}}) {
    PolygonMesh m = planar_face({{0, 0}, {1, 0}, {0, 1}});
    m.face_indices = face;
    m.face_offsets = {0, 4};
    const Triangulation t = triangulate(m);
    CHECK(t.quads == 1);
    CHECK(t.repeated_corners == 1);
    CHECK(t.pinched == 0);
    CHECK(t.dropped == 0);
    REQUIRE(t.mesh.face_count() == 1);
    check_covers(t, 0.5);
    CHECK(validate_mesh(t.mesh).degenerate_faces == 0);
  }
  // A pentagon with a repeated corner is the square it draws.
  {
    PolygonMesh m = planar_face({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    m.face_indices = {0, 1, 1, 2, 3};
    m.face_offsets = {0, 5};
    const Triangulation t = triangulate(m);
    CHECK(t.polygons == 1);
    CHECK(t.repeated_corners == 1);
    REQUIRE(t.mesh.face_count() == 2);
    check_covers(t, 1.0);
  }
  // Two distinct corners: no area, left out.
  {
    PolygonMesh m = planar_face({{0, 0}, {1, 0}});
    m.face_indices = {0, 0, 1, 1};
    m.face_offsets = {0, 4};
    const Triangulation t = triangulate(m);
    CHECK(t.dropped == 1);
    CHECK(t.mesh.face_count() == 0);
  }
  // Pinched like an 8 at corner 0: the loops 0 1 2 and 0 3 4, each its own triangle.
  {
    PolygonMesh m = planar_face({{0, 0}, {1, 0}, {1, 1}, {-1, 0}, {-1, -1}});
    m.face_indices = {0, 1, 2, 0, 3, 4};
    m.face_offsets = {0, 6};
    const Triangulation t = triangulate(m);
    CHECK(t.polygons == 1);
    CHECK(t.pinched == 1);
    CHECK(t.repeated_corners == 0);
    REQUIRE(t.mesh.face_count() == 2);
    std::vector<std::vector<std::uint32_t>> triangles;
    for (std::size_t f = 0; f < 2; ++f) {
      std::vector<std::uint32_t> c(t.mesh.triangles.begin() + 3 * f, t.mesh.triangles.begin() + 3 * f + 3);
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      triangles.push_back(c);
    }
    std::sort(triangles.begin(), triangles.end());
    CHECK(triangles == std::vector<std::vector<std::uint32_t>>{{0, 1, 2}, {0, 3, 4}});
    check_covers(t, 0.5 + 0.5);
  }
}
