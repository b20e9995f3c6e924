// Placing a refined base on the input surface (surface_fit.h): the normal-line placement.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "../../codec/local_frames.h"
#include "meshlift/closest_point.h"
#include "meshlift/decimate.h"
#include "meshlift/lifting.h"
#include "meshlift/mesh_io.h"
#include "meshlift/metric.h"
#include "meshlift/surface_fit.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// How many level-1 vertices of `mesh` lie on the line through their butterfly prediction along
/// their frame normal (tangential part of the detail below 1e-5 of the detail's length: the ray
/// hits are computed in single precision), and how many level-1 vertices there are.
std::pair<std::size_t, std::size_t> on_normal_lines(const SemiRegularMesh& mesh) {
  const SemiRegularHierarchy& h = mesh.hierarchy;
  std::vector<double> predicted(mesh.positions.begin(), mesh.positions.begin() + 3 * std::ptrdiff_t{h.vertex_count(1)});
  std::fill(predicted.begin() + 3 * std::ptrdiff_t{h.vertex_count(0)}, predicted.end(), 0.0);
  WaveletTransform(h, {Scheme::butterfly}).synthesize(predicted, 3, 1, 0);
  const std::vector<std::array<double, 3>> normal = edge_frame_normals(h.topology(0), mesh.positions);
  std::size_t on_line = 0;
  for (std::uint32_t e = 0; e < normal.size(); ++e) {
    const std::uint32_t v = h.odd_vertex(0, e);
    double d[3], along = 0, length2 = 0;
    for (int c = 0; c < 3; ++c) d[c] = mesh.positions[3 * v + c] - predicted[3 * v + c];
    for (int c = 0; c < 3; ++c) along += d[c] * normal[e][c], length2 += d[c] * d[c];
    const double tangential2 = length2 - along * along;
    if (tangential2 <= 1e-10 * length2) ++on_line;
  }
  return {on_line, normal.size()};
}

/// A base decimated from `input` to `base_vertices`, refined `levels` times, and placed on
/// `input` twice by fit_to_surface(): with `options` and with `control_options`, from the guide
/// the remesher starts level 1 from (here the Loop subdivision of the base rather than its limit
/// surface: as good a start for these tests; its points are off the normal lines).
struct TwoPlacements {
  SemiRegularMesh placed, control;
};
TwoPlacements place_twice(const TriangleMesh& input, const SurfaceQuery& surface, std::size_t base_vertices, int levels,
                          const SurfaceFitOptions& options, const SurfaceFitOptions& control_options) {
  DecimateOptions decimate_options;
  decimate_options.target_vertices = base_vertices;
  const TriangleMesh base = decimate(input, decimate_options).base;
  const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles),
                               levels);
  std::vector<double> guide(3 * std::size_t{h.vertex_count(levels)}, 0.0);
  std::copy(base.positions.begin(), base.positions.end(), guide.begin());
  WaveletTransform(h, {Scheme::loop}).synthesize(guide);
  std::copy(base.positions.begin(), base.positions.end(), guide.begin());
  TwoPlacements out{{h, {}, {}}, {h, {}, {}}};
  fit_to_surface(out.placed, guide, surface, options);
  fit_to_surface(out.control, guide, surface, control_options);
  return out;
}

}  // namespace

TEST_CASE("The codec's frame normal of an edge is the normalized sum of its ends' area-weighted normals",
          "[remesh][surface_fit]") {
  // A flat square split into two triangles: every frame normal is +z.
  const std::vector<std::uint32_t> two_faces = {0, 1, 2, 0, 2, 3};
  const TriangleTopology square = TriangleTopology::build(4, two_faces);
  const std::vector<double> x = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  for (const auto& n : edge_frame_normals(square, x)) {
    CHECK(n[0] == 0);
    CHECK(n[1] == 0);
    CHECK(n[2] == 1);
  }
  // A roof: two faces of equal area along the ridge 0-2, with normals (1, -1, 1) and (-1, 1, 1)
  // (times twice their area); the ridge's frame normal bisects them: +z.
  const std::vector<double> roof = {0, 0, 0, 1, 0, 1, 1, 1, 0, 0, 1, 1};
  const TriangleTopology ridge = TriangleTopology::build(4, two_faces);
  const std::vector<std::array<double, 3>> normals = edge_frame_normals(ridge, roof);
  for (std::uint32_t e = 0; e < ridge.edge_count(); ++e) {
    const std::uint32_t a = ridge.edge_vertices[2 * e], b = ridge.edge_vertices[2 * e + 1];
    if ((a == 0 && b == 2) || (a == 2 && b == 0)) {
      CHECK(normals[e][0] == Approx(0).margin(1e-15));
      CHECK(normals[e][1] == Approx(0).margin(1e-15));
      CHECK(normals[e][2] == Approx(1));
    }
  }
  // No area at the ends: a zero normal, not a NaN.
  const std::vector<double> collapsed(12, 0.0);
  for (const auto& n : edge_frame_normals(square, collapsed)) CHECK((n[0] == 0 && n[1] == 0 && n[2] == 0));
}

TEST_CASE("The remesher's frame normals are the codec's (codec/local_frames.h, FORMAT.md §5)", "[remesh][surface_fit]") {
  // The normal lines are worth something only while they are the codec's own normals: on a
  // curved mesh with faces of unequal areas, every edge of two levels against the frames the
  // encoder rotates details by.
  const SemiRegularMesh mesh = refine_linear(test::bumpy_sphere(), 2);
  const SemiRegularHierarchy& h = mesh.hierarchy;
  for (int level = 0; level < 2; ++level) {
    const std::vector<std::array<double, 3>> normals = edge_frame_normals(h.topology(level), mesh.positions);
    std::size_t compared = 0;
    frames::for_each_frame_block(h, level, mesh.positions, 3, [&](const frames::FrameBlock& block) {
      for (std::uint32_t i = 0; i < block.count; ++i, ++compared) {
        const auto& n = normals[block.first_edge + i];
        REQUIRE_FALSE(block.identity[i]);
        CHECK(n[0] == Approx(block.nx[i]).margin(1e-12));
        CHECK(n[1] == Approx(block.ny[i]).margin(1e-12));
        CHECK(n[2] == Approx(block.nz[i]).margin(1e-12));
      }
    });
    CHECK(compared == normals.size());
  }
}

TEST_CASE("The normal-line placement puts level-1 vertices on their frame normal through the prediction",
          "[remesh][surface_fit]") {
  const TriangleMesh input = test::bumpy_sphere();
  const SurfaceQuery surface(input);
  SurfaceFitOptions with_lines, without;
  without.normal_line_levels = 0;
  const auto [placed, control] = place_twice(input, surface, 80, 2, with_lines, without);

  const auto [on_line, total] = on_normal_lines(placed);
  const auto [control_on_line, control_total] = on_normal_lines(control);
  INFO("on their normal lines: " << on_line << " of " << total << " with, " << control_on_line << " without");
  CHECK(on_line >= 0.8 * static_cast<double>(total));
  CHECK(control_on_line <= 0.1 * static_cast<double>(control_total));
  // No more folds than without.
  const FoldOvers folds = find_fold_overs(placed.finest(), surface), control_folds = find_fold_overs(control.finest(), surface);
  INFO("folded faces: " << folds.flipped.size() << " with, " << control_folds.flipped.size() << " without");
  CHECK(folds.flipped.size() <= control_folds.flipped.size());
  CHECK(folds.degenerate.empty());
}

TEST_CASE("fit_to_surface refuses a negative normal_line_levels or stray_distance", "[remesh][surface_fit]") {
  const TriangleMesh input = test::icosahedron();
  const SurfaceQuery surface(input);
  const SemiRegularHierarchy h(TriangleTopology::build(12, input.triangles), 1);
  SemiRegularMesh mesh{h, {}, {}};
  std::vector<double> guide(3 * std::size_t{h.vertex_count(1)}, 0.0);
  SurfaceFitOptions options;
  options.normal_line_levels = -1;
  CHECK_THROWS_AS(fit_to_surface(mesh, guide, surface, options), std::invalid_argument);
  options.normal_line_levels = 1;
  options.stray_distance = -1;
  CHECK_THROWS_AS(fit_to_surface(mesh, guide, surface, options), std::invalid_argument);
}

TEST_CASE("Strays: a new vertex that lands on another part of a thin input is placed again from its edge",
          "[corpus][remesh][surface_fit]") {
  // Turbine's disk and blades are a few base edges thick at ~16x (L = 3): the untangling steps
  // carried vertices inside them, whence the projection found the opposite wall, up to 21 edge
  // lengths away, and the levels' faces spanned the inside of the disk.
  const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path("turbine")));
  const SurfaceQuery surface(input);
  SurfaceFitOptions with_strays, without;
  without.stray_distance = 0;
  const auto [placed, control] = place_twice(input, surface, 2303, 3, with_strays, without);  // ~16x, as remesh() sizes it
  MetricOptions metric;
  metric.samples = 100'000;
  const double psnr = surface_distance(input, placed.finest(), metric).psnr_db();
  const double control_psnr = surface_distance(input, control.finest(), metric).psnr_db();
  INFO("PSNR " << psnr << " with, " << control_psnr << " without");  // measured 59.1 and 48.5 dB
  CHECK(psnr > 58);
  CHECK(psnr > control_psnr + 6);
}

TEST_CASE("count_at_crossings counts the flipped faces whose closest input face is marked", "[remesh][surface_fit]") {
  const TriangleMesh input = test::icosphere(2);
  const SurfaceQuery surface(input);
  TriangleMesh remeshed = input;
  for (const std::size_t f : {std::size_t{0}, std::size_t{40}}) std::swap(remeshed.triangles[3 * f + 1], remeshed.triangles[3 * f + 2]);
  const FoldOvers folds = find_fold_overs(remeshed, surface);
  REQUIRE(folds.flipped == std::vector<std::uint32_t>{0, 40});
  std::vector<std::uint8_t> crossing(input.face_count(), 0);
  CHECK(count_at_crossings(remeshed, folds.flipped, surface, crossing) == 0);
  crossing[40] = 1;  // each flipped face lies on its own input face
  CHECK(count_at_crossings(remeshed, folds.flipped, surface, crossing) == 1);
  crossing[0] = 1;
  CHECK(count_at_crossings(remeshed, folds.flipped, surface, crossing) == 2);
  crossing.assign(input.face_count(), 1);
  crossing[0] = crossing[40] = 0;  // every other face marked: none under the flipped ones
  CHECK(count_at_crossings(remeshed, folds.flipped, surface, crossing) == 0);
}

TEST_CASE("count_turned_over counts the faces more than 90 degrees from a face across an edge", "[remesh][surface_fit]") {
  auto all_faces = [](const TriangleMesh& m) {
    std::vector<std::uint32_t> faces(m.face_count());
    for (std::uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
    return faces;
  };
  SECTION("a flat grid, and one creased by 80 degrees: none; by 100 degrees: the faces along the crease") {
    TriangleMesh grid = test::grid(5);
    CHECK(count_turned_over(grid, all_faces(grid)) == 0);
    CHECK(count_turned_over(grid, {}) == 0);
    auto creased = [&](double degrees) {
      TriangleMesh m = grid;
      const double angle = degrees * std::acos(-1.0) / 180;
      for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const double x = m.positions[3 * v] - 0.5;
        if (x <= 0) continue;
        m.positions[3 * v] = 0.5 + x * std::cos(angle), m.positions[3 * v + 2] = x * std::sin(angle);
      }
      return m;
    };
    CHECK(count_turned_over(creased(80), all_faces(grid)) == 0);
    const TriangleMesh sharp = creased(100);
    CHECK(count_turned_over(sharp, all_faces(grid)) == 8);  // the 4 rows of squares: one face each side of the crease
    CHECK(count_turned_over(sharp, std::vector<std::uint32_t>{0}) == 0);  // a face away from it
  }
  SECTION("a vertex pushed past its neighbours: the faces it turns over count, each against one it did not") {
    TriangleMesh grid = test::grid(5);
    grid.positions[3 * 12] = 1.1;  // the centre vertex, (0.5, 0.5) -> (1.1, 0.5), past x = 0.75 and 1
    std::vector<std::uint32_t> inverted;
    for (std::uint32_t f = 0; f < grid.face_count(); ++f) {
      const std::uint32_t* t = &grid.triangles[3 * f];
      const double* a = &grid.positions[3 * t[0]];
      const double* b = &grid.positions[3 * t[1]];
      const double* c = &grid.positions[3 * t[2]];
      if ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0) inverted.push_back(f);
    }
    REQUIRE(!inverted.empty());
    CHECK(count_turned_over(grid, inverted) == inverted.size());
    CHECK(count_turned_over(grid, std::vector<std::uint32_t>{0}) == 0);
  }
  SECTION("a remesh facing away from its input everywhere: every face flipped, none turned over") {
    const TriangleMesh input = test::icosphere(2);
    TriangleMesh reversed = input;
    for (std::size_t f = 0; f < reversed.face_count(); ++f) std::swap(reversed.triangles[3 * f + 1], reversed.triangles[3 * f + 2]);
    const FoldOvers folds = find_fold_overs(reversed, SurfaceQuery(input));
    REQUIRE(folds.flipped.size() == input.face_count());
    CHECK(count_turned_over(reversed, folds.flipped) == 0);
    TriangleMesh one = input;  // one face turned alone: it, not its neighbours, is on the list
    std::swap(one.triangles[1], one.triangles[2]);
    CHECK(count_turned_over(one, find_fold_overs(one, SurfaceQuery(input)).flipped) == 1);
  }
}

TEST_CASE("round_to_float mends a face that rounding turns to the other wall of a groove", "[remesh][surface_fit]") {
  // A narrow groove along the x axis: two walls whose normals face into it and away from each
  // other, (0, 1, 0.3) and (0, -1, 0.3). A small face whose centroid lies a hair (1e-13) on wall
  // 0's side of the bisector plane y = 0 and that faces like wall 0 does not fold in double; once
  // its corners are rounded to floats its centroid may lie on wall 1's side, and against wall 1
  // it folds (find_fold_overs()'s test). round_to_float() must then round its corners the other
  // way, to floats around the same exact values, so that it does not fold.
  const TriangleMesh groove{{0, 0, 0, 1, 0, 0, 0.5, -0.3, 1, 0.5, 0.3, 1}, {1, 0, 2, 0, 1, 3}};
  const SurfaceQuery surface(groove);
  const double n = std::sqrt(1.09), vy = -0.3 / n, vz = 1 / n, s = 1e-3;  // v: in the face's plane
  int found = 0;
  for (int k = 0; k < 200 && found < 3; ++k) {
    const double cx = 0.4 + 1e-4 * k, cy = -1e-13, cz = 0.4 + 1e-3 * ((k * 37) % 100);
    const std::vector<double> exact{cx - s, cy - s * vy / 2, cz - s * vz / 2, cx, cy + s * vy, cz + s * vz,
                                    cx + s, cy - s * vy / 2, cz - s * vz / 2};
    const SemiRegularMesh face{SemiRegularHierarchy(TriangleTopology::build(3, std::vector<std::uint32_t>{0, 1, 2}), 0),
                               exact, {}};
    REQUIRE(find_fold_overs(face.finest(), surface).flipped.empty());
    SemiRegularMesh rounded = face;
    for (double& x : rounded.positions) x = static_cast<float>(x);
    if (find_fold_overs(rounded.finest(), surface).flipped.empty()) continue;  // rounding kept wall 0
    ++found;
    SemiRegularMesh stored = face;
    const FoldOvers folds = round_to_float(stored, surface);
    CHECK(folds.flipped.empty());
    CHECK(folds.degenerate.empty());
    CHECK(find_fold_overs(stored.finest(), surface).flipped.empty());
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const double x = stored.positions[i];
      CHECK(static_cast<float>(x) == x);
      // One of the two floats around the exact value.
      const float nearest = static_cast<float>(exact[i]);
      CHECK(std::abs(x - exact[i]) <= std::abs(static_cast<double>(std::nextafter(nearest, 2.0f * nearest + 1)) - nearest));
    }
  }
  CHECK(found == 3);  // the groove gives such faces at all (3 in the first 9 tried)
}
