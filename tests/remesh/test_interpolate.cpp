// Interpolation by iterated limit differences (interpolate.h; seed 000 eq. 1-3).
//
// Two checks per mesh. (1) The residual max |P - A C| reaches 1e-10 x bbox diagonal, and a limit
// computed afresh from the returned control mesh (loop_limit / catmull_clark_limit) agrees, so the
// reported residual is the control's. (2) Independently of our limit stencils: subdivide the
// control mesh 8 levels with OpenMesh's LoopT / CatmullClarkT (closed quad meshes; OpenMesh's
// Catmull-Clark boundary rule differs from ours, BoundaryVertexRule, so the open grid uses our
// catmull_clark) and measure how far the original vertices are from the targets.
//
// Tolerance of (2). After K levels an original vertex v is off its limit point (A C)_v by
// e_K = ρ^K e_0 (one mode: Loop interior, any boundary curve) or a ρ_a^K + b ρ_b^K (Catmull-Clark
// interior; test_limit.cpp derives both), with e_0 = C_v - (A C)_v and ρ the subdominant
// eigenvalue at v: Loop (3/8 + ¼ cos(2π/n))², 0.20 at n = 5, 0.28 at n = 7; Catmull-Clark 1/6,
// 1/4, 0.32 at n = 3, 4, 5; 1/4 on a boundary. So the fitted mesh must be within
// 2 ρ_max^K max|C - A C| + residual of the targets (the factor 2 covers the second Catmull-Clark
// mode; the one-mode cases land on ρ^K |e_0| to three digits), and, as a fixed ceiling, within
// 1e-4 x diagonal (ρ_max^8 <= 1.2e-4 and |C - A C| <= 0.6 x diagonal here). The unfitted mesh
// (control = targets) ends at its own limit points, |P - A P| = residuals[0] away, which these
// meshes keep above 1e-2 x diagonal: a fit that did nothing, or fitted another scheme's limit,
// fails. Sizes: at most 10 base triangles (655k after 8 Loop levels), 20 base quads (1.3 M).
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "meshlift/interpolate.h"
#include "meshlift/limit.h"
#include "meshlift/polygon_subdivision.h"
#include "test_meshes.h"
#include "test_openmesh.h"

namespace {

using namespace meshlift;

using Loop = OpenMesh::Subdivider::Uniform::LoopT<test::OpenMeshTri, double>;
using CatmullClark = OpenMesh::Subdivider::Uniform::CatmullClarkT<test::OpenMeshPoly, double>;

constexpr double kFitTolerance = 1e-10;    // FitOptions default, x diagonal
constexpr int kLevels = 8;                 // subdivision levels of the independent check
constexpr double kSubdividedFitted = 1e-4;    // x diagonal, see the file comment
constexpr double kSubdividedUnfitted = 1e-2;  // x diagonal: the unfitted mesh must be at least this far

/// Largest Euclidean distance between corresponding vertices of two xyz arrays.
double max_distance(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (std::size_t v = 0; 3 * v < a.size(); ++v)
    worst = std::max(worst, std::hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]));
  return worst;
}

/// Checks (1) of the file comment; `limit_of` computes the limit positions of a control mesh.
template <typename LimitOf>
void check_converged(const char* name, const FitResult& fit, const PolygonMesh& targets, int max_iterations,
                     LimitOf limit_of) {
  const double diagonal = bounding_box_diagonal(targets.positions);
  const double rate = std::pow(fit.residuals.back() / fit.residuals.front(), 1.0 / fit.iterations());
  std::printf("fit %-48s %3d iterations, residual %.2e -> %.2e x diagonal (%.3f per iteration)\n", name,
              fit.iterations(), fit.residuals.front() / diagonal, fit.residuals.back() / diagonal, rate);
  INFO(name << ": " << fit.iterations() << " iterations, final residual " << fit.residuals.back() / diagonal
            << " x diagonal");
  CHECK(fit.diagonal == diagonal);
  REQUIRE(fit.converged);
  CHECK(fit.iterations() > 0);
  CHECK(fit.iterations() < max_iterations);
  CHECK(fit.residuals.back() <= kFitTolerance * diagonal);
  CHECK(fit.residuals.front() > 1e-2 * diagonal);  // there was something to fit
  // The residual before the last update was still above the tolerance (no early stop).
  CHECK(fit.residuals[fit.residuals.size() - 2] > kFitTolerance * diagonal);
  CHECK(fit.control.face_offsets == targets.face_offsets);
  CHECK(fit.control.face_indices == targets.face_indices);
  // C_0 = P: the first residual is |P - A P|.
  CHECK(fit.residuals.front() == Approx(max_distance(limit_of(targets), targets.positions)).epsilon(1e-12));
  const double recomputed = max_distance(limit_of(fit.control), targets.positions);
  CHECK(recomputed <= kFitTolerance * diagonal);
  CHECK(recomputed == Approx(fit.residuals.back()).margin(1e-14 * diagonal));
}

/// Subdominant eigenvalue of Loop subdivision at an interior vertex of valence n.
double loop_rate(int n) {
  const double x = 3.0 / 8.0 + 0.25 * std::cos(2 * M_PI / n);
  return x * x;
}

/// Larger subdominant eigenvalue of Catmull-Clark at an interior vertex of valence n (all quads):
/// of the (V, E, F) block V' = ((4n-7)/(4n)) V + (3/(2n)) E + (1/(4n)) F,
/// E' = 3/8 V + 1/2 E + 1/8 F, F' = 1/4 V + 1/2 E + 1/4 F, whose third eigenvalue is 1.
double catmull_clark_rate(int n) {
  const double m[3][3] = {{(4.0 * n - 7) / (4 * n), 3.0 / (2 * n), 1.0 / (4 * n)}, {3.0 / 8, 0.5, 1.0 / 8}, {0.25, 0.5, 0.25}};
  const double sum = m[0][0] + m[1][1] + m[2][2] - 1;
  const double product = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return (sum + std::sqrt(std::max(0.0, sum * sum - 4 * product))) / 2;
}

/// Checks (2) of the file comment: `subdivide(mesh)` returns the original vertices after kLevels;
/// `rate` is the slowest subdominant eigenvalue over the mesh's vertices.
template <typename Subdivide, typename LimitOf>
void check_subdivided(const char* name, const FitResult& fit, const PolygonMesh& targets, double rate,
                      Subdivide subdivide, LimitOf limit_of) {
  const double diagonal = bounding_box_diagonal(targets.positions);
  const double fitted = max_distance(subdivide(fit.control), targets.positions) / diagonal;
  const double unfitted = max_distance(subdivide(targets), targets.positions) / diagonal;
  const double initial_offset = max_distance(limit_of(fit.control), fit.control.positions) / diagonal;
  const double bound = 2 * std::pow(rate, kLevels) * initial_offset + fit.residuals.back() / diagonal;
  std::printf("%-48s %d levels: fitted %.2e (bound %.2e), unfitted %.2e x diagonal\n", name, kLevels, fitted, bound,
              unfitted);
  INFO(name << ": fitted " << fitted << " (bound " << bound << "), unfitted " << unfitted << " x diagonal; |C - A C| "
            << initial_offset << ", rate " << rate);
  CHECK(fitted <= bound);
  CHECK(fitted <= kSubdividedFitted);
  CHECK(unfitted >= kSubdividedUnfitted);
}

std::vector<double> loop_limit_of(const PolygonMesh& mesh) { return loop_limit(to_triangle_mesh(mesh)).positions; }
std::vector<double> catmull_clark_limit_of(const PolygonMesh& mesh) { return catmull_clark_limit(mesh).positions; }

std::vector<double> openmesh_loop(const PolygonMesh& mesh) {
  return test::openmesh_subdivided_originals<test::OpenMeshTri, Loop>(mesh, kLevels);
}
std::vector<double> openmesh_catmull_clark(const PolygonMesh& mesh) {
  return test::openmesh_subdivided_originals<test::OpenMeshPoly, CatmullClark>(mesh, kLevels);
}
std::vector<double> our_catmull_clark(const PolygonMesh& mesh) {
  const PolygonMesh fine = catmull_clark(mesh, kLevels);
  return {fine.positions.begin(), fine.positions.begin() + static_cast<std::ptrdiff_t>(mesh.positions.size())};
}

/// ±1 on alternate corners of test::cube_quads() (by the parity of x + y + z).
double checkerboard_sign(std::uint32_t v) {
  constexpr double signs[8] = {1, -1, 1, -1, -1, 1, -1, 1};
  return signs[v];
}

/// The unit cube with random offsets, minus their checkerboard component (±1 on alternate
/// corners), which the all-valence-3 cube's limit operator maps to 0 (interpolate.h).
PolygonMesh perturbed_cube() {
  PolygonMesh cube = test::perturbed(test::cube_quads(), 0.15, 11);
  for (int k = 0; k < 3; ++k) {
    double component = 0;
    for (std::uint32_t v = 0; v < 8; ++v) {
      component += checkerboard_sign(v) * cube.positions[3 * v + k] / 8;
    }
    for (std::uint32_t v = 0; v < 8; ++v) {
      cube.positions[3 * v + k] -= checkerboard_sign(v) * component;
    }
  }
  return cube;
}

}  // namespace

TEST_CASE("fit_loop interpolates: residual, fresh limit and OpenMesh LoopT agree", "[remesh][interpolate]") {
  struct Case {
    const char* name;
    TriangleMesh targets;
    double rate;  // slowest subdominant eigenvalue: interior valence 5 / 7 (boundary: 1/4)
  };
  const Case cases[] = {
      {"Loop, bicone 5 perturbed (closed, valence 5)", test::perturbed(test::bicone(5), 0.05, 21), loop_rate(5)},
      {"Loop, disk 7 (open, valence 7)", test::disk(7), loop_rate(7)},
  };
  for (const Case& c : cases) {
    const PolygonMesh targets = to_polygon_mesh(c.targets);
    REQUIRE(targets.face_count() <= 10);
    const FitResult fit = fit_loop(c.targets);
    CHECK_FALSE(fit.subdivided_first);
    check_converged(c.name, fit, targets, FitOptions{}.max_iterations, loop_limit_of);
    check_subdivided(c.name, fit, targets, c.rate, openmesh_loop, loop_limit_of);
  }
}

TEST_CASE("fit_catmull_clark interpolates: residual, fresh limit and subdivision agree", "[remesh][interpolate]") {
  SECTION("closed: OpenMesh CatmullClarkT") {
    struct Case {
      const char* name;
      PolygonMesh targets;
      double rate;
      int max_iterations;
    };
    // catmull_clark(pyramid, 1) has ten vertices of valence 3 (the triangles' face points and
    // the base corners): A's smallest eigenvalue there is about 0.09, so 1e-10 takes some 235
    // iterations, more than the default 200.
    const Case cases[] = {
        {"Catmull-Clark, cube (valence 3)", test::cube_quads(), catmull_clark_rate(3), 200},
        {"Catmull-Clark, cube perturbed (valence 3)", perturbed_cube(), catmull_clark_rate(3), 200},
        {"Catmull-Clark, pyramid once (valence 5, 3, 4)", catmull_clark(test::pentagonal_pyramid(), 1),
         catmull_clark_rate(5), 400},
    };
    for (const Case& c : cases) {
      const FitResult fit = fit_catmull_clark(c.targets, {c.max_iterations, kFitTolerance});
      CHECK_FALSE(fit.subdivided_first);
      check_converged(c.name, fit, c.targets, c.max_iterations, catmull_clark_limit_of);
      check_subdivided(c.name, fit, c.targets, c.rate, openmesh_catmull_clark, catmull_clark_limit_of);
    }
  }
  SECTION("open grid: our catmull_clark (OpenMesh's boundary vertex rule differs)") {
    const PolygonMesh grid = test::open_quad_grid(3);
    const FitResult fit = fit_catmull_clark(grid);
    check_converged("Catmull-Clark, open quad grid 3x3", fit, grid, FitOptions{}.max_iterations, catmull_clark_limit_of);
    // Interior valence 4 and the boundary curve: both 1/4.
    check_subdivided("Catmull-Clark, open quad grid 3x3 (ours)", fit, grid, catmull_clark_rate(4), our_catmull_clark,
                     catmull_clark_limit_of);
  }
}

TEST_CASE("fit_catmull_clark on non-quad faces fits the once-subdivided mesh", "[remesh][interpolate]") {
  const PolygonMesh pyramid = test::pentagonal_pyramid();
  const FitResult direct = fit_catmull_clark(pyramid);
  CHECK(direct.subdivided_first);
  const FitResult once = fit_catmull_clark(catmull_clark(pyramid, 1));
  CHECK_FALSE(once.subdivided_first);
  CHECK(direct.control.face_indices == once.control.face_indices);
  CHECK(direct.control.positions == once.control.positions);
  CHECK(direct.residuals == once.residuals);
}

TEST_CASE("fit stops at max_iterations and reports it", "[remesh][interpolate]") {
  const TriangleMesh targets = test::perturbed(test::bicone(5), 0.05, 21);
  const FitResult full = fit_loop(targets);
  REQUIRE(full.iterations() > 3);
  const FitResult three = fit_loop(targets, {3, 1e-10});
  CHECK_FALSE(three.converged);
  REQUIRE(three.residuals.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) CHECK(three.residuals[k] == full.residuals[k]);
  // The returned control is C_3: its residual is residuals[3].
  CHECK(max_distance(loop_limit(to_triangle_mesh(three.control)).positions, targets.positions) ==
        Approx(three.residuals[3]).margin(1e-15));
  const FitResult none = fit_loop(targets, {0, 1e-10});
  CHECK(none.residuals.size() == 1);
  CHECK(none.control.positions == targets.positions);
  // A loose tolerance stops early: the first residual at or below it.
  const double loose = full.residuals[5] / full.diagonal;
  const FitResult early = fit_loop(targets, {200, loose});
  CHECK(early.converged);
  CHECK(early.residuals.back() <= loose * early.diagonal);
  CHECK(early.iterations() <= 5);
}

TEST_CASE("fit_catmull_clark: the cube's checkerboard mode is never reached", "[remesh][interpolate]") {
  // All corners of valence 3: the limit operator maps ±ε on alternate corners to 0, so
  // P - A C_k keeps that component forever (interpolate.h); the fit must say it did not converge.
  PolygonMesh cube = test::cube_quads();
  const double epsilon = 0.01;
  for (std::uint32_t v = 0; v < 8; ++v) {
    for (int k = 0; k < 3; ++k) cube.positions[3 * v + k] += checkerboard_sign(v) * epsilon;
  }
  const FitResult fit = fit_catmull_clark(cube, {100, 1e-10});
  CHECK_FALSE(fit.converged);
  CHECK(fit.iterations() == 100);
  CHECK(fit.residuals.back() == Approx(epsilon * std::sqrt(3.0)).epsilon(1e-9));
}

TEST_CASE("fit rejects bad input", "[remesh][interpolate]") {
  TriangleMesh fin = test::icosahedron();  // a fourth face on edge (0, 11): non-manifold edge
  const std::size_t extra = fin.positions.size() / 3;
  fin.positions.insert(fin.positions.end(), {0.3, 0.3, 0.3});
  fin.triangles.insert(fin.triangles.end(), {0, 11, static_cast<std::uint32_t>(extra)});
  CHECK_THROWS_AS(fit_loop(fin), MeshError);
  CHECK_THROWS_AS(fit_catmull_clark(to_polygon_mesh(fin)), MeshError);  // via the subdivision step
  PolygonMesh quads = test::cube_quads();  // a seventh quad on edge (0, 3): non-manifold
  quads.positions.insert(quads.positions.end(), {0.5, 0.5, -1, 0.5, 0.6, -1});
  quads.face_indices.insert(quads.face_indices.end(), {0, 3, 9, 8});
  quads.face_offsets.push_back(static_cast<std::uint32_t>(quads.face_indices.size()));
  CHECK_THROWS_AS(fit_catmull_clark(quads), MeshError);

  TriangleMesh not_finite = test::disk(5);
  not_finite.positions[4] = std::nan("");
  CHECK_THROWS_AS(fit_loop(not_finite), MeshError);
  CHECK_THROWS_AS(fit_loop(test::disk(5), {-1, 1e-10}), std::invalid_argument);
  CHECK_THROWS_AS(fit_loop(test::disk(5), {10, -1.0}), std::invalid_argument);
  CHECK_THROWS_AS(fit_catmull_clark(test::cube_quads(), {10, std::nan("")}), std::invalid_argument);
}
