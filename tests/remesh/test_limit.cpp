// Limit stencils against repeated subdivision by independent subdividers (OpenMesh's LoopT and
// CatmullClarkT, and our catmull_clark on open meshes, whose boundary rule OpenMesh does not share).
//
// Tolerances. Near an interior vertex of valence n the subdivision of its 1-ring is a fixed
// linear map S; the vertex itself only sees S's rotation-invariant eigenvectors (the others vanish
// at the centre). So, with e_k = v_k - v∞ the error of an original vertex after k levels:
// - Loop interior:      e_k = μ^k e_0, μ = (3/8 + ¼ cos(2π/n))² (the eigenvalue 5/8 - nβ_n);
// - any boundary curve (cubic B-spline, Loop or Catmull-Clark): e_k = 4^-k e_0 (the 1/2 mode
//   vanishes at the centre, seed 004's E matrix);
// - Catmull-Clark interior (all quads): two modes ρ_a, ρ_b, so e_{k+1} = s e_k - p e_{k-1} with
//   s = ρ_a + ρ_b, p = ρ_a ρ_b from the 3x3 block of (V, E, F) (for n = 3: 1/6 and 0; n = 4: 1/4, 1/16).
// The tests check these identities at every level to 1e-13 x bbox diagonal (measured residuals
// stay below 2e-16 x diagonal), which is far stronger than "small after many levels": a wrong
// limit weight leaves e_k at a constant offset. They also check the plain error after the last
// level against |e_K| <= ρ_a^K |a| + ρ_b^K |b| (+ rounding), < 1e-4 x diagonal everywhere, and
// < 1e-6 x diagonal on the cube (8 levels) and bicone 3 (9 levels). Levels stay at 7-9 (at most
// ~1.5 M faces, ~250 MB, ~2 s for the file): 10 Loop levels of even a 5-triangle mesh are 5 M
// faces, too many for OpenMesh's half-edge mesh in that budget, and with the decay rates known
// exactly, more levels add nothing the identities do not already check.
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include "meshlift/limit.h"
#include "meshlift/polygon_subdivision.h"
#include "test_meshes.h"
#include "test_openmesh.h"

namespace {

using namespace meshlift;

using test::OpenMeshPoly;
using test::OpenMeshTri;
using test::to_openmesh;

using test::from_openmesh;

// history[k] = positions of the original vertices after k levels. OpenMesh's uniform subdividers
// append new vertices and keep old indices; the identities checked at k = 1 would fail otherwise.
template <typename OM, typename Subdivider>
std::vector<std::vector<double>> openmesh_history(const PolygonMesh& mesh, int levels) {
  OM om = to_openmesh<OM>(mesh);
  const std::size_t count = mesh.vertex_count();
  std::vector<std::vector<double>> history{mesh.positions};
  Subdivider subdivider;
  for (int k = 1; k <= levels; ++k) {
    REQUIRE(subdivider(om, 1));
    REQUIRE(om.n_vertices() > count);
    std::vector<double> positions(3 * count);
    for (std::size_t v = 0; v < count; ++v)
      for (int c = 0; c < 3; ++c) positions[3 * v + c] = om.point(OpenMesh::VertexHandle(static_cast<int>(v)))[c];
    history.push_back(std::move(positions));
  }
  return history;
}

std::vector<std::vector<double>> our_catmull_clark_history(const PolygonMesh& mesh, int levels) {
  std::vector<std::vector<double>> history{mesh.positions};
  PolygonMesh current = mesh;
  for (int k = 1; k <= levels; ++k) {
    current = catmull_clark(current, 1);
    history.emplace_back(current.positions.begin(), current.positions.begin() + mesh.positions.size());
  }
  return history;
}

// Valence and boundary flag of each vertex, computed here from the face lists.
struct VertexClass {
  std::size_t valence = 0;
  bool boundary = false;
};
std::vector<VertexClass> classify(const PolygonMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_faces;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
      const std::uint32_t a = mesh.face_indices[c];
      const std::uint32_t b = mesh.face_indices[c + 1 == mesh.face_offsets[f + 1] ? mesh.face_offsets[f] : c + 1];
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<VertexClass> classes(mesh.vertex_count());
  for (const auto& [edge, faces] : edge_faces)
    for (std::uint32_t v : {edge.first, edge.second}) {
      ++classes[v].valence;
      classes[v].boundary = classes[v].boundary || faces == 1;
    }
  return classes;
}

double norm3(const double* a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

// Checks the decay identity at every level and the plain error at the last level.
// `modes(v)` returns {ρ_a, ρ_b}; ρ_b = 0 for the one-mode vertices (Loop interior, boundary curves).
// One mode: e_k = ρ_a e_{k-1} from k = 1. Two modes (Catmull-Clark interior): e_k = a ρ_a^k + b ρ_b^k,
// so e_k = s e_{k-1} - p e_{k-2} from k = 2, even when ρ_b = 0 (n = 3: b shows at k = 0 only).
template <typename Modes>
double check_convergence(const std::vector<std::vector<double>>& history, const std::vector<double>& limit,
                       double diagonal, bool two_modes, Modes modes) {
  const std::size_t count = limit.size() / 3;
  const std::size_t levels = history.size() - 1;
  double worst_identity = 0, worst_final = 0;
  for (std::size_t v = 0; v < count; ++v) {
    const auto [rho_a, rho_b] = modes(v);
    const double s = rho_a + rho_b, p = rho_a * rho_b;
    std::vector<std::array<double, 3>> e(levels + 1);
    for (std::size_t k = 0; k <= levels; ++k)
      for (int c = 0; c < 3; ++c) e[k][c] = history[k][3 * v + c] - limit[3 * v + c];
    for (std::size_t k = two_modes ? 2 : 1; k <= levels; ++k)
      for (int c = 0; c < 3; ++c) {
        const double predicted = two_modes ? s * e[k - 1][c] - p * e[k - 2][c] : rho_a * e[k - 1][c];
        worst_identity = std::max(worst_identity, std::abs(e[k][c] - predicted));
      }
    // |e_K| <= ρ_a^K |a| + ρ_b^K |b| with a + b = e_0, a ρ_a + b ρ_b = e_1 (one mode: a = e_0).
    double bound = 0;
    for (int c = 0; c < 3; ++c) {
      const double a = two_modes ? (e[1][c] - rho_b * e[0][c]) / (rho_a - rho_b) : e[0][c];
      const double b = two_modes ? (rho_a * e[0][c] - e[1][c]) / (rho_a - rho_b) : 0.0;
      const double term = std::pow(rho_a, double(levels)) * std::abs(a) + std::pow(rho_b, double(levels)) * std::abs(b);
      bound += term * term;
    }
    bound = std::sqrt(bound);
    const double final_error = norm3(e[levels].data());
    INFO("vertex " << v << ": |e_0| = " << norm3(e[0].data()) << ", |e_" << levels << "| = " << final_error
                   << ", rate " << rho_a);
    CHECK(final_error <= bound * (1 + 1e-6) + 1e-12 * diagonal);
    worst_final = std::max(worst_final, final_error);
  }
  INFO("worst identity residual " << worst_identity / diagonal << " x diagonal, worst final error "
                                  << worst_final / diagonal << " x diagonal after " << levels << " levels");
  CHECK(worst_identity <= 1e-13 * diagonal);
  return worst_final / diagonal;
}

double loop_rate(const VertexClass& c) {
  if (c.boundary) return 0.25;
  const double x = 3.0 / 8.0 + 0.25 * std::cos(2 * M_PI / static_cast<double>(c.valence));
  return x * x;
}

// Catmull-Clark interior: eigenvalues ≠ 1 of the (V, E, F) block, rows
// V' = ((4n-7)/(4n)) V + (3/(2n)) E + (1/(4n)) F, E' = 3/8 V + 1/2 E + 1/8 F, F' = 1/4 V + 1/2 E + 1/4 F.
std::pair<double, double> catmull_clark_rates(const VertexClass& c) {
  if (c.boundary) return {0.25, 0.0};
  const double n = static_cast<double>(c.valence);
  const double m[3][3] = {{(4 * n - 7) / (4 * n), 3 / (2 * n), 1 / (4 * n)}, {3.0 / 8, 0.5, 1.0 / 8}, {0.25, 0.5, 0.25}};
  const double trace = m[0][0] + m[1][1] + m[2][2];
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  const double s = trace - 1, p = det;  // the other two eigenvalues: sum s, product p
  const double root = std::sqrt(std::max(0.0, s * s - 4 * p));
  return {(s + root) / 2, (s - root) / 2};
}



TriangleMesh perturbed(TriangleMesh mesh, unsigned seed) {
  const auto noise = test::random_values(mesh.positions.size(), seed);
  for (std::size_t i = 0; i < noise.size(); ++i) mesh.positions[i] += 0.05 * noise[i];
  return mesh;
}

}  // namespace

TEST_CASE("Loop limit points are where OpenMesh LoopT converges", "[remesh][limit]") {
  using Loop = OpenMesh::Subdivider::Uniform::LoopT<OpenMeshTri, double>;
  struct Case {
    const char* name;
    TriangleMesh mesh;
    int levels;
  };
  const std::vector<Case> cases = {
      {"icosahedron (valence 5)", perturbed(test::icosahedron(), 3), 7},
      {"bicone 3", test::bicone(3), 9},
      {"bicone 4", test::bicone(4), 8},
      {"bicone 6", test::bicone(6), 8},
      {"bicone 7", perturbed(test::bicone(7), 4), 8},
      {"disk 5 (boundary)", test::disk(5), 9},
      {"grid 4 (boundary, corners of valence 2 and 3)", perturbed(test::grid(4), 5), 7},
  };
  for (const auto& c : cases) {
    INFO(c.name << ", " << c.levels << " levels");
    const PolygonMesh polygons = to_polygon_mesh(c.mesh);
    const auto history = openmesh_history<OpenMeshTri, Loop>(polygons, c.levels);
    const TriangleMesh limit = loop_limit(c.mesh);
    REQUIRE(limit.triangles == c.mesh.triangles);
    const auto classes = classify(polygons);
    const double worst = check_convergence(history, limit.positions, bounding_box_diagonal(c.mesh.positions), false,
                                           [&](std::size_t v) { return std::pair{loop_rate(classes[v]), 0.0}; });
    // Slowest rate here 4^-k (boundary, valence 6) or 0.28^k (valence 7): below 1e-5 x diagonal
    // at these levels; bicone 3 (rates 1/16 and 0.14) gets below 1e-6.
    CHECK(worst < (c.levels == 9 && c.mesh.vertex_count() == 5 ? 1e-6 : 1e-4));
  }
}

TEST_CASE("Catmull-Clark limit points are where subdivision converges", "[remesh][limit]") {
  using CatmullClark = OpenMesh::Subdivider::Uniform::CatmullClarkT<OpenMeshPoly, double>;
  SECTION("cube, OpenMesh CatmullClarkT, 8 levels") {
    PolygonMesh cube = test::cube_quads();
    const auto noise = test::random_values(cube.positions.size(), 7);
    for (std::size_t i = 0; i < noise.size(); ++i) cube.positions[i] += 0.1 * noise[i];
    const auto history = openmesh_history<OpenMeshPoly, CatmullClark>(cube, 8);
    const PolygonMesh limit = catmull_clark_limit(cube);
    REQUIRE(limit.face_indices == cube.face_indices);
    const auto classes = classify(cube);
    const double diagonal = bounding_box_diagonal(cube.positions);
    check_convergence(history, limit.positions, diagonal, true, [&](std::size_t v) { return catmull_clark_rates(classes[v]); });
    for (std::size_t v = 0; v < cube.vertex_count(); ++v) {
      double e[3];
      for (int c = 0; c < 3; ++c) e[c] = history.back()[3 * v + c] - limit.positions[3 * v + c];
      CHECK(norm3(e) < 1e-6 * diagonal);
    }
  }
  SECTION("open quad grid, our catmull_clark (cubic B-spline boundary), 8 levels") {
    const PolygonMesh grid = test::open_quad_grid(3);
    const auto history = our_catmull_clark_history(grid, 8);
    const PolygonMesh limit = catmull_clark_limit(grid);
    const auto classes = classify(grid);
    CHECK(check_convergence(history, limit.positions, bounding_box_diagonal(grid.positions), true,
                            [&](std::size_t v) { return catmull_clark_rates(classes[v]); }) < 1e-4);
  }
  SECTION("pentagonal pyramid: the limit of the once-subdivided mesh (valence 5 and 3)") {
    const PolygonMesh pyramid = test::pentagonal_pyramid();
    OpenMeshPoly om = to_openmesh<OpenMeshPoly>(pyramid);
    CatmullClark subdivider;
    REQUIRE(subdivider(om, 1));
    const PolygonMesh once = from_openmesh(om);  // all quads, OpenMesh's vertex order
    const auto history = openmesh_history<OpenMeshPoly, CatmullClark>(once, 7);
    const PolygonMesh limit = catmull_clark_limit(once);
    const auto classes = classify(once);
    REQUIRE(std::any_of(classes.begin(), classes.end(), [](const auto& c) { return c.valence == 5; }));
    CHECK(check_convergence(history, limit.positions, bounding_box_diagonal(once.positions), true,
                            [&](std::size_t v) { return catmull_clark_rates(classes[v]); }) < 1e-4);
    // On the pyramid itself (not all quads) catmull_clark_limit subdivides once first.
    const PolygonMesh direct = catmull_clark_limit(pyramid);
    const PolygonMesh ours_once = catmull_clark(pyramid, 1);
    REQUIRE(direct.face_indices == ours_once.face_indices);
    const PolygonMesh expected = catmull_clark_limit(ours_once);
    for (std::size_t i = 0; i < direct.positions.size(); ++i) CHECK(direct.positions[i] == expected.positions[i]);
  }
}

TEST_CASE("1D cubic B-spline: a polyline converges to (1/6 4/6 1/6)", "[remesh][limit]") {
  // Closed polyline refined with (1/8, 3/4, 1/8) at old points and midpoints at new ones (seed 004).
  std::vector<double> points = {0.0, 1.0, 0.3, -0.7, 2.0, 1.1, -0.4};
  const std::size_t n = points.size();
  std::vector<double> limit(n), initial = points;
  for (std::size_t i = 0; i < n; ++i)
    limit[i] = (points[(i + n - 1) % n] + 4 * points[i] + points[(i + 1) % n]) / 6;
  const int levels = 16;
  for (int k = 1; k <= levels; ++k) {
    const std::size_t m = points.size();
    std::vector<double> refined(2 * m);
    for (std::size_t i = 0; i < m; ++i) {
      refined[2 * i] = (points[(i + m - 1) % m] + 6 * points[i] + points[(i + 1) % m]) / 8;
      refined[2 * i + 1] = (points[i] + points[(i + 1) % m]) / 2;
    }
    points = std::move(refined);
    for (std::size_t i = 0; i < n; ++i) {  // original point i now sits at i·2^k
      const double error = points[i << k] - limit[i];
      CHECK(error == Approx(std::pow(0.25, k) * (initial[i] - limit[i])).margin(1e-14));
    }
  }
  for (std::size_t i = 0; i < n; ++i) CHECK(std::abs(points[i << levels] - limit[i]) < 1e-9);
}

TEST_CASE("LimitStencil rows - apply and errors", "[remesh][limit]") {
  const TriangleMesh disk = test::disk(6);
  const LimitStencil stencil = loop_limit_stencil(disk);
  REQUIRE(stencil.vertex_count() == disk.vertex_count());
  for (std::size_t v = 0; v < stencil.vertex_count(); ++v) {
    double sum = 0;
    for (std::uint32_t r = stencil.row_offsets[v]; r < stencil.row_offsets[v + 1]; ++r) sum += stencil.weights[r];
    CHECK(sum == Approx(1.0).margin(1e-15));
  }
  // Regular interior vertex: ½ itself, 1/12 each neighbour (CODEC-NOTES §5).
  CHECK(stencil.row_offsets[1] - stencil.row_offsets[0] == 7);
  CHECK(stencil.weights[0] == Approx(0.5).margin(1e-15));
  for (int r = 1; r < 7; ++r) CHECK(stencil.weights[r] == Approx(1.0 / 12).margin(1e-15));

  std::vector<double> out(disk.positions.size());
  apply_loop_limit(disk, disk.positions, out);
  CHECK(out == loop_limit(disk).positions);
  std::vector<double> short_out(3);
  CHECK_THROWS_AS(stencil.apply(disk.positions, short_out), std::invalid_argument);

  // Regular quad vertex: 16/36 itself, 4/36 edge neighbours, 1/36 diagonals.
  const PolygonMesh grid = test::open_quad_grid(2);
  const LimitStencil quads = catmull_clark_limit_stencil(grid);
  const std::uint32_t centre = 4;
  REQUIRE(quads.row_offsets[centre + 1] - quads.row_offsets[centre] == 9);
  CHECK(quads.weights[quads.row_offsets[centre]] == Approx(16.0 / 36).margin(1e-15));
  std::vector<double> quad_out(grid.positions.size());
  apply_catmull_clark_limit(grid, grid.positions, quad_out);
  CHECK(quad_out == catmull_clark_limit(grid).positions);

  CHECK_THROWS_AS(catmull_clark_limit_stencil(test::pentagonal_pyramid()), MeshError);
  TriangleMesh broken = test::icosahedron();
  broken.triangles.push_back(0);
  CHECK_THROWS_AS(loop_limit(broken), MeshError);
}

TEST_CASE("Interpolation by iterated limit differences converges", "[remesh][limit]") {
  // Seed 000 eq. 1-3: C_{k+1} = C_k + (P - A C_k) with A the Catmull-Clark limit operator of a
  // mesh with a vertex of valence > 3; the limit points of C then interpolate P.
  const PolygonMesh mesh = catmull_clark(test::pentagonal_pyramid(), 1);
  const LimitStencil a = catmull_clark_limit_stencil(mesh);
  const std::vector<double>& target = mesh.positions;
  std::vector<double> control = target, limit(target.size());
  double residual = 0, residual_at_50 = 0;
  for (int iteration = 0; iteration < 400; ++iteration) {
    a.apply(control, limit);
    residual = 0;
    for (std::size_t i = 0; i < target.size(); ++i) {
      const double difference = target[i] - limit[i];
      residual = std::max(residual, std::abs(difference));
      control[i] += difference;
    }
    if (iteration == 50) residual_at_50 = residual;
  }
  INFO("max |P - A C_k|: " << residual_at_50 << " at k = 50, " << residual << " at k = 400");
  CHECK(residual < 1e-3 * residual_at_50);
  CHECK(residual < 1e-12 * bounding_box_diagonal(target));
}
