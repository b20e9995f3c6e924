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
#include "meshlift/mesh_io.h"
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

/// The cylinder of radius 1 between z = 0 and 1 with flat caps, `around` vertices round: its
/// rims are 90-degree creases, two closed lines of `around` edges turning by 360 / around degrees
/// at each vertex.
TriangleMesh capped_cylinder(std::uint32_t around) {
  TriangleMesh m;
  auto ring = [&](double r, double z) {
    const auto first = static_cast<std::uint32_t>(m.vertex_count());
    for (std::uint32_t i = 0; i < around; ++i) {
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

TEST_CASE("Feature lines: lines between rough sides and lines that zigzag are left out", "[remesh][features]") {
  // The cube's faces made rough (their inner vertices moved in and out by up to 0.12, a third of
  // the grid step): its edges still turn by about 90 degrees, but their sides by ~20.
  TriangleMesh rough = gridded_cube(6);
  std::uint64_t state = 7;
  for (std::size_t v = 0; v < rough.vertex_count(); ++v) {
    int at_side = 0, axis = 0;
    for (int c = 0; c < 3; ++c)
      if (std::abs(std::abs(rough.positions[3 * v + c]) - 1) < 1e-12) ++at_side, axis = c;
    if (at_side != 1) continue;
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    rough.positions[3 * v + axis] *= 1 + 0.12 * (static_cast<double>(state >> 11) * 0x1p-53 * 2 - 1);
  }
  // (Near the corners the noise breaks a few chains below 5 edges: 10 of the 12 are left.)
  CHECK(find_feature_lines(rough, 60, 5).edge_count() == 60);
  CHECK(find_feature_lines(rough, 60, 5, 180, 30).edge_count() == 60);  // sides at 18-29 degrees (median)
  CHECK(find_feature_lines(rough, 60, 5, 180, 10).empty());
  CHECK(find_feature_lines(gridded_cube(6), 60, 5, 180, 10).edge_count() == 72);
  // A line ends where it turns by more than max_turn: the rims of an octagonal prism turn by 45
  // degrees at each vertex (its sides meet at 45: no lines), so with a limit of 30 they break
  // into one-edge chains, too short; with 50 they are two loops of 8.
  const TriangleMesh prism = capped_cylinder(8);
  CHECK(find_feature_lines(prism, 60, 5, 50, 180).edge_count() == 16);
  CHECK(find_feature_lines(prism, 60, 5, 30, 180).empty());
  CHECK(find_feature_lines(prism, 60, 1, 30, 180).edge_count() == 16);
  CHECK(find_feature_lines(prism, 60, 1, 30, 180).is_corner(0));  // every rim vertex is a kink
}

TEST_CASE("Feature lines: the decimation keeps a line as a chain of base edges", "[remesh][features][decimate]") {
  // A flat grid (no quadric resists a collapse across the line) with a line along its middle
  // row; decimated to 12 vertices, the line's surviving vertices must still be joined by edges.
  const int n = 17;
  const TriangleMesh grid = test::grid(n);
  std::vector<std::array<std::uint32_t, 2>> row_edges;
  for (int j = 0; j + 1 < n; ++j) row_edges.push_back({static_cast<std::uint32_t>(n / 2 * n + j), static_cast<std::uint32_t>(n / 2 * n + j + 1)});
  const FeatureLines lines = FeatureLines::from_edges(grid.vertex_count(), row_edges);
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

TEST_CASE("Feature lines: random lines that cross survive a deep decimation as chains of base edges", "[remesh][features][decimate]") {
  // Random walks over a sphere's edges make lines that meet and cross (corners of 3 or 4) and
  // close loops; decimated to 60 of 2,562 vertices, every line edge must lie in exactly one base
  // feature edge's path, and every base feature edge must be an edge of the base.
  const TriangleMesh sphere = test::icosphere(4);
  std::vector<std::set<std::uint32_t>> adjacent(sphere.vertex_count());
  for (std::size_t f = 0; f < sphere.face_count(); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = sphere.triangles[3 * f + i], b = sphere.triangles[3 * f + (i + 1) % 3];
      adjacent[a].insert(b), adjacent[b].insert(a);
    }
  std::set<std::pair<std::uint32_t, std::uint32_t>> line_edges;
  std::uint64_t state = 11;
  auto next = [&] { return state = state * 6364136223846793005ULL + 1442695040888963407ULL, static_cast<std::uint32_t>(state >> 33); };
  for (int walk = 0; walk < 12; ++walk) {
    std::uint32_t at = next() % sphere.vertex_count();
    for (int step = 0; step < 25; ++step) {
      const std::vector<std::uint32_t> options(adjacent[at].begin(), adjacent[at].end());
      const std::uint32_t to = options[next() % options.size()];
      line_edges.insert(std::minmax(at, to));
      at = to;
    }
  }
  std::vector<std::array<std::uint32_t, 2>> edge_list;
  for (const auto& [a, b] : line_edges) edge_list.push_back({a, b});
  const FeatureLines lines = FeatureLines::from_edges(sphere.vertex_count(), edge_list);

  DecimateOptions options;
  options.target_vertices = 60;
  options.feature_lines = &lines;
  const DecimateResult decimated = decimate(sphere, options);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> covered;
  for (const BaseFeatureEdge& edge : base_feature_edges(lines, decimated.original_vertex)) {
    CHECK(is_base_edge(decimated.base, edge.a, edge.b));
    for (std::size_t i = 0; i + 1 < edge.path.size(); ++i) {
      REQUIRE(line_edges.count(std::minmax(edge.path[i], edge.path[i + 1])) == 1);
      ++covered[std::minmax(edge.path[i], edge.path[i + 1])];
    }
  }
  CHECK(covered.size() == line_edges.size());
  for (const auto& [edge, count] : covered) CHECK(count == 1);
  INFO("base vertices " << decimated.base.vertex_count());
  CHECK(decimated.base.vertex_count() < 200);
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
  const std::uint32_t around = 40;
  const TriangleMesh m = capped_cylinder(around);
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
  // midpoints and the corners in distance from the axis, within the rounding of a remesh's
  // positions to 32-bit floats (remesh.h: a float moves a coordinate below 1 by at most 2^-24).
  auto on_rims = [&](const std::vector<double>& x) {
    std::size_t count = 0;
    for (std::size_t v = 0; v < x.size() / 3; ++v) {
      const double r = std::hypot(x[3 * v], x[3 * v + 1]), z = x[3 * v + 2];
      count += (z == 0 || z == 1) && r >= std::cos(std::numbers::pi / around) - 1e-7 && r <= 1 + 1e-7;
    }
    return count;
  };
  CHECK(with.feature_vertices > 0);
  CHECK(on_rims(with.mesh.positions) >= with.feature_vertices);
  const double with_db = surface_distance(m, with.mesh.finest()).psnr_db();
  const double without_db = surface_distance(m, without.mesh.finest()).psnr_db();
  INFO("PSNR with feature lines " << with_db << " dB, without " << without_db << " dB");
  CHECK(with_db > without_db + 10);
  // The second level placed on the finished remesh of one over the same base
  // (RemeshOptions::level_by_level_from): its vertices on the base's feature edges are placed on
  // the rims too, as many as placed from the base, and held there.
  options.feature_angle = 60;
  options.base_vertices = with.base_vertices;
  options.level_by_level_from = 2;
  const RemeshResult deep = remesh(m, options);
  CHECK(deep.direct_levels == 1);
  CHECK(deep.feature_edges == 2 * around);
  CHECK(deep.feature_vertices == with.feature_vertices);
  CHECK(deep.flipped_triangles + deep.degenerate_triangles == 0);
  CHECK(on_rims(deep.mesh.positions) >= deep.feature_vertices);
  CHECK(surface_distance(m, deep.mesh.finest()).psnr_db() > without_db + 10);
}

TEST_CASE("Feature lines with the automatic density: fandisk follows its creases at 1x, turbine goes on without", "[corpus][remesh][features][pipeline][heavy]") {
  // Fandisk's 2x remesh with its lines qualifies (81.9 dB; 76.0 without them), and far within
  // the threshold, and so does its 1.5x one (80.0 dB), so its 1x one is kept (75.3 dB, no fold). Turbine's lines fold its 2x remesh, so it is remeshed as with no lines at all.
  const TriangleMesh fandisk = to_triangle_mesh(read_mesh(test::corpus_mesh_path("fandisk")));
  const RemeshResult lined = remesh(fandisk, RemeshOptions{});
  CHECK(lined.feature_edges > 600);
  CHECK(lined.feature_vertices > 0);
  CHECK(lined.density == 1);
  CHECK(lined.flipped_triangles + lined.degenerate_triangles == 0);
  CHECK(surface_distance(fandisk, lined.mesh.finest()).psnr_db() >= 75);

  const TriangleMesh turbine = to_triangle_mesh(read_mesh(test::corpus_mesh_path("turbine")));
  const RemeshResult fallback = remesh(turbine, RemeshOptions{});
  CHECK(fallback.feature_vertices == 0);
  RemeshOptions no_lines;
  no_lines.feature_angle = 0;
  CHECK(remesh(turbine, no_lines).mesh.positions == fallback.mesh.positions);
}
