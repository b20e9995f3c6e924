// Consistent face orientation (orient.h).
#include <catch2/catch.hpp>
#include <cmath>
#include <utility>
#include <vector>

#include "meshlift/orient.h"
#include "meshlift/validate.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// Six times the signed volume of a closed triangle mesh.
double volume6(const TriangleMesh& m) {
  double v = 0;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const double* a = &m.positions[3 * m.triangles[3 * f]];
    const double* b = &m.positions[3 * m.triangles[3 * f + 1]];
    const double* c = &m.positions[3 * m.triangles[3 * f + 2]];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v;
}

void turn_over(TriangleMesh& m, std::size_t f) { std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]); }

bool consistent(const TriangleMesh& m) {
  const MeshReport r = validate_mesh(m);
  for (const ComponentReport& c : r.components)
    if (!c.orientable) return false;
  return r.inconsistent_edges == 0;
}

}  // namespace

TEST_CASE("orient: a closed mesh with faces written in either turn faces outwards again", "[orient]") {
  const TriangleMesh sphere = test::icosphere(2);  // 320 faces, outwards
  REQUIRE(volume6(sphere) > 0);
  // A third of the faces turned over: the walk from face 0 puts them back exactly.
  TriangleMesh some = sphere;
  for (std::size_t f = 0; f < some.face_count(); f += 3) turn_over(some, f);
  REQUIRE_FALSE(consistent(some));
  const Orientation a = orient_consistently(some);
  CHECK(a.flipped_faces == (some.face_count() + 2) / 3);
  CHECK(a.fixed_components == 1);
  CHECK(a.unorientable_components == 0);
  CHECK(a.mesh.triangles == sphere.triangles);
  // Two thirds turned over, face 0 among them: the walk starts inwards, the volume turns it out.
  TriangleMesh most = sphere;
  for (std::size_t f = 0; f < most.face_count(); ++f)
    if (f % 3 != 1) turn_over(most, f);
  const Orientation b = orient_consistently(most);
  CHECK(b.mesh.triangles == sphere.triangles);
  CHECK(volume6(b.mesh) > 0);
  // Consistent but facing inwards: left as it is.
  TriangleMesh inwards = sphere;
  for (std::size_t f = 0; f < inwards.face_count(); ++f) turn_over(inwards, f);
  const Orientation c = orient_consistently(inwards);
  CHECK(c.flipped_faces == 0);
  CHECK(c.fixed_components == 0);
  CHECK(c.mesh.triangles == inwards.triangles);
}

TEST_CASE("orient: an open mesh keeps its majority's turn, a Moebius strip and a fin are left alone", "[orient]") {
  const TriangleMesh grid = test::grid(6);
  TriangleMesh g = grid;
  turn_over(g, 0);
  turn_over(g, 7);
  const Orientation o = orient_consistently(g);
  CHECK(o.flipped_faces == 2);
  CHECK(o.mesh.triangles == grid.triangles);
  CHECK(consistent(o.mesh));

  // A strip of 8 quads around a loop with a half twist: no orientation exists.
  TriangleMesh moebius;
  const int n = 8;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n, twist = M_PI * i / n;
    for (const double s : {-0.3, 0.3}) {
      const double r = 1 + s * std::cos(twist);
      moebius.positions.insert(moebius.positions.end(), {r * std::cos(angle), r * std::sin(angle), s * std::sin(twist)});
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = 2 * i, b = 2 * i + 1;
    // The last quad joins the first with its sides swapped: the half twist.
    const std::uint32_t c = i + 1 < n ? 2 * i + 2 : 1, d = i + 1 < n ? 2 * i + 3 : 0;
    moebius.triangles.insert(moebius.triangles.end(), {a, c, b, b, c, d});
  }
  const Orientation m = orient_consistently(moebius);
  CHECK(m.unorientable_components == 1);
  CHECK(m.flipped_faces == 0);
  CHECK(m.mesh.triangles == moebius.triangles);

  // Three faces on one edge: no orientation is defined there; each face is a component of its own
  // (components join through edges of two faces), and the mesh comes back as it was.
  TriangleMesh fin;
  fin.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  fin.triangles = {0, 1, 2, 0, 1, 3, 1, 0, 4};
  const Orientation t = orient_consistently(fin);
  CHECK(t.unorientable_components == 3);
  CHECK(t.mesh.triangles == fin.triangles);
}
