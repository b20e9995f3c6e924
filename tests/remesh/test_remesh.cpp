// The remeshing pipeline (remesh.h): any mesh -> semi-regular mesh close to its surface.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "meshlift/decimate.h"
#include "meshlift/mesh_io.h"
#include "meshlift/metric.h"
#include "meshlift/remesh.h"
#include "meshlift/surface_fit.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// A wavy square sheet with one boundary loop: an n x n grid with z = 0.1 sin(4x) cos(3y).
TriangleMesh wavy_sheet(int n) {
  TriangleMesh m = test::grid(n);
  for (std::size_t v = 0; v < m.vertex_count(); ++v)
    m.positions[3 * v + 2] = 0.1 * std::sin(4 * m.positions[3 * v]) * std::cos(3 * m.positions[3 * v + 1]);
  return m;
}

/// How many times a remesh went through a stage (RemeshResult::stage_seconds).
std::ptrdiff_t count(const RemeshResult& r, const std::string& stage) {
  return std::count_if(r.stage_seconds.begin(), r.stage_seconds.end(), [&](const auto& s) { return s.first == stage; });
}

/// A remesh of `input` at L = 3 with nothing recognized, checked to be the input's own midpoint
/// refinement (RemeshResult::input_refined): the same faces, positions and vertex count.
RemeshResult remesh_refined(const TriangleMesh& input, const RemeshOptions& options) {
  RemeshResult r = remesh(input, options);
  CHECK(r.input_refined);
  SemiRegularMesh refined = refine_linear(input, options.levels);
  for (double& x : refined.positions) x = static_cast<float>(x);  // a remesh's positions are floats (remesh.h)
  CHECK(r.mesh.positions == refined.positions);
  CHECK(r.mesh.hierarchy.triangles(options.levels) == refined.hierarchy.triangles(options.levels));
  CHECK(r.flipped_triangles + r.degenerate_triangles == 0);
  return r;
}

/// Options for remeshing small inputs: three levels, the input never taken over as it is.
RemeshOptions small_input_options() {
  RemeshOptions options;
  options.levels = 3;
  options.recognize = false;
  return options;
}

}  // namespace

TEST_CASE("Remeshing a smooth closed surface gives a close semi-regular mesh without folds", "[remesh][pipeline]") {
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 3;
  options.recognize = false;
  const RemeshResult result = remesh(input, options);
  CHECK_FALSE(result.recognized);
  const SemiRegularHierarchy& h = result.mesh.hierarchy;
  CHECK(h.levels() == 3);
  CHECK(result.base_vertices == h.vertex_count(0));
  CHECK(result.flipped_triangles == 0);
  CHECK(result.degenerate_triangles == 0);
  // Its positions are what a mesh file stores (32-bit floats), so the counts above are the file's.
  CHECK(std::all_of(result.mesh.positions.begin(), result.mesh.positions.end(),
                    [](double x) { return static_cast<float>(x) == x; }));
  const FoldOvers recounted = find_fold_overs(result.mesh.finest(), SurfaceQuery(input));
  CHECK(recounted.flipped.size() + recounted.degenerate.size() == 0);
  // The output is in level order: its hierarchy comes back from the file alone.
  const auto again = recover_level_ordered(result.mesh.finest());
  REQUIRE(again.has_value());
  CHECK(again->hierarchy.levels() == 3);
  const SurfaceDistance d = surface_distance(input, result.mesh.finest());
  INFO("PSNR " << d.psnr_db() << " dB, " << h.vertex_count(3) << " vertices");
  CHECK(d.psnr_db() > 70);
  // Stage times, in pipeline order (the automatic density runs the stages once or twice).
  REQUIRE(result.stage_seconds.size() >= 3);
  CHECK(result.stage_seconds.front().first == "decimate");
  CHECK(result.stage_seconds.back().first == "store as float");  // the chosen remesh rounded, last
  CHECK(result.stage_seconds[result.stage_seconds.size() - 2].first == "choose density");
  for (const auto& [stage, seconds] : result.stage_seconds) CHECK(seconds >= 0);
  // Loop fitting of the base brings the start positions closer: not worse than without.
  options.fit = BaseFit::none;
  const RemeshResult unfitted = remesh(input, options);
  CHECK(surface_distance(input, unfitted.mesh.finest()).psnr_db() > 65);
}

TEST_CASE("A base that keeps half the input's vertices or more is the input, refined on it exactly", "[remesh][pipeline]") {
  RemeshOptions options = small_input_options();
  // The icosahedron: its decimation stops at 8 of its 12 vertices. Placed from there it was
  // rounded off (52.5 dB); its own midpoint refinement is the icosahedron.
  const TriangleMesh ico = test::icosahedron();
  const RemeshResult r = remesh_refined(ico, options);
  CHECK(r.base_vertices == 12);
  CHECK(count(r, "the input refined") == 1);
  CHECK(count(r, "place and compare") == 0);
  // On the input but for the rounding of the midpoints to floats (2^-24 of a coordinate at most).
  CHECK(surface_distance(ico, r.mesh.finest()).rms_relative() < 1e-7);
  // A torus of 48 vertices, asked for all of them: the input. Asked for half: what was asked.
  const TriangleMesh torus = test::torus();
  options.base_vertices = 48;
  CHECK(count(remesh_refined(torus, options), "place and compare") == 0);
  options.base_vertices = 24;
  const RemeshResult half = remesh(torus, options);
  CHECK_FALSE(half.input_refined);
  CHECK(half.base_vertices == 24);
  CHECK(count(half, "place and compare") == 1);
  // One level at the automatic density: 2x asks for half the input's vertices, a density's own
  // base, not a floor's (1x, 1.5x and 2x remeshes, not the input's 4x refinement).
  options.base_vertices = 0;
  options.levels = 1;
  const RemeshResult one_level = remesh(test::bumpy_sphere(), options);
  CHECK_FALSE(one_level.input_refined);
  CHECK(one_level.base_vertices <= 1281);
  options.levels = 3;
  // An input face of zero area would refine to degenerate faces: placed instead.
  TriangleMesh flat = test::grid(3);  // (0,0), (0.5,0), (1,0), ... ; face 0 = (0,0), (0.5,0), (0.5,0.5)
  flat.positions[3] = flat.positions[4] = 0.25;  // vertex 1 onto the line from vertex 0 to vertex 4
  const RemeshResult degenerate = remesh(flat, options);
  CHECK_FALSE(degenerate.input_refined);
  CHECK(count(degenerate, "place and compare") >= 1);
}

TEST_CASE("Where the automatic density makes nothing close enough, a small input's own refinement is taken", "[remesh][pipeline]") {
  RemeshOptions options = small_input_options();
  // A coarse torus (48 vertices, faceted): from its 14-vertex base no density reaches 75 dB.
  const TriangleMesh torus = test::torus();
  const RemeshResult r = remesh_refined(torus, options);
  CHECK(count(r, "place and compare") >= 1);  // the densities were tried first
  CHECK(count(r, "the input refined") == 1);
  // Turned off: the closest remesh made, as before.
  options.input_refinement_vertices = 0;
  CHECK_FALSE(remesh(torus, options).input_refined);
  options.input_refinement_vertices = -1;
  CHECK_THROWS_AS(remesh(torus, options), MeshError);
  options.input_refinement_vertices = RemeshOptions{}.input_refinement_vertices;
  // A threshold the placed remesh meets: it is kept.
  options.auto_density_psnr = options.dense_density_psnr = 30;
  CHECK_FALSE(remesh(torus, options).input_refined);
  // An explicit density: what was asked for.
  options.auto_density_psnr = options.dense_density_psnr = 75;
  options.density = 2;
  CHECK_FALSE(remesh(torus, options).input_refined);
  // An input whose refinement would have more than 65,536 vertices (260 x 4^4): not taken.
  options.density = 0;
  options.levels = 4;
  options.auto_density_psnr = options.dense_density_psnr = 500;
  const RemeshResult larger = remesh(test::torus(20, 13), options);
  CHECK_FALSE(larger.input_refined);
  CHECK(count(larger, "the input refined") == 0);
}

TEST_CASE("Remeshing keeps boundaries on the input's boundary", "[remesh][pipeline]") {
  const TriangleMesh input = wavy_sheet(21);
  RemeshOptions options;
  options.levels = 2;
  options.recognize = false;
  const RemeshResult result = remesh(input, options);
  // Two level-2 faces next to one extraordinary base vertex folded here before untangle.cpp.
  CHECK(result.flipped_triangles == 0);
  CHECK(result.degenerate_triangles == 0);
  // Boundary vertices of the result lie on the square's sides (x or y in {0, 1}).
  const TriangleMesh out = result.mesh.finest();
  const TriangleTopology t = TriangleTopology::build(static_cast<std::uint32_t>(out.vertex_count()), out.triangles);
  std::size_t boundary_vertices = 0;
  for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
    if (!t.is_boundary_edge(e)) continue;
    for (int i = 0; i < 2; ++i) {
      const double* p = &out.positions[3 * t.edge_vertices[2 * e + i]];
      const double side = std::min({std::abs(p[0]), std::abs(p[0] - 1), std::abs(p[1]), std::abs(p[1] - 1)});
      CHECK(side < 1e-12);
      ++boundary_vertices;
    }
  }
  CHECK(boundary_vertices > 0);
  CHECK(surface_distance(input, out).psnr_db() > 60);
}

TEST_CASE("Remeshing rejects what it cannot remesh with the validator's message", "[remesh][pipeline]") {
  TriangleMesh soup = test::icosahedron();
  soup.triangles.insert(soup.triangles.end(), {0, 1, 2});  // a third face on edge (0, 1)... and a duplicate
  CHECK_THROWS_AS(remesh(soup), MeshError);
  RemeshOptions options;
  options.levels = 13;
  CHECK_THROWS_AS(remesh(test::icosahedron(), options), MeshError);
  // The last resort's options, checked before any work (not after the remesh, where they are used).
  options = {};
  options.fold_search.first_rings = 0;
  CHECK_THROWS_AS(remesh(test::icosahedron(), options), MeshError);
  options = {};
  options.fold_search.attempts = 0;
  CHECK_THROWS_AS(remesh(test::icosahedron(), options), MeshError);
}

TEST_CASE("Remeshing development meshes leaves no folded face and stays close", "[corpus][remesh][pipeline]") {
  // L = 3, base for ~4x the input's vertices (the table of RESULTS). The PSNR floors are the figures
  // of docs/RESULTS.md less half a decibel; cow and mannequin-devil still fold where they pass
  // through themselves (the next test holds cow to that). Camel and turbine fold nowhere since the refinement
  // is placed from two guides (were 8 and 8 folds, 76.0 and 53.7 dB); turbine is 80.9 dB since
  // level 1 is placed on normal lines (was 60.8) and 81.9 since strays are placed again
  // (surface_fit.h), fandisk 77.7 (was 78.7: the price of details
  // with no tangential part, which code in fewer bits).
  const std::pair<const char*, double> meshes[] = {{"fandisk", 77.2}, {"homer", 79.0},     {"elephant", 69.4}, {"knot1", 75.4},
                                                   {"lion-head", 81.5}, {"camel", 83.5}, {"turbine", 81.4}};
  for (const auto& [name, floor_db] : meshes) {
    DYNAMIC_SECTION(name) {
      const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path(name)));
      RemeshOptions options;
      options.density = 4;
      const RemeshResult result = remesh(input, options);
      CHECK(result.density == 4);
      CHECK(result.flipped_triangles == 0);
      CHECK(result.degenerate_triangles == 0);
      CHECK(result.input_crossing_pairs == (std::string(name) == "camel" ? 20u : 0u));  // camel crosses itself in one spot, and folds nowhere
      CHECK(surface_distance(input, result.mesh.finest()).psnr_db() > floor_db);
    }
  }
}

TEST_CASE("Development meshes that still fold fold only where the input passes through itself", "[corpus][remesh][pipeline][heavy]") {
  // Cow's tail passes through its body: 89 pairs of its faces cross (self_intersection.h), and
  // a remesh face there may have one of those as the closest input face to its centroid, where
  // no orientation agrees with both sheets; mannequin-devil (1643 pairs) likewise (its automatic
  // density is this 4x). The bounds are the current counts, so that a change that folds more is
  // seen: cow 0 and mannequin-devil 0 of ~103,000 (4 before the last resort, search_unfolded():
  // its 3 searches at the crossings unfold all 4). The untangling's vertex passes search the
  // fold test itself where their linear program finds nothing (before that 2 and 7, and 8 for
  // mannequin-devil while degenerate faces counted as folded without that search:
  // docs/RESULTS.md, "Direct search"); since its patches also try relaxation on the input,
  // mannequin-devil folds 4 for 3 (76.33 dB for 76.30: "Relaxation"). Before the untangling's
  // patches tried the input's own flattening (InputChart, untangle.cpp), cow folded 8 faces and
  // mannequin-devil 15, one of them away from its crossings. Cow's 4x base stops above its size (193 vertices for 182), so the
  // missing-parts step keeps 8 input vertices in it: 67.1 dB (66.1 without).
  const std::tuple<const char*, std::size_t, std::size_t, double> meshes[] = {{"cow", 89, 0, 66.5},
                                                                              {"mannequin-devil", 1643, 0, 75.8}};
  for (const auto& [name, crossing_pairs, most_folds, floor_db] : meshes) {
    DYNAMIC_SECTION(name) {
      const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path(name)));
      RemeshOptions options;
      options.density = 4;
      const RemeshResult result = remesh(input, options);
      CHECK(result.input_crossing_pairs == crossing_pairs);
      CHECK(result.flipped_where_input_crosses == result.flipped_triangles);
      CHECK(result.flipped_triangles <= most_folds);
      CHECK(result.degenerate_triangles == 0);
      CHECK(surface_distance(input, result.mesh.finest()).psnr_db() > floor_db);
    }
  }
}

TEST_CASE("A small CAD input whose remesh folds is refined as it is instead", "[corpus][remesh][pipeline]") {
  // ALSTOM_TEST4 (1,138 vertices): its automatic remesh kept 12 folded faces, 3 away from the
  // input's crossings, at 79.1 dB. Its refinement has 65,986 vertices: over the bound for a
  // remesh merely short of 75 dB (65,536), within the one for a failed remesh (16 times that).
  const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path("ALSTOM_TEST4")));
  RemeshOptions options;
  const RemeshResult result = remesh(input, options);
  CHECK(result.input_refined);
  CHECK(result.flipped_triangles == 0);
  CHECK(result.degenerate_triangles == 0);
  CHECK(result.mesh.hierarchy.vertex_count(3) > options.input_refinement_vertices);
  CHECK(surface_distance(input, result.mesh.finest()).psnr_db() > 140);  // 165.6: the midpoints rounded to floats
  options.input_refinement_vertices = 0;  // off: the failed remesh, as before
  const RemeshResult before = remesh(input, options);
  CHECK_FALSE(before.input_refined);
  CHECK(before.flipped_triangles > before.flipped_where_input_crosses);
  // Of its 12 folded faces, 9 are at the input's crossings and 2 next to them; the last resort
  // (untangle.h, search_unfolded) searches around all 12, the one elsewhere first, and unfolds
  // that one and one at the crossings (where no orientation faces both sheets, most stay).
  CHECK(before.folds_searched == 12);
  CHECK(before.folds_mended_by_search == 2);
  CHECK(before.flipped_triangles == before.flipped_where_input_crosses + before.flipped_near_input_crossings);
  // The report's count of those turned over on the remesh itself is count_turned_over's of its
  // flipped faces.
  {
    const TriangleMesh finest = before.mesh.finest();
    const FoldOvers folds = find_fold_overs(finest, SurfaceQuery(input));
    CHECK(folds.flipped.size() == before.flipped_triangles);
    CHECK(before.flipped_turned_over == count_turned_over(finest, folds.flipped));
    CHECK(before.flipped_turned_over > 0);
    CHECK(before.flipped_turned_over < before.flipped_triangles);
  }
  options.fold_search.evaluations = 0;  // without it, those two stay folded
  const RemeshResult unsearched = remesh(input, options);
  CHECK(unsearched.folds_searched == 0);
  CHECK(unsearched.flipped_triangles == before.flipped_triangles + 2);
  CHECK(unsearched.flipped_triangles == 12);
}

TEST_CASE("Turbine at ~16x: no folded face, within 85 dB", "[corpus][remesh][pipeline][heavy]") {
  // Turbine's disk and blades are a few base edges thick at ~16x. The untangling's vertex passes
  // left 5 folded faces there (85.84 dB); their direct search on the fold test, where the linear
  // program finds nothing, leaves none (85.42 dB; 1 while it tried only points on the input:
  // docs/RESULTS.md, "Direct search").
  const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path("turbine")));
  RemeshOptions options;
  options.density = 16;
  const RemeshResult result = remesh(input, options);
  CHECK(result.flipped_triangles == 0);
  CHECK(result.degenerate_triangles == 0);
  CHECK(surface_distance(input, result.mesh.finest()).psnr_db() > 85);
}

TEST_CASE("The automatic density takes 3x where 2x misses a part, folds at the input's crossings allowed", "[corpus][remesh][pipeline]") {
  // Camel's 2x remesh misses a part (59 dB); its 3x one is 81.8 dB from the input with one
  // flipped face where the input passes through itself (20 crossing face pairs), which does not
  // count against it: it is kept before 4x (docs/RESULTS.md: BD-rate -64.3 -> -66.4 %).
  const TriangleMesh input = to_triangle_mesh(read_mesh(test::corpus_mesh_path("camel")));
  const RemeshResult result = remesh(input, RemeshOptions{});
  CHECK(result.density == 3);
  CHECK(result.flipped_triangles == result.flipped_where_input_crosses);
  CHECK(result.degenerate_triangles == 0);
  CHECK(surface_distance(input, result.mesh.finest()).psnr_db() >= RemeshOptions{}.middle_density_psnr);
}

TEST_CASE("The automatic base size follows the density asked for", "[remesh][pipeline]") {
  const TriangleMesh input = test::icosphere(5);  // 10,242 vertices
  // ceil(density * V / 4^L).
  CHECK(automatic_remesh_base(input, 3) == 641);
  CHECK(automatic_remesh_base(input, 3, 4) == 641);
  CHECK(automatic_remesh_base(input, 3, 2) == 321);
  CHECK(automatic_remesh_base(input, 3, 16) == 2561);
  CHECK(automatic_remesh_base(input, 3, 1) == 161);
  CHECK_THROWS_AS(automatic_remesh_base(input, 3, 0.5), MeshError);
  CHECK_THROWS_AS(automatic_remesh_base(input, 3, std::nan("")), MeshError);
  RemeshOptions options;
  options.density = -1;
  CHECK_THROWS_AS(remesh(input, options), MeshError);
  options.density = 0.5;
  CHECK_THROWS_AS(remesh(input, options), MeshError);
}

TEST_CASE("The automatic density keeps the sparser remesh only when it is close enough", "[remesh][pipeline][heavy]") {
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 2;
  options.recognize = false;
  options.input_refinement_vertices = 0;  // thresholds no remesh meets below: the ladder, not the input's refinement
  REQUIRE(options.density == 0);  // automatic by default
  MetricOptions metric;
  metric.samples = 200'000;
  // A smooth surface: the 2x remesh is within the threshold, and it is what comes back (when it
  // is not far within: see below). The set-aside by the guides alone is off until the end.
  options.auto_density_psnr = 60;
  options.sparsest_density_psnr = 500;
  options.sparsest_guide_psnr = std::numeric_limits<double>::infinity();
  const RemeshResult sparse = remesh(input, options);
  CHECK(sparse.density == 2);
  CHECK(surface_distance(input, sparse.mesh.finest(), metric).psnr_db() >= 60);
  CHECK(sparse.mesh.positions == [&] {
    RemeshOptions two = options;
    two.density = 2;
    return remesh(input, two).mesh.positions;
  }());
  CHECK(count(sparse, "place, then set aside") == 0);
  // Far within the threshold as first placed: the 2x remesh is set aside, and the sparser
  // densities come first, 1x then 1.5x, the first within the threshold kept; the 2x one is not
  // finished.
  options.sparsest_density_psnr = 60;
  const RemeshResult sparsest = remesh(input, options);
  const double sparsest_db = surface_distance(input, sparsest.mesh.finest(), metric).psnr_db();
  CHECK(sparsest.density == 1);
  CHECK(sparsest_db >= 60);
  CHECK(sparsest.mesh.hierarchy.vertex_count(0) < sparse.mesh.hierarchy.vertex_count(0));
  CHECK(count(sparsest, "place, then set aside") == 1);
  CHECK(count(sparsest, "least squares and untangle") == 1);
  // 1x not within the threshold: 1.5x.
  options.auto_density_psnr = sparsest_db + 0.5;
  const RemeshResult sparser = remesh(input, options);
  const double sparser_db = surface_distance(input, sparser.mesh.finest(), metric).psnr_db();
  CHECK(sparser.density == 1.5);
  CHECK(sparser_db >= sparsest_db + 0.5);
  CHECK(sparser.mesh.hierarchy.vertex_count(0) < sparse.mesh.hierarchy.vertex_count(0));
  CHECK(sparser.mesh.hierarchy.vertex_count(0) > sparsest.mesh.hierarchy.vertex_count(0));
  // 1.5x not within either: the 2x one set aside is finished after all, the same remesh.
  options.auto_density_psnr = sparser_db + 0.5;
  const RemeshResult set_aside = remesh(input, options);
  CHECK(set_aside.density == 2);
  CHECK(count(set_aside, "place, then set aside") == 1);
  CHECK(set_aside.mesh.positions == sparse.mesh.positions);
  // A guide that close already: set aside without being placed, the same choice.
  options.auto_density_psnr = 60;
  options.sparsest_guide_psnr = 0;
  const RemeshResult unplaced = remesh(input, options);
  CHECK(count(unplaced, "guides, then set aside") == 1);
  CHECK(count(unplaced, "place, then set aside") == 0);
  CHECK(unplaced.density == 1);
  CHECK(unplaced.mesh.positions == sparsest.mesh.positions);
  options.sparsest_guide_psnr = std::numeric_limits<double>::infinity();
  options.sparsest_density_psnr = 500;
  // A threshold no 2x remesh reaches: the 3x one when it reaches its own (identical to asking
  // for density 3), else the 4x one (identical to asking for density 4) when it is the closest
  // and reaches dense_density_psnr, else the denser ones in turn while the one kept is short of
  // it (each identical to asking for its density).
  options.auto_density_psnr = 500;
  options.middle_density_psnr = 60;
  const RemeshResult middle = remesh(input, options);
  CHECK(middle.density == 3);
  CHECK(surface_distance(input, middle.mesh.finest(), metric).psnr_db() >= 60);
  options.middle_density_psnr = surface_distance(input, middle.mesh.finest(), metric).psnr_db() + 0.5;
  options.dense_density_psnr = 0;
  const RemeshResult dense = remesh(input, options);
  CHECK(dense.density == 4);
  const double dense_db = surface_distance(input, dense.mesh.finest(), metric).psnr_db();
  std::vector<RemeshResult> asked;  // at each denser density, asked for
  std::vector<double> denser_db;
  for (const double density : kDenserAutoDensities) {
    RemeshOptions fixed = options;
    fixed.density = density;
    asked.push_back(remesh(input, fixed));
    REQUIRE(asked.back().flipped_triangles == 0);
    denser_db.push_back(surface_distance(input, asked.back().mesh.finest(), metric).psnr_db());
  }
  REQUIRE(denser_db[0] > dense_db);
  REQUIRE(denser_db[1] > denser_db[0]);
  options.dense_density_psnr = denser_db[0];  // 4x short of it, 6x reaches it: no further step
  const RemeshResult denser = remesh(input, options);
  CHECK(denser.density == kDenserAutoDensities[0]);
  CHECK(denser.mesh.hierarchy.vertex_count(0) > dense.mesh.hierarchy.vertex_count(0));
  options.dense_density_psnr = denser_db[0] + 0.01;  // 6x short of it too: 8x
  const RemeshResult densest = remesh(input, options);
  CHECK(densest.density == kDenserAutoDensities[1]);
  CHECK(densest.mesh.positions == asked[1].mesh.positions);
  CHECK(denser.mesh.positions == asked[0].mesh.positions);
  options.density = 4;
  CHECK(remesh(input, options).mesh.positions == dense.mesh.positions);
  options.density = 3;
  CHECK(remesh(input, options).mesh.positions == middle.mesh.positions);
  // A base size given: no density.
  options.density = 0;
  options.base_vertices = 100;
  CHECK(remesh(input, options).density == 0);
}

TEST_CASE("The automatic density remeshes once a base that every density's decimation stops at", "[remesh][pipeline]") {
  // Five levels over a 2,562-vertex sphere: the decimation stops at the same 8 vertices for the
  // targets of 1x, 1.5x and 2x, so they have one base. Set aside, the 2x remesh would be made
  // three times over, as 1x, as 1.5x, then finished.
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 5;
  options.recognize = false;
  options.missing_part_rounds = 0;
  options.level_by_level_from = 0;  // the automatic density's own choices at L = 5
  options.sparsest_density_psnr = 0;  // every 2x remesh with sparser bases is set aside
  DecimateOptions two;
  two.levels = options.levels;
  two.target_vertices = automatic_remesh_base(input, options.levels, 2);
  const std::size_t base = decimate(input, two).base.vertex_count();
  for (const double density : kSparserAutoDensities) {
    DecimateOptions sparser = two;
    sparser.target_vertices = automatic_remesh_base(input, options.levels, density);
    REQUIRE(decimate(input, sparser).base.vertex_count() == base);
  }
  const RemeshResult r = remesh(input, options);
  CHECK(count(r, "place, then set aside") == 0);
  CHECK(count(r, "guides, then set aside") == 0);
  CHECK(count(r, "least squares and untangle") == 1);
  CHECK(r.density == 2);
  CHECK(r.mesh.hierarchy.vertex_count(0) == base);
  options.density = 2;
  CHECK(remesh(input, options).mesh.positions == r.mesh.positions);
}

TEST_CASE("The automatic density gives up a candidate that cannot qualify after its first placement, and chooses as if it had finished it", "[remesh][pipeline]") {
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 2;
  options.recognize = false;
  // Thresholds no 2x or 3x remesh reaches: both are given up after their first placement, the
  // 4x one is finished and kept, as when nothing is given up. (On this smooth sphere the
  // finished 4x remesh is not 10 dB closer than the 2x one as first placed, so with the
  // default margin the given-up ones would be finished after all, as below: with a margin of
  // 0 they stay given up.) No 2x placement is set aside for sparser ones here.
  options.sparsest_density_psnr = std::numeric_limits<double>::infinity();
  options.give_up_margin = 0;
  options.auto_density_psnr = 500;
  options.middle_density_psnr = 500;
  options.dense_density_psnr = 0;
  const RemeshResult given_up = remesh(input, options);
  CHECK(count(given_up, "place, then give up") == 2);
  CHECK(count(given_up, "least squares and untangle") == 1);
  RemeshOptions never = options;
  never.give_up_margin = std::numeric_limits<double>::infinity();
  const RemeshResult finished = remesh(input, never);
  CHECK(count(finished, "place, then give up") == 0);
  CHECK(count(finished, "least squares and untangle") == 3);
  CHECK(given_up.density == 4);
  CHECK(given_up.density == finished.density);
  CHECK(given_up.mesh.positions == finished.mesh.positions);
  // A margin so wide that the given-up ones could still be closer than the 4x remesh: they are
  // finished after all, and the closest of the three is kept, as when nothing is given up.
  options.give_up_margin = 1000;
  options.auto_density_psnr = options.middle_density_psnr = 2000;
  never.auto_density_psnr = never.middle_density_psnr = 2000;
  const RemeshResult redone = remesh(input, options);
  CHECK(count(redone, "place, then give up") == 2);
  CHECK(count(redone, "least squares and untangle") == 3);
  const RemeshResult closest = remesh(input, never);
  CHECK(redone.density == closest.density);
  CHECK(redone.mesh.positions == closest.mesh.positions);
  options.give_up_margin = std::nan("");
  CHECK_THROWS_AS(remesh(input, options), MeshError);
}

TEST_CASE("The automatic density goes denser where the 4x remesh stays below 75 dB", "[corpus][remesh][pipeline][heavy]") {
  // Elephant's 4x base is 174 vertices: its remesh is 69.9 dB from the input, which would cap the
  // codec's curve below the top of 55-75 dB. At 6x it is 75.9 dB with no fold (docs/RESULTS.md:
  // BD-rate against Draco -30.2 -> -39.2 %), so 8x is not tried. Knot1 (76.0 dB at 4x) stays.
  const TriangleMesh elephant = to_triangle_mesh(read_mesh(test::corpus_mesh_path("elephant")));
  const RemeshResult result = remesh(elephant, RemeshOptions{});
  // Its 2x remesh (on the 3x base too: the decimation stops at 154 vertices) is given up after
  // its first placement (47.5 dB there), and the choice is the one made when every candidate is
  // finished.
  auto given_up = [](const RemeshResult& r) {
    return std::count_if(r.stage_seconds.begin(), r.stage_seconds.end(),
                         [](const auto& s) { return s.first == "place, then give up"; });
  };
  RemeshOptions never;
  never.give_up_margin = std::numeric_limits<double>::infinity();
  CHECK(given_up(result) == 1);
  CHECK(result.mesh.positions == remesh(elephant, never).mesh.positions);
  CHECK(result.density == kDenserAutoDensities[0]);
  CHECK(result.flipped_triangles == 0);
  CHECK(result.degenerate_triangles == 0);
  CHECK(surface_distance(elephant, result.mesh.finest()).psnr_db() >= RemeshOptions{}.dense_density_psnr);
  const TriangleMesh knot = to_triangle_mesh(read_mesh(test::corpus_mesh_path("knot1")));
  CHECK(remesh(knot, RemeshOptions{}).density == 4);
  // Cow's 6x remesh (71.8 dB) folds one face away from its crossings: not kept; its 8x one
  // (74.5 dB) folds only where the input passes through itself.
  const TriangleMesh cow = to_triangle_mesh(read_mesh(test::corpus_mesh_path("cow")));
  const RemeshResult cow_result = remesh(cow, RemeshOptions{});
  // Its one base for 2x to 4x (61.8 dB as first placed) is given up: the denser steps follow.
  CHECK(given_up(cow_result) == 1);
  CHECK(cow_result.mesh.positions == remesh(cow, never).mesh.positions);
  CHECK(cow_result.density == kDenserAutoDensities[1]);
  CHECK(cow_result.flipped_where_input_crosses == cow_result.flipped_triangles);
  CHECK(surface_distance(cow, cow_result.mesh.finest()).psnr_db() > 74);
}

TEST_CASE("Where the base stops above its size, parts the remesh missed are kept in the base", "[corpus][remesh][pipeline][heavy]") {
  // Elephant at L = 4: the decimation stops at 154 vertices (its checks refuse every further
  // collapse), above the automatic density's bases, and that base has no vertex on a foot: the
  // remesh passes it by (59.7 dB, 96 % of the squared error in two base faces; docs/RESULTS.md).
  // Keeping the input vertices farthest from the remesh in the base brings it back.
  const TriangleMesh elephant = to_triangle_mesh(read_mesh(test::corpus_mesh_path("elephant")));
  RemeshOptions options;
  options.levels = 4;
  options.density = 4;
  const RemeshResult kept = remesh(elephant, options);
  options.missing_part_rounds = 0;
  const RemeshResult missed = remesh(elephant, options);
  const double kept_db = surface_distance(elephant, kept.mesh.finest()).psnr_db();
  const double missed_db = surface_distance(elephant, missed.mesh.finest()).psnr_db();
  INFO("kept " << kept_db << " dB, " << kept.kept_vertices << " vertices kept; missed " << missed_db << " dB");
  CHECK(missed.kept_vertices == 0);
  CHECK(missed_db < 65);
  CHECK(kept.kept_vertices > 0);
  CHECK(kept_db >= 75);
  CHECK(kept.flipped_triangles == 0);
  CHECK(kept.base_vertices > missed.base_vertices);
  // Where the base reaches its size nothing changes: elephant at L = 3, 6x, byte for byte.
  RemeshOptions three;
  three.density = 6;
  const RemeshResult reached = remesh(elephant, three);
  three.missing_part_rounds = 0;
  CHECK(reached.kept_vertices == 0);
  CHECK(reached.mesh.positions == remesh(elephant, three).mesh.positions);
}

TEST_CASE("A deep hierarchy over the base of a level fewer is that remesh refined once more", "[remesh][pipeline]") {
  // Three levels over a 12-vertex base of the bumpy sphere, the third placed on the finished
  // remesh of two (RemeshOptions::level_by_level_from = 3): the same base as placed directly,
  // fold-free, and closer to the input than the remesh of two levels it was made from.
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 3;
  options.recognize = false;
  options.base_vertices = 12;
  options.level_by_level_from = 3;
  std::vector<double> fractions;  // the progress reported: never back, up to 1
  options.progress = [&](double f) { fractions.push_back(f); };
  const RemeshResult deep = remesh(input, options);
  options.progress = nullptr;
  CHECK(std::is_sorted(fractions.begin(), fractions.end()));
  REQUIRE_FALSE(fractions.empty());
  CHECK(fractions.back() == 1);
  CHECK(deep.direct_levels == 2);
  CHECK(count(deep, "refine once more") == 1);
  CHECK(count(deep, "search the folds") == 1);  // the remesh of two levels, before it is refined
  CHECK(deep.flipped_triangles + deep.degenerate_triangles == 0);
  options.level_by_level_from = 0;
  const RemeshResult direct = remesh(input, options);
  CHECK(direct.direct_levels == 3);
  CHECK(count(direct, "refine once more") == 0);
  CHECK(deep.mesh.hierarchy.triangles(0) == direct.mesh.hierarchy.triangles(0));
  CHECK(deep.mesh.hierarchy.triangles(3) == direct.mesh.hierarchy.triangles(3));
  options.levels = 2;
  const RemeshResult two = remesh(input, options);
  const double deep_db = surface_distance(input, deep.mesh.finest()).psnr_db();
  const double two_db = surface_distance(input, two.mesh.finest()).psnr_db();
  INFO("three levels, level by level " << deep_db << " dB; two levels " << two_db << " dB");
  CHECK(deep_db > two_db + 6);  // four times the vertices: about 12 dB where the error is O(h^2)
  // A base of its own at each level: placed directly. The automatic density's 2x base at L = 3
  // for this 2,562-vertex input is reached (80 vertices), below that of two levels (320).
  RemeshOptions automatic;
  automatic.levels = 3;
  automatic.recognize = false;
  automatic.level_by_level_from = 3;
  CHECK(remesh(input, automatic).direct_levels == 3);
  automatic.level_by_level_from = -1;
  CHECK_THROWS_AS(remesh(input, automatic), MeshError);
}

TEST_CASE("A deep hierarchy at an explicit density, or over an input refined as it is", "[remesh][pipeline]") {
  // --density 1 at L = 6 over the 2,562-vertex sphere: the decimation stops at its floor (8
  // vertices), which is also the base of 5 levels at that density, and of 4 levels not (11):
  // levels 1-5 placed from the base, the sixth on their remesh. The base is decimated once at
  // each level, for its check (at L = 5 the remesh then takes that base, not a second one).
  const TriangleMesh input = test::bumpy_sphere();
  RemeshOptions options;
  options.levels = 6;
  options.recognize = false;
  options.density = 1;
  const RemeshResult deep = remesh(input, options);
  CHECK(deep.direct_levels == 5);
  CHECK(deep.base_vertices == 8);
  CHECK(count(deep, "decimate") == 2);
  CHECK(count(deep, "refine once more") == 1);
  CHECK(deep.flipped_triangles + deep.degenerate_triangles == 0);
  // The icosahedron at L = 4: its remesh of 3 levels is the input refined (its decimation keeps
  // 8 of its 12 vertices), not refined once more but made again at L = 4 by the same rule, its
  // time listed as one stage.
  RemeshOptions four = small_input_options();
  four.levels = 4;
  const RemeshResult exact = remesh_refined(test::icosahedron(), four);
  CHECK(count(exact, "a level fewer, not refined") == 1);
  CHECK(exact.direct_levels == 0);
}

TEST_CASE("An explicit density whose decimation stops at its floor refines a remesh of a level fewer over that base", "[remesh][pipeline]") {
  // A 45 x 11 torus (495 vertices) at --density 4, L = 4: the decimation stops at 19 vertices,
  // above the 14 this level asks for (the topology's floor) and below the 31 that 4x of 3 levels
  // would. The remesh of 3 levels is made with this level's base size, so its missing-parts step
  // runs there, and then refined once more. Placed from the floor base directly it is farther
  // from the input.
  const TriangleMesh input = test::torus(45, 11);
  RemeshOptions options;
  options.levels = 4;
  options.density = 4;
  std::vector<double> fractions;
  options.progress = [&](double f) { fractions.push_back(f); };
  const RemeshResult deep = remesh(input, options);
  options.progress = nullptr;
  CHECK(std::is_sorted(fractions.begin(), fractions.end()));
  REQUIRE_FALSE(fractions.empty());
  CHECK(fractions.back() == 1);
  CHECK(deep.direct_levels == 3);
  CHECK(count(deep, "refine once more") == 1);
  CHECK(deep.density == 4);
  CHECK(deep.target_base_vertices == 14);
  CHECK(deep.kept_vertices > 0);
  CHECK(deep.base_vertices > 19);
  CHECK(deep.flipped_triangles + deep.degenerate_triangles == 0);
  options.level_by_level_from = 0;
  const RemeshResult direct = remesh(input, options);
  CHECK(direct.direct_levels == 4);
  const double deep_db = surface_distance(input, deep.mesh.finest()).psnr_db();
  const double direct_db = surface_distance(input, direct.mesh.finest()).psnr_db();
  INFO("over the floor base, a level at a time " << deep_db << " dB; placed from it " << direct_db << " dB");
  CHECK(deep_db > direct_db);
}

TEST_CASE("At an explicit density, a refinement over the floor base that folds is set aside for the remesh placed from the base", "[corpus][remesh][pipeline][heavy]") {
  // Fandisk at --density 4, L = 5: its decimation stops at 53 vertices, above the 26 asked for
  // and below the 102 of 4x at L = 4. Made a level at a time over that base (feature lines
  // followed), the remesh folds 6 faces at 87.2 dB; placed from the base, none at 74.1 dB.
  const TriangleMesh fandisk = to_triangle_mesh(read_mesh(test::corpus_mesh_path("fandisk")));
  RemeshOptions options;
  options.levels = 5;
  options.density = 4;
  const RemeshResult r = remesh(fandisk, options);
  INFO(r.set_aside_refinement_folds << " folds set aside");
  CHECK(r.set_aside_refinement_folds > 0);
  CHECK(count(r, "refine once more") > 0);
  CHECK(r.direct_levels == 5);
  CHECK(r.flipped_triangles + r.degenerate_triangles == 0);
  CHECK(surface_distance(fandisk, r.mesh.finest()).psnr_db() > 70);
}

TEST_CASE("Where the base stops above its size, remesh faces far from the input bring their input vertices into the base", "[corpus][remesh][pipeline][heavy]") {
  // Turbine at L = 4: its floor base spans the gaps between blades, and the remesh fills them
  // with sheets far from the input (53.7 dB, 9 folded faces); the input vertices nearest those
  // faces, kept in the base, take it back onto the blades: 80.4 dB with 24 kept, and no fold
  // since the untangling's patches try relaxation on the input (UntangleOptions::
  // relaxation_steps; 81.1 dB with 16 kept and 2 folded faces before). The rounds go on past one
  // that is closer but folds more, not kept (a round not kept passes its vertices on).
  // Asked for L = 5, the decimation stops at the same floor, and that L = 4 remesh is refined
  // once more (RemeshOptions::level_by_level_from): 89.2 dB, no fold (placed from its own base
  // instead: 56.6 dB, 79 folded faces).
  const TriangleMesh turbine = to_triangle_mesh(read_mesh(test::corpus_mesh_path("turbine")));
  RemeshOptions deep;
  deep.levels = 5;
  const RemeshResult blades = remesh(turbine, deep);
  const double db = surface_distance(turbine, blades.mesh.finest()).psnr_db();
  INFO("turbine " << db << " dB, " << blades.flipped_triangles << " folds, " << blades.kept_vertices << " vertices kept");
  CHECK(blades.direct_levels == 4);
  CHECK(blades.kept_vertices > 0);
  CHECK(db >= 85);
  CHECK(blades.flipped_triangles == 0);
  CHECK(blades.degenerate_triangles == 0);
}
