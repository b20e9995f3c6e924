// Feature lines: found on a cube's edges and nowhere on a sphere, kept by the decimation as
// chains of base edges, and followed exactly by the remesh (features.h).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <utility>

#include "meshlift/decimate.h"
#include "meshlift/features.h"
#include "meshlift/metric.h"
#include "meshlift/remesh.h"
#include "meshlift/validate.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// The cube [-1, 1]^3, each face an n x n grid of squares split along a diagonal, outward facing.
TriangleMesh gridded_cube(int n) {
  TriangleMesh m;
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vertex = [&](std::array<int, 3> p) {
    const auto [it, added] = index.try_emplace(p, static_cast<std::uint32_t>(m.vertex_count()));
    if (added)
      for (int c : p) m.positions.push_back(2.0 * c / n - 1);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {0, n}) {
      // u x v is +axis for (axis + 1, axis + 2); swapped on the low side so faces point outward.
      const int u = side == n ? (axis + 1) % 3 : (axis + 2) % 3, v = side == n ? (axis + 2) % 3 : (axis + 1) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> p{};
            p[axis] = side, p[u] = i + di, p[v] = j + dj;
            return vertex(p);
          };
          const std::uint32_t a = corner(0, 0), b = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
          m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
        }
    }
  return m;
}

bool is_base_edge(const TriangleMesh& base, std::uint32_t a, std::uint32_t b) {
  for (std::size_t f = 0; f < base.face_count(); ++f)
    for (int i = 0; i < 3; ++i)
      if (std::minmax(base.triangles[3 * f + i], base.triangles[3 * f + (i + 1) % 3]) == std::minmax(a, b)) return true;
  return false;
}

}  // namespace

TEST_CASE("Feature lines: a cube's twelve edges, nothing on a sphere, short chains left out", "[remesh][features]") {
  const TriangleMesh cube = gridded_cube(6);
  const FeatureLines lines = find_feature_lines(cube, 60, 5);
  CHECK(lines.edge_count() == 12 * 6);
  std::size_t corners = 0, inside = 0;
  for (std::uint32_t v = 0; v < cube.vertex_count(); ++v) {
    corners += lines.is_corner(v);
    inside += lines.degree(v) == 2;
    if (lines.is_corner(v)) CHECK(lines.degree(v) == 3);
  }
  CHECK(corners == 8);
  CHECK(inside == 12 * 5);
  // Each cube edge is a chain of 6 feature edges: 7 is too short a minimum, 6 is enough.
  CHECK(find_feature_lines(cube, 60, 7).empty());
  CHECK(find_feature_lines(cube, 60, 6).edge_count() == 72);
  // The cube's edges turn by 90 degrees.
  CHECK(find_feature_lines(cube, 89, 1).edge_count() == 72);
  CHECK(find_feature_lines(cube, 91, 1).empty());
  CHECK(find_feature_lines(cube, 0, 1).empty());  // off
  CHECK(find_feature_lines(test::icosphere(3), 20, 1).empty());
}

TEST_CASE("Feature lines: the decimation keeps a line as a chain of base edges", "[remesh][features][decimate]") {
  // A flat grid (no quadric resists a collapse across the line) with a line along its middle
  // row; decimated to 12 vertices, the line's surviving vertices must still be joined by edges.
  const int n = 17;
  const TriangleMesh grid = test::grid(n);
  FeatureLines lines;
  lines.offsets.assign(grid.vertex_count() + 1, 0);
  const int row = n / 2;
  for (std::uint32_t v = 0; v < grid.vertex_count(); ++v) {
    const int i = static_cast<int>(v) / n, j = static_cast<int>(v) % n;
    lines.offsets[v + 1] = lines.offsets[v];
    if (i != row) continue;
    if (j > 0) lines.neighbours.push_back(v - 1), ++lines.offsets[v + 1];
    if (j + 1 < n) lines.neighbours.push_back(v + 1), ++lines.offsets[v + 1];
  }
  DecimateOptions options;
  options.target_vertices = 12;
  options.feature_lines = &lines;
  const DecimateResult decimated = decimate(grid, options);
  const std::vector<BaseFeatureEdge> edges = base_feature_edges(lines, decimated.original_vertex);
  REQUIRE(!edges.empty());
  std::size_t covered = 0;
  for (const BaseFeatureEdge& edge : edges) {
    CHECK(is_base_edge(decimated.base, edge.a, edge.b));
    CHECK(edge.path.front() == decimated.original_vertex[edge.a]);
    CHECK(edge.path.back() == decimated.original_vertex[edge.b]);
    covered += edge.path.size() - 1;
  }
  CHECK(covered == static_cast<std::size_t>(n - 1));  // the whole row, each input edge once
}

TEST_CASE("Feature lines: the remesh of a cube follows its edges and is exact", "[remesh][features][pipeline]") {
  const TriangleMesh cube = gridded_cube(6);
  RemeshOptions options;
  options.levels = 2;
  options.density = 4;
  options.recognize = false;
  options.feature_angle = 60;
  const RemeshResult remeshed = remesh(cube, options);
  CHECK(remeshed.feature_edges == 72);
  CHECK(remeshed.flipped_triangles + remeshed.degenerate_triangles == 0);
  // Every vertex on a feature line lies on a cube edge (two coordinates at +-1), and so do no
  // others: the faces between the lines lie in the cube's faces.
  const std::vector<double>& x = remeshed.mesh.positions;
  std::size_t on_edges = 0;
  for (std::size_t v = 0; v < x.size() / 3; ++v) {
    int at_side = 0;
    for (int c = 0; c < 3; ++c) at_side += std::abs(std::abs(x[3 * v + c]) - 1) < 1e-12;
    on_edges += at_side >= 2;
  }
  CHECK(remeshed.feature_vertices > 0);
  CHECK(on_edges == remeshed.feature_vertices);
  CHECK(surface_distance(cube, remeshed.mesh.finest()).psnr_db() > 200);
}

TEST_CASE("Feature lines: a capped cylinder's rims are followed, far closer than without", "[remesh][features][pipeline]") {
  // Radius 1, height 1, 40 vertices round; the rims (90-degree creases) are two loops of 40 edges
  // that turn by 9 degrees at each vertex.
  const int around = 40;
  TriangleMesh m;
  auto ring = [&](double r, double z) {
    const auto first = static_cast<std::uint32_t>(m.vertex_count());
    for (int i = 0; i < around; ++i) {
      const double a = 2 * std::numbers::pi * i / around;
      m.positions.insert(m.positions.end(), {r * std::cos(a), r * std::sin(a), z});
    }
    return first;
  };
  // Quads between rings a and b (b one step outward or upward of a), split along a diagonal.
  auto band = [&](std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t i = 0; i < around; ++i) {
      const std::uint32_t j = (i + 1) % around;
      m.triangles.insert(m.triangles.end(), {a + i, a + j, b + j, a + i, b + j, b + i});
    }
  };
  std::vector<std::uint32_t> side;
  for (int k = 0; k <= 4; ++k) side.push_back(ring(1, k / 4.0));
  for (int k = 0; k < 4; ++k) band(side[k], side[k + 1]);
  for (const double z : {0.0, 1.0}) {
    const std::uint32_t inner = ring(1.0 / 3, z), middle = ring(2.0 / 3, z), rim = z == 0 ? side.front() : side.back();
    const auto centre = static_cast<std::uint32_t>(m.vertex_count());
    m.positions.insert(m.positions.end(), {0, 0, z});
    // The top faces up (+z), the bottom down: a band from ring a out to ring b faces down.
    auto cap_band = [&](std::uint32_t a, std::uint32_t b) { z == 0 ? band(a, b) : band(b, a); };
    cap_band(inner, middle);
    cap_band(middle, rim);
    for (std::uint32_t i = 0; i < around; ++i) {
      const std::uint32_t j = (i + 1) % around;
      if (z == 0) m.triangles.insert(m.triangles.end(), {centre, inner + j, inner + i});
      else m.triangles.insert(m.triangles.end(), {centre, inner + i, inner + j});
    }
  }
  REQUIRE(first_problem_for_triangle_codec(validate_mesh(m)).empty());
  RemeshOptions options;
  options.levels = 2;
  options.density = 2;
  options.feature_angle = 60;
  const RemeshResult with = remesh(m, options);
  options.feature_angle = 0;
  const RemeshResult without = remesh(m, options);
  CHECK(with.feature_edges == 2 * around);
  CHECK(with.flipped_triangles + with.degenerate_triangles == 0);
  // The vertices on the lines lie on the rims' polygons: z = 0 or 1, between the chords'
  // midpoints and the corners in distance from the axis.
  const std::vector<double>& x = with.mesh.positions;
  std::size_t on_rims = 0;
  for (std::size_t v = 0; v < x.size() / 3; ++v) {
    const double r = std::hypot(x[3 * v], x[3 * v + 1]), z = x[3 * v + 2];
    on_rims += (z == 0 || z == 1) && r >= std::cos(std::numbers::pi / around) - 1e-12 && r <= 1 + 1e-12;
  }
  CHECK(with.feature_vertices > 0);
  CHECK(on_rims >= with.feature_vertices);
  const double with_db = surface_distance(m, with.mesh.finest()).psnr_db();
  const double without_db = surface_distance(m, without.mesh.finest()).psnr_db();
  INFO("PSNR with feature lines " << with_db << " dB, without " << without_db << " dB");
  CHECK(with_db > without_db + 10);
}
