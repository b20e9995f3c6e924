// Any triangle mesh -> semi-regular mesh (remesh.h). The pipeline, each stage in its own file:
//   recover_hierarchy.cpp  the input already is a refinement: take it over as it is;
//   decimate.cpp           else quadric decimation to the base mesh (vertices on the input);
//   interpolate.cpp        --fit loop: control points whose Loop limit surface passes through
//                          the base vertices (seed 000);
//   lifting.cpp, limit.cpp the guide: the Loop limit surface of those control points, sampled at
//                          every vertex of the L-times refined base;
//   surface_fit.cpp        coarse to fine, the new vertices of each level are placed on the
//                          input by normal shooting from the guide (or the butterfly prediction
//                          from the level below), level 1 then on the codec's normal lines
//                          where that folds nothing (details with no tangential part as
//                          placed; the least-squares fit adds a little), and
//                          folded faces are untangled;
//   untangle.cpp           patches of folded faces are re-embedded (Tutte) and put back on
//                          the input;
//   least_squares_fit.cpp  the vertices move off the surface where that brings the mesh
//                          closer to it in the least-squares sense, both ways (Hoppe 1993);
//                          then untangle.cpp once more.
//   With --fit loop the refinement is placed from two guides (the fitted limit surface, and one
//   that takes the unfitted limit where that is closer to the input); the placement with fewest
//   folds goes on, one with normal lines among equals, then the one closer to the input.
//   (geometry_image.cpp    --method sphere: the octahedral spherical geometry image instead.)
#include "meshlift/remesh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include "meshlift/closest_point.h"
#include "meshlift/decimate.h"
#include "meshlift/features.h"
#include "meshlift/geometry_image.h"
#include "meshlift/interpolate.h"
#include "meshlift/least_squares_fit.h"
#include "meshlift/lifting.h"
#include "meshlift/limit.h"
#include "meshlift/metric.h"
#include "meshlift/self_intersection.h"
#include "meshlift/snap.h"
#include "meshlift/spherical_parametrization.h"
#include "meshlift/surface_fit.h"
#include "meshlift/untangle.h"
#include "meshlift/validate.h"
#include "meshlift/weld.h"
#include "parallel.h"
#include "vec3.h"

namespace meshlift {

namespace {

/// Appends (stage, seconds since the previous lap) to a list of stage times.
class StageClock {
 public:
  explicit StageClock(std::vector<std::pair<std::string, double>>& stages) : stages_(stages) {}
  void lap(const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    stages_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  std::vector<std::pair<std::string, double>>& stages_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// Samples a side of the PSNR the automatic choices compare (±0.01 dB, METRIC.md) ...
constexpr std::size_t kChoiceSamples = 200'000;
/// ... and of the quick one that tells a first placement far from the input (a tenth of the
/// cost, about ±0.03 dB, against RemeshOptions::give_up_margin).
constexpr std::size_t kQuickSamples = 20'000;

/// The missing-parts step (RemeshOptions::missing_part_rounds) keeps at most this many input
/// vertices a round, each at least kMissingPartSpacing of the diagonal from the others of its
/// round: one or two per missed part (elephant's four feet at L = 4: 13 in all), not a cluster
/// around the worst one. Measured on the corpus at L = 4 and 5 (docs/RESULTS.md).
constexpr std::size_t kMissingPartsPerRound = 8;
constexpr double kMissingPartSpacing = 0.05;

/// PSNRs of remeshes against the input on `samples` area samples a side, without the vertices
/// (they enter only the Hausdorff distance: MetricOptions::vertices): surface_distance()'s
/// values, with the input's samples made once per sample count for all the remeshes compared.
class InputPsnr {
 public:
  explicit InputPsnr(const TriangleMesh& input) : input_(input) {}
  double operator()(const TriangleMesh& remeshed, std::size_t samples = kChoiceSamples) {
    MetricOptions metric;
    metric.samples = samples;
    metric.vertices = false;
    auto at = sampled_.find(samples);
    if (at == sampled_.end())
      at = sampled_.emplace(samples, SampledSurface(input_, samples, metric.seed, metric.threads, metric.vertices)).first;
    return surface_distance(at->second, remeshed, metric).psnr_db();
  }
  double operator()(const SemiRegularMesh& remeshed, std::size_t samples = kChoiceSamples) {
    return (*this)(remeshed.finest(), samples);
  }

 private:
  const TriangleMesh& input_;
  std::map<std::size_t, SampledSurface> sampled_;  // by sample count
};

/// Puts the vertices of `guide` (xyz per vertex of the finest level) that `features` places on
/// the feature lines at their places there (features.h).
void hold_on_features(const FeaturePlacement& features, std::span<double> guide) {
  for (std::size_t v = 0; v < features.fixed.size(); ++v)
    if (features.fixed[v]) std::copy_n(features.positions.begin() + 3 * std::ptrdiff_t(v), 3, guide.begin() + 3 * std::ptrdiff_t(v));
}

/// The untangling right after a placement: patches only, and no relaxation: the least-squares
/// rounds move every vertex again, and per-vertex moves made before them shifted their result
/// for no fewer folds after (camel -0.3 dB); a patch relaxed there cost cow's 8x remesh 1.7 dB
/// (76.2 -> 74.4).
void untangle_patches(SemiRegularMesh& mesh, const SurfaceQuery& surface, std::span<const std::uint8_t> fixed) {
  UntangleOptions patches_only;
  patches_only.vertex_passes = 0;
  patches_only.relaxation_steps = 0;
  patches_only.rounds = 1;
  patches_only.fixed = fixed;
  untangle(mesh, surface, patches_only);
}

/// Places the refined base on the surface from `guide` and untangles its folded patches.
SemiRegularMesh place_refinement(const SemiRegularHierarchy& hierarchy, const std::vector<double>& guide,
                                 bool normal_lines, const SurfaceQuery& surface, std::span<const std::uint8_t> fixed,
                                 const std::function<void(double)>& report) {
  SemiRegularMesh mesh{hierarchy, {}, {}};
  SurfaceFitOptions fit_options;
  if (!normal_lines) fit_options.normal_line_levels = 0;
  fit_options.progress = report;
  fit_options.fixed = fixed;
  fit_to_surface(mesh, guide, surface, fit_options);
  untangle_patches(mesh, surface, fixed);
  return mesh;
}

/// The last resort, search_unfolded() (untangle.h), around the faces of `folds` (the remesh's
/// folded and degenerate faces): around each one away from the input's crossings first
/// (`crossing`: per input face, 1 where it cuts through another or lies within two rings of one,
/// computed only where needed), where an orientation that faces the input exists; then around
/// those at or next to the crossings, as far as the search's cap on faces
/// (FoldSearchOptions::max_faces) allows. Sets the result's fold counts. Run on the remesh
/// returned (store_as_float) and on the remesh of a level fewer that a deep hierarchy refines once
/// more (remesh_levels()), so that a fold there is not refined into more; the vertices it moves
/// are rounded to floats (search_unfolded()). At L = 6 it leaves
/// turbine, homer, cow and armadillo without a fold. Mannequin-devil, whose input passes through
/// itself, folds 12 faces at L = 4 without it, none with it; at L = 5 110, 54 with it on the
/// remesh returned, 46 with it on the level below too; at L = 6 528, 517, 424 (docs/RESULTS.md,
/// "The folds left at L = 6, mended by a search", and "Folds at the input's crossings searched too").
void search_folds(RemeshResult& result, FoldOvers folds, const SurfaceQuery& surface, const FoldSearchOptions& search,
                  const std::function<const std::vector<std::uint8_t>&()>& crossing) {
  result.folds_searched = result.folds_mended_by_search = 0;  // not those of a level fewer
  if (search.evaluations > 0 && !(folds.flipped.empty() && folds.degenerate.empty())) {
    const std::vector<std::uint8_t>& at_crossing = crossing();
    const std::vector<std::uint32_t>& finest = result.mesh.hierarchy.triangles(result.mesh.hierarchy.levels());
    std::vector<std::uint32_t> faces = folds.degenerate, at_crossings;
    for (const std::uint32_t f : folds.flipped)
      (closest_is_marked(result.mesh.positions, &finest[3 * std::size_t{f}], surface, at_crossing) ? at_crossings : faces)
          .push_back(f);
    faces.insert(faces.end(), at_crossings.begin(), at_crossings.end());
    const FoldSearchReport searched = search_unfolded(result.mesh, surface, faces, search);
    result.folds_searched = searched.tried;
    result.folds_mended_by_search = searched.mended;
    if (searched.mended > 0) folds = find_fold_overs(result.mesh.finest(), surface);
  }
  result.flipped_triangles = folds.flipped.size();
  result.degenerate_triangles = folds.degenerate.size();
}

/// The remesh as a mesh file stores it (mesh_io.h: 32-bit floats, which every reader parses):
/// round_to_float() (surface_fit.h), its fold counts those of the rounded positions. Made on the
/// chosen remesh only: the choices before it (densities, missing parts) are made on the double
/// positions, as before; rounding every candidate instead changed them (turbine at L = 4: 80.4
/// -> 56.8 dB, its missing parts no longer kept), and so does a remesh of a level fewer refined
/// from rounded positions (remesh_levels()).
/// Then, where faces still fold, the last resort (search_folds()).
void store_as_float(RemeshResult& result, const SurfaceQuery& surface, const FoldSearchOptions& search,
                    const std::function<const std::vector<std::uint8_t>&()>& crossing) {
  search_folds(result, round_to_float(result.mesh, surface), surface, search, crossing);
}

/// A placement's last stage: the least-squares fit, then the untangling once more (the solve
/// keeps faces that face the input from turning away, but a face can still end up nearest to
/// another part of the input), and with `snap` the snap onto the input's corners and creases.
/// `features` (per vertex of the finest level, or empty): 1 where a vertex holds its place on a
/// feature line; where a face still folds there, its corners on the line are let go and
/// untangled with the rest.
SnapReport finish_placement(SemiRegularMesh& mesh, const SurfaceQuery& surface, std::span<const std::uint8_t> features,
                            int least_squares_rounds, bool snap) {
  LeastSquaresFitOptions least_squares;
  least_squares.iterations = least_squares_rounds;
  least_squares.fixed = features;
  fit_least_squares(mesh, surface, least_squares);
  std::vector<std::uint8_t> fixed(features.begin(), features.end());
  UntangleOptions untangle_options;
  untangle_options.fixed = fixed;
  untangle(mesh, surface, untangle_options);
  if (std::any_of(fixed.begin(), fixed.end(), [](std::uint8_t f) { return f != 0; })) {
    const FoldOvers folds = find_fold_overs(mesh.finest(), surface);
    const std::vector<std::uint32_t>& finest = mesh.hierarchy.triangles(mesh.hierarchy.levels());
    bool released = false;
    for (const auto* list : {&folds.flipped, &folds.degenerate})
      for (const std::uint32_t f : *list)
        for (int i = 0; i < 3; ++i) {
          const std::uint32_t v = finest[3 * std::size_t{f} + i];
          released |= fixed[v] != 0;
          fixed[v] = 0;
        }
    if (released) untangle(mesh, surface, untangle_options);
  }
  // Last, so that it can add no fold: a snap turns no face away from the input (snap.h). Made
  // before the untangling instead, it changed what that left: mannequin-devil at ~4x 7 folded
  // faces -> 11, cow at ~16x 3 -> 0.
  if (!snap) return {};
  SnapOptions snapping;
  snapping.fixed = fixed;
  return snap_to_input(mesh, surface, snapping);
}

/// `coarse` one level deeper (RemeshOptions::level_by_level_from): its base refined once more,
/// the new vertices shot onto the surface from their butterfly predictions while every vertex of
/// `coarse` holds its place (surface_fit.h, as place_refinement), then the placement finished as
/// one from the base (finish_placement) over all vertices. Where `coarse` follows the feature
/// lines `lines` of `input`, the vertices on them are placed on them at every level and held
/// there (features.h), as remesh_by_decimation places them.
RemeshResult refined_once_more(RemeshResult coarse, const TriangleMesh& input, const FeatureLines& lines,
                               const SurfaceQuery& surface, int least_squares_rounds, bool snap,
                               const std::function<void(double)>& report) {
  const SemiRegularHierarchy& from = coarse.mesh.hierarchy;
  const int levels = from.levels() + 1;
  SemiRegularHierarchy h(TriangleTopology::build(from.vertex_count(0), from.triangles(0)), levels);
  // The hierarchies number their vertices alike up to from's finest level (level by level, a
  // level's new vertices in the order of the edges they split).
  std::vector<std::uint8_t> held(h.vertex_count(levels), 0);
  std::fill_n(held.begin(), from.vertex_count(from.levels()), std::uint8_t{1});
  std::vector<double> guide = std::move(coarse.mesh.positions);
  guide.resize(3 * std::size_t{h.vertex_count(levels)}, 0.0);  // the new level starts at butterfly's prediction
  FeaturePlacement features;
  if (coarse.feature_edges > 0) {
    TriangleMesh base{{}, h.triangles(0)};
    for (const std::uint32_t v : coarse.base_input_vertex)
      base.positions.insert(base.positions.end(), input.positions.begin() + 3 * std::ptrdiff_t{v},
                            input.positions.begin() + 3 * std::ptrdiff_t{v} + 3);
    features = place_on_features(h, input, base, base_feature_edges(lines, coarse.base_input_vertex));
    hold_on_features(features, guide);
    for (std::size_t v = 0; v < features.fixed.size(); ++v) held[v] |= features.fixed[v];
  }
  RemeshResult result = std::move(coarse);  // its base, density and counts; its mesh a level deeper
  result.mesh = SemiRegularMesh{std::move(h), {}, {}};
  SurfaceFitOptions fit_options;
  fit_options.progress = [&](double f) { report(0.4 * f); };
  fit_options.fixed = held;
  fit_to_surface(result.mesh, guide, surface, fit_options);
  untangle_patches(result.mesh, surface, features.fixed);  // the coarser vertices free to move again
  report(0.4);
  const SnapReport snapped = finish_placement(result.mesh, surface, features.fixed, least_squares_rounds, snap);
  const FoldOvers folds = find_fold_overs(result.mesh.finest(), surface);
  result.feature_vertices = features.count();
  result.flipped_triangles = folds.flipped.size();
  result.degenerate_triangles = folds.degenerate.size();
  result.flipped_where_input_crosses = 0;  // counted again at the end (remesh())
  result.snapped_to_vertices = snapped.onto_vertices;
  result.snapped_to_creases = snapped.onto_creases;
  report(1);
  return result;
}

/// remesh_by_decimation's abandon_below for a remesh that is never given up ...
constexpr double kNever = -std::numeric_limits<double>::infinity();
/// ... and its set_aside_at for one that is never set aside.
constexpr double kNowhere = std::numeric_limits<double>::infinity();

/// The input itself as the base, refined `levels` times by midpoint splits: every new vertex on
/// an input edge or face, so the remesh is the input exactly (RemeshResult::input_refined; its
/// midpoints are then rounded to floats with the rest, store_as_float()).
/// nullopt where it folds or degenerates somewhere (an input face of zero area refines to
/// degenerate ones).
std::optional<RemeshResult> input_refinement(const TriangleMesh& mesh, const SurfaceQuery& surface, int levels) {
  DecimateOptions none;
  none.levels = levels;
  none.target_vertices = mesh.vertex_count();
  const DecimateResult input = decimate(mesh, none);  // the input as it stands (no isolated vertex), no collapse
  RemeshResult exact{refine_linear(input.base, levels)};
  const FoldOvers folds = find_fold_overs(exact.mesh.finest(), surface);
  if (!folds.flipped.empty() || !folds.degenerate.empty()) return std::nullopt;
  exact.base_vertices = input.base.vertex_count();
  exact.base_input_vertex = input.original_vertex;
  exact.input_refined = true;
  return exact;
}

/// From the decimated base (`asked_base`: the base size asked for, before any floor): fit the base, build the guide, place the refinement on the surface
/// (level 1 on normal lines where that folds nothing) and untangle it (place_refinement), fit it
/// by least squares, untangle again, and with `snap` move it onto the input's corners and creases
/// (snap.h). With --fit loop there are two guides; the placement that
/// folds fewest faces goes on, one with normal lines among equals, then the closer to the input.
/// A candidate of the automatic density that could only be kept at `abandon_below` dB or more
/// is given up after its first placement (nullopt) when that placement is so far from the input
/// that the rest could not bring it there: its PSNR plus `give_up_margin` is below `abandon_below`
/// (RemeshOptions::give_up_margin). One is set aside after it instead (nullopt) when that
/// placement is `set_aside_at` dB or closer, or before it when one of its guides is
/// `set_aside_guide_at` dB or closer: the automatic density then tries sparser bases first
/// (RemeshOptions::sparsest_density_psnr, sparsest_guide_psnr). `*placed_psnr`, if given,
/// receives the placement's PSNR (kQuickSamples a side) when it stops there, kNowhere when it
/// stops at its guides. kNever, kNowhere: never.
std::optional<RemeshResult> remesh_by_decimation(const TriangleMesh& mesh, const SurfaceQuery& surface,
                                                 InputPsnr& remesh_psnr, const DecimateResult& decimated, std::size_t asked_base,
                                                 const FeatureLines& lines, int levels,
                                                 BaseFit fit, int least_squares_rounds, bool snap, double abandon_below,
                                                 double set_aside_at, double set_aside_guide_at, double give_up_margin,
                                                 double* placed_psnr,
                                                 const std::function<void(double)>& report,
                                                 std::vector<std::pair<std::string, double>>& stages) {
  StageClock clock(stages);
  report(0.1);
  // A base that keeps half the input's vertices or more where less was asked for (`asked_base`,
  // before any floor: a small input, the decimation stopped at or near its topology's floor), or
  // all of them: the input's own midpoint refinement has about as many vertices and lies on the
  // input exactly, where a placement from that base rounds it off (a cube at L = 3: 57 dB; an
  // icosahedron from an 8-vertex base: 52.5 dB).
  const std::size_t kept = decimated.base.vertex_count(), input_vertices = kept + decimated.collapses;
  if (decimated.collapses == 0 || (2 * kept >= input_vertices && 2 * asked_base < input_vertices))
    if (std::optional<RemeshResult> exact = input_refinement(mesh, surface, levels)) {
      clock.lap("the input refined");
      report(1);
      return exact;
    }
  const TriangleMesh& base = decimated.base;

  // Control points of the guide surface: the base itself, or fitted so that the Loop limit
  // surface interpolates the base vertices.
  std::vector<double> control = base.positions;
  if (fit == BaseFit::loop) control = fit_loop(base).control.positions;
  clock.lap("fit base");
  report(0.15);

  // Guide = Loop limit of the control mesh refined L times: Loop subdivision is the Loop
  // wavelet's synthesis with zero details, and a vertex's limit point is the same at every level.
  const SemiRegularHierarchy h(TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles),
                               levels);
  auto limit_surface = [&](const std::vector<double>& control_points) {
    std::vector<double> subdivided(3 * static_cast<std::size_t>(h.vertex_count(h.levels())), 0.0);
    std::copy(control_points.begin(), control_points.end(), subdivided.begin());
    for (int j = 0; j < h.levels(); ++j) synthesize_level(h, {Scheme::loop}, j, subdivided);  // no tables: the same bits
    std::vector<double> limit(subdivided.size());
    apply_loop_limit(TriangleMesh{subdivided, h.triangles(h.levels())}, subdivided, limit);
    // Base vertices stay exactly where decimation left them (on the input surface); without the
    // fit the limit surface of the base has shrunk away from them.
    std::copy(base.positions.begin(), base.positions.end(), limit.begin());
    return limit;
  };
  std::vector<std::vector<double>> guides{limit_surface(control)};
  // The vertices on feature lines have their places already (features.h): every guide holds them.
  const FeaturePlacement features = place_on_features(h, mesh, base, base_feature_edges(lines, decimated.original_vertex));
  hold_on_features(features, guides[0]);
  if (fit == BaseFit::loop) {
    // Second guide: where the unfitted limit surface is closer to the input than the fitted one
    // (the fitted control mesh overshoots around thin parts: camel's head, turbine's blades),
    // the new vertices of the levels that start at the guide start there instead. Measured (L =
    // 3, ~4x; fitted / mixed): camel 76.0 dB, 8 folds / 84.4, 0; turbine 53.7, 8 / 60.8, 0 (at
    // ~2x 70.1, 10 / 75.2, 0); mannequin-devil 76.2, 12 / 76.3, 34; fandisk 78.7 / 77.4, no folds
    // either way; the others within ±0.5 dB. Neither is better everywhere, hence both.
    const std::vector<double> plain = limit_surface(base.positions);
    std::vector<double> mixed = guides[0];
    const std::uint32_t end = h.vertex_count(std::min(SurfaceFitOptions{}.guide_levels, h.levels()));
    for (std::uint32_t v = h.vertex_count(0); v < end; ++v) {
      const std::array<double, 3> fitted{mixed[3 * v], mixed[3 * v + 1], mixed[3 * v + 2]},
          unfitted{plain[3 * v], plain[3 * v + 1], plain[3 * v + 2]};
      if (surface.closest(unfitted).distance < surface.closest(fitted).distance)
        std::copy_n(plain.begin() + 3 * std::ptrdiff_t{v}, 3, mixed.begin() + 3 * std::ptrdiff_t{v});
    }
    hold_on_features(features, mixed);
    if (mixed != guides[0]) guides.push_back(std::move(mixed));
  }
  if (set_aside_guide_at < kNowhere)
    for (const std::vector<double>& guide : guides)
      if (remesh_psnr(TriangleMesh{guide, h.triangles(h.levels())}, kQuickSamples) >= set_aside_guide_at) {
        clock.lap("guides, then set aside");
        if (placed_psnr) *placed_psnr = kNowhere;
        return std::nullopt;
      }
  clock.lap("guides");
  report(0.2);

  // Each guide's refinement is placed with the normal-line placement of level 1 (surface_fit.h)
  // and its patches untangled; if each folds some face, also without it. The placement that
  // folds fewest faces goes on; among those, one with normal lines (it codes in fewer bits: 4
  // to 11 points of BD-rate against Draco on the corpus, docs/RESULTS.md), then the one closest
  // to the input. Measured on the corpus (L = 3, ~4x, guides alone): the choice made here is the
  // one made after the least-squares fit and the last untangling, but for homer (79.72 against
  // 79.76 dB), at a fifth of the cost of finishing both. The guides' placements run on threads
  // of their own: the patch untangling is partly serial, so they overlap on two cores (the result
  // is the same as one after the other).
  struct Placed {
    std::optional<SemiRegularMesh> mesh;
    bool normal_lines = false;
    std::size_t flipped = 0, degenerate = 0;
    SnapReport snapped{};
    std::size_t folds() const { return flipped + degenerate; }
    void count_folds(const SurfaceQuery& surface) {
      const FoldOvers found = find_fold_overs(mesh->finest(), surface);
      flipped = found.flipped.size(), degenerate = found.degenerate.size();
    }
  };
  std::vector<Placed> candidates;
  auto place_each_guide = [&](bool normal_lines) {
    auto place = [&](std::size_t g, const std::function<void(double)>& progress) {
      Placed placed{place_refinement(h, guides[g], normal_lines, surface, features.fixed, progress), normal_lines};
      placed.count_folds(surface);
      return placed;
    };
    std::vector<std::future<Placed>> others;
    for (std::size_t g = 1; g < guides.size(); ++g) others.push_back(std::async(std::launch::async, place, g, [](double) {}));
    candidates.push_back(place(0, [&](double f) { report(normal_lines ? 0.2 + 0.4 * f : 0.6 + 0.15 * f); }));
    for (auto& future : others) candidates.push_back(future.get());
  };
  // The best of some candidates: fewest folds, then normal lines, then closest to the input.
  auto best_of = [&](std::vector<Placed>& from) {
    auto key = [](const Placed& c) { return std::pair(c.folds(), !c.normal_lines); };
    const auto best_key =
        key(*std::min_element(from.begin(), from.end(), [&](const Placed& a, const Placed& b) { return key(a) < key(b); }));
    std::optional<Placed> chosen;
    std::optional<double> chosen_psnr;  // computed at the first tie only
    for (Placed& candidate : from) {
      if (key(candidate) != best_key) continue;
      if (!chosen) {
        chosen = std::move(candidate);
        continue;
      }
      // A tie: the closer to the input.
      if (!chosen_psnr) chosen_psnr = remesh_psnr(*chosen->mesh);
      if (const double psnr = remesh_psnr(*candidate.mesh); psnr > *chosen_psnr)
        chosen = std::move(candidate), chosen_psnr = psnr;
    }
    return std::move(*chosen);
  };
  auto finish = [&](Placed& placed) {
    placed.snapped = finish_placement(*placed.mesh, surface, features.fixed, least_squares_rounds, snap);
    placed.count_folds(surface);
  };

  place_each_guide(true);
  Placed placed = best_of(candidates);
  if (abandon_below > kNever || set_aside_at < kNowhere) {
    const double placed_db = remesh_psnr(*placed.mesh, kQuickSamples);
    const bool set_aside = placed_db >= set_aside_at;
    if (set_aside || placed_db + give_up_margin < abandon_below) {
      clock.lap(set_aside ? "place, then set aside" : "place, then give up");
      if (placed_psnr) *placed_psnr = placed_db;
      return std::nullopt;
    }
  }
  // The normal-line placements fold: those without may fold fewer faces. When they do, the two
  // best are finished (the last stages remove many folds) and compared as they end.
  std::optional<Placed> plain;
  if (placed.folds() > 0) {
    candidates.clear();
    place_each_guide(false);
    plain = best_of(candidates);
    if (plain->folds() >= placed.folds()) plain.reset();
  }
  clock.lap("place and compare");
  report(0.75);
  if (plain) {
    std::future<void> other = std::async(std::launch::async, [&] { finish(*plain); });
    finish(placed);
    other.get();
    if (plain->folds() < placed.folds()) placed = std::move(*plain);
  } else {
    finish(placed);
  }
  clock.lap(snap ? "least squares, untangle and snap" : "least squares and untangle");
  report(0.9);

  RemeshResult result{std::move(*placed.mesh)};
  result.base_vertices = base.vertex_count();
  result.feature_edges = lines.edge_count();
  result.feature_vertices = features.count();
  result.direct_levels = levels;
  result.base_input_vertex = decimated.original_vertex;
  result.flipped_triangles = placed.flipped;
  result.degenerate_triangles = placed.degenerate;
  result.snapped_to_vertices = placed.snapped.onto_vertices;
  result.snapped_to_creases = placed.snapped.onto_creases;
  report(1);
  return result;
}

/// automatic_remesh_base() for an input of `vertices` vertices whose automatic_base_vertices()
/// is `decimator_floor` (it validates the mesh: worth computing once).
/// The base size for about `density` x `vertices` after `levels` refinements: ceil(D V / 4^L),
/// a 1:4 refinement multiplying the vertex count by about 4 (decimate.cpp, automatic_target).
std::size_t base_from_density(std::size_t vertices, int levels, double density) {
  return static_cast<std::size_t>(std::ceil(density * static_cast<double>(vertices) / std::ldexp(1.0, 2 * levels)));
}

std::size_t base_for_density(std::size_t vertices, int levels, double density, std::size_t decimator_floor) {
  // Below 1 the decimator's own automatic size, ceil(V / 4^L), would take over anyway.
  if (!(density >= 1 && density <= 1024))
    throw MeshError("density must be in [1, 1024], got " + std::to_string(density));
  return std::max(base_from_density(vertices, levels, density), decimator_floor);
}

}  // namespace

std::size_t automatic_remesh_base(const TriangleMesh& mesh, int levels, double density) {
  return base_for_density(mesh.vertex_count(), levels, density, automatic_base_vertices(mesh, levels));
}

namespace {

/// remesh(), and with `as_stored` false its result left in double: the remesh of a level fewer
/// that a deep hierarchy refines once more (RemeshOptions::level_by_level_from) goes on from
/// the positions it chose among, as before store_as_float() (rounded there, cow's remesh of 5
/// levels went from 0 folded faces to 4).
RemeshResult remesh_levels(const TriangleMesh& mesh, const RemeshOptions& options, bool as_stored) {
  if (options.least_squares_rounds < 0) throw MeshError("least_squares_rounds must be >= 0");
  if (const std::string problem = out_of_range(options.fold_search); !problem.empty())
    throw MeshError("fold_search: " + problem);
  if (options.missing_part_rounds < 0 || !(options.missing_part_distance >= 0))
    throw MeshError("missing_part_rounds and missing_part_distance must be >= 0");
  if (std::isnan(options.give_up_margin)) throw MeshError("give_up_margin must be a number (infinity: never give up)");
  if (!(options.input_refinement_vertices >= 0)) throw MeshError("input_refinement_vertices must be >= 0");
  if (options.level_by_level_from < 0) throw MeshError("level_by_level_from must be >= 0 (0: off)");
  if (options.density != 0 && !(options.density >= 1 && options.density <= 1024))
    throw MeshError("density must be 0 (automatic) or in [1, 1024], got " + std::to_string(options.density));
  if (options.levels < 0 || options.levels > kMaxLevels)
    throw MeshError("levels must be between 0 and " + std::to_string(kMaxLevels) + ", got " +
                    std::to_string(options.levels));
  // Where report()'s [0, 1] starts: past the share of a remesh of a level fewer that was made
  // and not refined (level_by_level_from), so that the fraction never goes back.
  double progress_from = 0;
  auto report = [&](double fraction) {
    if (options.progress) options.progress(progress_from + (1 - progress_from) * fraction);
  };
  auto taken_over = [&](SemiRegularMesh recovered, std::size_t coincident_vertices) {
    RemeshResult result{std::move(recovered)};
    result.recognized = true;
    result.base_vertices = result.mesh.hierarchy.vertex_count(0);
    result.coincident_vertices = coincident_vertices;
    report(1);
    return result;
  };
  const int recognized_levels = std::min(options.levels, 2);  // fewer: remeshed instead
  bool in_level_order = false;  // then recover_semi_regular() would find the same hierarchy again
  if (options.recognize) {
    // A mesh whose top levels are in level order (a remesh, a decoded file) is recognized before
    // the whole check below (validate_mesh: 3.7 s of a 3.3 M-vertex mesh's 4.3 s): its faces
    // refine a base that TriangleTopology::build() accepted (recover_in_level_order), so they
    // have what first_problem_for_triangle_codec() asks of faces. Its coordinates are checked
    // here; a mesh that fails goes the way of any other, to the check and its message.
    // The coincident vertices a recognized mesh reports are counted on a second thread meanwhile
    // (a 3.3 M-vertex mesh: 125 ms to recover, 150 to count; wasted when it is not recognized,
    // which then takes much longer anyway). Where no thread can be started, libstdc++ runs it
    // at get() or wait() instead (the deferred policy).
    std::future<std::size_t> coincident = std::async(std::launch::async | std::launch::deferred,
                                                     [&mesh] { return coincident_vertex_count(mesh.positions); });
    std::optional<SemiRegularMesh> recovered = recover_in_level_order(mesh);
    in_level_order = recovered.has_value();
    if (recovered && recovered->hierarchy.levels() >= recognized_levels &&
        std::all_of(mesh.positions.begin(), mesh.positions.end(), [](double x) { return std::isfinite(x); }) &&
        has_nonzero_area_face(mesh))
      return taken_over(std::move(*recovered), coincident.get());
    coincident.wait();  // its thread reads `mesh`: done before anything else happens
  }
  const MeshReport checked = validate_mesh(mesh);
  const std::string problem = first_problem_for_triangle_codec(checked);
  if (!problem.empty()) throw MeshError(problem);
  // A polygon soup (faces that share no vertex: unwelded triangles) is a valid mesh of many
  // one- or two-face pieces, but nothing a remesh can make surfaces of: name it.
  if (checked.connected_components > 1 && mesh.face_count() < 2 * checked.connected_components)
    throw MeshError("polygon soup: " + std::to_string(mesh.face_count()) + " faces in " +
                    std::to_string(checked.connected_components) +
                    " separate pieces; weld the vertices that coincide so that faces share them, then remesh");
  // Faces of zero area are sampled as nothing and remeshed as they come; but with no area at all
  // there is no surface to fit, and the "remesh" would be degenerate triangles at an infinite PSNR.
  if (checked.zero_area_faces == mesh.face_count())
    throw MeshError("every face has zero area (its corners on a line or at one point): there is no surface to remesh");

  if (options.recognize && !in_level_order) {
    // Any other order of a refinement's vertices and faces (the level-ordered route failed above).
    auto recovered = recover_semi_regular(mesh);
    if (recovered && recovered->hierarchy.levels() >= recognized_levels)
      return taken_over(std::move(*recovered), checked.duplicate_vertices);
  }

  const SurfaceQuery surface(mesh);
  InputPsnr input_psnr(mesh);  // the automatic choices' PSNRs against the input (one thread)
  auto by_sphere = [&](int levels) {
    std::vector<std::pair<std::string, double>> sphere_stages;
    StageClock clock(sphere_stages);
    RemeshResult result{remesh_sphere(mesh, levels)};
    clock.lap("sphere");
    if (options.snap) {
      const SnapReport snapped = snap_to_input(result.mesh, surface, {});
      result.snapped_to_vertices = snapped.onto_vertices;
      result.snapped_to_creases = snapped.onto_creases;
      clock.lap("snap");
    }
    result.stage_seconds = std::move(sphere_stages);
    result.method = RemeshMethod::sphere;
    result.base_vertices = result.mesh.hierarchy.vertex_count(0);
    const FoldOvers folds = find_fold_overs(result.mesh.finest(), surface);
    result.flipped_triangles = folds.flipped.size();
    result.degenerate_triangles = folds.degenerate.size();
    return result;
  };
  // Flipped faces where the input passes through itself (cow's tail through its body,
  // mannequin-devil's hands): counted apart, since no orientation agrees with both sheets.
  std::optional<std::vector<std::array<std::uint32_t, 2>>> input_crossings;  // found once, when first needed
  std::optional<std::vector<std::uint8_t>> crossing_faces;                    // per input face: 1 at a crossing
  auto crossing_marks = [&]() -> const std::vector<std::uint8_t>& {
    if (!input_crossings) input_crossings = self_intersections(mesh);
    if (!crossing_faces) {
      crossing_faces.emplace(mesh.face_count(), 0);
      for (const auto& [f, g] : *input_crossings) (*crossing_faces)[f] = (*crossing_faces)[g] = 1;
    }
    return *crossing_faces;
  };
  std::optional<std::vector<std::uint8_t>> near_crossing_faces;  // per input face: 1 within two rings of one (not at one)
  auto near_crossing_marks = [&]() -> const std::vector<std::uint8_t>& {
    if (!near_crossing_faces) near_crossing_faces = faces_near_marked(mesh, crossing_marks(), 2);
    return *near_crossing_faces;
  };
  std::optional<std::vector<std::uint8_t>> by_crossing_faces;  // per input face: 1 at a crossing or within two rings of one
  auto by_crossing_marks = [&]() -> const std::vector<std::uint8_t>& {
    if (!by_crossing_faces) {
      by_crossing_faces = crossing_marks();
      const std::vector<std::uint8_t>& near = near_crossing_marks();
      for (std::size_t f = 0; f < near.size(); ++f) (*by_crossing_faces)[f] |= near[f];
    }
    return *by_crossing_faces;
  };
  // `returned`: the result remesh() returns, whose flipped faces turned over on the remesh itself
  // are counted too (a report only, not made for every candidate).
  auto note_crossings = [&](RemeshResult& result, bool returned = false) {
    const std::vector<std::uint8_t>& crossing = crossing_marks();
    result.input_crossing_pairs = input_crossings->size();
    result.coincident_vertices = checked.duplicate_vertices;
    result.flipped_where_input_crosses = result.flipped_near_input_crossings = 0;  // set by a fold_free() before rounding
    result.flipped_turned_over = 0;
    if (result.flipped_triangles == 0 || (!returned && input_crossings->empty())) return;
    const TriangleMesh finest = result.mesh.finest();
    const std::vector<std::uint32_t> flipped = find_fold_overs(finest, surface).flipped;
    if (returned) result.flipped_turned_over = count_turned_over(finest, flipped);
    if (input_crossings->empty()) return;
    result.flipped_where_input_crosses = count_at_crossings(finest, flipped, surface, crossing);
    result.flipped_near_input_crossings = count_at_crossings(finest, flipped, surface, near_crossing_marks());
  };
  // The chosen remesh's last step, where it is the one returned: stored as floats (and searched
  // where it folds). A remesh a deeper level refines stays in double (its search is made there).
  auto last_step = [&](RemeshResult& result) {
    if (!as_stored) return;
    StageClock clock(result.stage_seconds);
    store_as_float(result, surface, options.fold_search, by_crossing_marks);
    clock.lap("store as float");
  };
  if (options.method == RemeshMethod::sphere) {
    RemeshResult result = by_sphere(options.levels);
    last_step(result);
    note_crossings(result, true);
    report(1);
    return result;
  }
  const FeatureLines lines = find_feature_lines(mesh, options.feature_angle, options.feature_min_edges,
                                                options.feature_max_turn, options.feature_max_side);
  const FeatureLines no_lines;
  // The base size for a density (automatic_remesh_base(), the mesh validated once).
  std::optional<std::size_t> decimator_floor;
  auto base_size = [&](double density) {
    if (!decimator_floor) decimator_floor = automatic_base_vertices(mesh, options.levels);
    return base_for_density(mesh.vertex_count(), options.levels, density, *decimator_floor);
  };
  auto decimate_options = [&](const FeatureLines& with) {
    DecimateOptions decimate_options;
    decimate_options.feature_lines = &with;
    decimate_options.levels = options.levels;
    return decimate_options;
  };
  std::vector<std::pair<std::string, double>> stages;  // of every decimation remesh made
  // The automatic density's bases, with and without the feature lines: each set from one
  // decimation, made when first needed, that stops at every density's base on its way
  // (decimate_each: the bases decimate() would make, byte for byte, for the cost of the
  // smallest; armadillo subdivided to 104,002 vertices decimated in 3.3 s per density tried).
  std::vector<double> auto_densities(std::begin(kAutoDensities), std::end(kAutoDensities));
  auto_densities.insert(auto_densities.end(), std::begin(kDenserAutoDensities), std::end(kDenserAutoDensities));
  auto_densities.insert(auto_densities.end(), std::begin(kSparserAutoDensities), std::end(kSparserAutoDensities));
  std::optional<std::vector<DecimateResult>> auto_bases[2];  // [1]: with the lines
  auto auto_base = [&](double density, const FeatureLines& with) -> const DecimateResult& {
    std::optional<std::vector<DecimateResult>>& bases = auto_bases[&with == &lines];
    if (!bases) {
      StageClock clock(stages);
      std::vector<std::size_t> targets;
      for (const double d : auto_densities) targets.push_back(base_size(d));
      bases = decimate_each(mesh, decimate_options(with), targets);
      clock.lap("decimate");
    }
    const auto at = std::find(auto_densities.begin(), auto_densities.end(), density);
    return (*bases)[static_cast<std::size_t>(at - auto_densities.begin())];
  };
  // The remesh of a decimated base, or nullopt if given up below `abandon_below` dB or set aside
  // at `set_aside_at` (or, where that is set, by its guides at sparsest_guide_psnr), with
  // `*placed_psnr` its first placement's PSNR (remesh_by_decimation).
  auto remesh_base = [&](const DecimateResult& decimated, double density, double from, double to,
                         const FeatureLines& with, double abandon_below = kNever, double* placed_psnr = nullptr,
                         double set_aside_at = kNowhere) {
    const std::size_t asked =
        options.base_vertices != 0 ? options.base_vertices : base_from_density(mesh.vertex_count(), options.levels, density);
    std::optional<RemeshResult> r = remesh_by_decimation(
        mesh, surface, input_psnr, decimated, asked, with, options.levels, options.fit, options.least_squares_rounds, options.snap, abandon_below,
        set_aside_at, set_aside_at < kNowhere ? options.sparsest_guide_psnr : kNowhere, options.give_up_margin, placed_psnr,
        [&](double f) { report(from + (to - from) * f); }, stages);
    if (r && !r->input_refined) r->target_base_vertices = options.base_vertices != 0 ? options.base_vertices : base_size(density);
    if (r) r->density = options.base_vertices != 0 ? 0 : density;
    return r;
  };
  // An explicit density's base without the feature lines where the check of
  // level_by_level_from below decimated it already: by_decimation() takes it from there.
  std::optional<DecimateResult> plain_base;
  auto by_decimation = [&](double from, double to, const FeatureLines& with) {
    std::optional<DecimateResult> decimated;
    if (&with != &no_lines || !plain_base) {
      StageClock clock(stages);
      DecimateOptions one = decimate_options(with);
      one.target_vertices = options.base_vertices != 0 ? options.base_vertices : base_size(options.density);
      decimated = decimate(mesh, one);
      clock.lap("decimate");
    }
    return std::move(*remesh_base(decimated ? *decimated : *plain_base, options.density, from, to, with));
  };
  // Errors measured on kChoiceSamples a side.
  auto psnr = [&](const RemeshResult& r) {
    StageClock clock(stages);
    const double db = input_psnr(r.mesh);
    clock.lap("choose density");
    return db;
  };
  // No folded or degenerate face but where the input passes through itself.
  auto fold_free = [&](RemeshResult& r) {
    if (r.flipped_triangles == 0) return r.degenerate_triangles == 0;
    note_crossings(r);
    return r.flipped_triangles == r.flipped_where_input_crosses && r.degenerate_triangles == 0;
  };
  // What the automatic density keeps: close enough to the input, and fold-free as above.
  auto qualifies = [&](RemeshResult& r, double db) { return db >= options.auto_density_psnr && fold_free(r); };
  // RemeshOptions::missing_part_rounds: where the decimation stopped above its target, the input
  // vertices where the remesh and the input part are kept in the base, and the remesh made again,
  // each round with more of them; a round's remesh is kept where it is closer and folds no more.
  auto keep_missing_parts = [&](RemeshResult& result) {
    if (result.method != RemeshMethod::decimate || result.recognized || result.input_refined) return;
    const std::size_t target = result.target_base_vertices;
    if (result.base_vertices <= target) return;
    const FeatureLines& with = result.feature_edges > 0 ? lines : no_lines;
    const double diagonal = checked.bbox_diagonal;
    std::vector<std::uint32_t> keep;
    std::vector<char> used(mesh.vertex_count(), 0);
    for (const std::uint32_t v : mesh.triangles) used[v] = 1;
    double result_db = 0;
    for (int round = 0; round < options.missing_part_rounds; ++round) {
      StageClock clock(stages);
      // Where the remesh and the input part, farthest first: input vertices far from the remesh
      // (a part it passed by: elephant's foot), and, for remesh faces far from the input (a sheet
      // across a gap: turbine's blades at L = 4), the nearest corner of the input face closest to
      // them. The far ones are kept, spaced out.
      const TriangleMesh finest = result.mesh.finest();
      const SurfaceQuery remeshed(finest);
      const double limit = options.missing_part_distance * diagonal;
      std::vector<double> vertex_distance(mesh.vertex_count(), 0);
      parallel_blocks(mesh.vertex_count(), 0, [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v)
          if (used[v]) vertex_distance[v] = remeshed.closest(vec3::at(mesh.positions, static_cast<std::uint32_t>(v))).distance;
      });
      std::vector<std::pair<double, std::uint32_t>> face_corner(finest.face_count(), {0.0, kNone});
      parallel_blocks(finest.face_count(), 0, [&](std::size_t begin, std::size_t end) {
        std::uint32_t hint = kNone;
        for (std::size_t f = begin; f < end; ++f) {
          const std::uint32_t* t = &finest.triangles[3 * f];
          vec3::Vec3 centroid{0, 0, 0};
          for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) centroid[k] += finest.positions[3 * std::size_t{t[i]} + k] / 3;
          const SurfacePoint on = surface.closest(centroid, hint);
          hint = on.face;
          if (!(on.distance > limit)) continue;
          face_corner[f] = {on.distance, mesh.triangles[3 * std::size_t{on.face} + on.heaviest_corner()]};
        }
      });
      std::vector<std::pair<double, std::uint32_t>> far;
      for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
        if (vertex_distance[v] > limit) far.push_back({vertex_distance[v], v});
      for (const auto& candidate : face_corner)
        if (candidate.second != kNone) far.push_back(candidate);
      std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
      });
      const std::size_t before = keep.size();
      for (const auto& [distance, v] : far) {
        if (keep.size() == before + kMissingPartsPerRound) break;
        if (std::find(keep.begin(), keep.end(), v) != keep.end()) continue;  // kept already, and still far
        bool apart = true;
        for (std::size_t k = before; k < keep.size() && apart; ++k) {
          const vec3::Vec3 d = vec3::sub(vec3::at(mesh.positions, v), vec3::at(mesh.positions, keep[k]));
          apart = vec3::dot(d, d) > kMissingPartSpacing * kMissingPartSpacing * diagonal * diagonal;
        }
        if (apart) keep.push_back(v);
      }
      if (keep.size() == before) return;
      DecimateOptions one = decimate_options(with);
      one.target_vertices = target;
      one.keep = keep;
      const DecimateResult decimated = decimate(mesh, one);
      clock.lap("missing parts: decimate");
      RemeshResult again = std::move(*remesh_base(decimated, result.density, 1, 1, with));
      // Folds where the input passes through itself (no orientation faces both sheets) aside; a
      // remesh kept from an earlier round has both measures already.
      if (result_db == 0) {
        result_db = psnr(result);
        note_crossings(result);
      }
      const double again_db = psnr(again);
      note_crossings(again);
      // A round that is not closer ends the step. One that is closer but folds more is not kept,
      // but the next round goes on with its vertices and more: turbine at L = 4 needs two rounds
      // (53.7 dB and 9 folds, then 56.0 and 11, then 84.0 and 1), and stopping at the first kept
      // the 53.7 dB remesh.
      if (!(again_db > result_db)) return;
      if (again.flipped_triangles - again.flipped_where_input_crosses >
          result.flipped_triangles - result.flipped_where_input_crosses)
        continue;
      again.kept_vertices = keep.size();
      result = std::move(again);
      result_db = again_db;
    }
  };
  // Deep hierarchies, level by level (RemeshOptions::level_by_level_from): the remesh of a level
  // fewer, refined once more, where its base is this one's. With a density, whether the
  // decimation stops above that level's target is seen from this level's base first, so that a
  // larger input's remesh of a level fewer is not made for nothing.
  // Made over this level's base at an explicit density (below), a refinement that folds away
  // from the input's crossings is set against the remesh placed from the base: its share of the
  // progress is then the first half.
  bool over_floor_base = false;
  double deeper_share = 1;
  std::optional<RemeshResult> deeper = [&]() -> std::optional<RemeshResult> {
    const int coarser_levels = options.levels - 1;
    std::size_t coarser_base_size = options.base_vertices;  // the base size a level fewer is given
    if (options.level_by_level_from == 0 || options.levels < options.level_by_level_from || coarser_levels < 1)
      return std::nullopt;
    if (options.base_vertices == 0) {
      // Where this level's decimation stops (its base for the density, or the automatic
      // density's sparsest of 2x, 3x and 4x), against the base the remesh of a level fewer asks
      // for: with the automatic density, that of 4x, so that whichever of the three it keeps has
      // this level's base (only 6x and 8x can go above it: small inputs). Measured: 2x's there
      // made the remesh of a level fewer for nothing on armadillo and fandisk at L = 5, elephant
      // and mannequin-devil at L = 4 (3x or 4x above the floor kept), 27-30 % of their time.
      std::size_t reached = 0;
      if (options.density == 0) {
        reached = auto_base(kAutoDensities[0], no_lines).base.vertex_count();
      } else {
        StageClock clock(stages);
        DecimateOptions one = decimate_options(no_lines);
        one.target_vertices = base_size(options.density);
        reached = plain_base.emplace(decimate(mesh, one)).base.vertex_count();
        clock.lap("decimate");
      }
      const double asked = options.density != 0 ? options.density : kAutoDensities[2];
      if (reached < base_for_density(mesh.vertex_count(), coarser_levels, asked,
                                     automatic_base_vertices(mesh, coarser_levels))) {
        // An explicit density whose decimation stops at its floor, above this level's target
        // but below a level fewer's: the remesh of a level fewer given this level's target as
        // its base size (so it stops at the same floor, and its missing-parts step runs), not
        // the one at the density asked for. Placed from that floor directly, turbine at
        // --density 16, L = 5 gave 80.3 dB with 14 folded faces (docs/RESULTS.md, "Explicit
        // densities a level at a time").
        if (options.density == 0 || reached <= base_size(options.density)) return std::nullopt;
        coarser_base_size = base_size(options.density);
        over_floor_base = true;
        deeper_share = 0.5;
      }
    }
    RemeshOptions coarser = options;
    coarser.levels = coarser_levels;
    coarser.base_vertices = coarser_base_size;
    coarser.method = RemeshMethod::decimate;
    coarser.recognize = false;
    coarser.snap = false;  // at the finest level only
    coarser.progress = [&](double f) { report(deeper_share * 0.5 * f); };
    RemeshResult above = remesh_levels(mesh, coarser, false);
    if (over_floor_base) above.density = options.density;  // not 0 (a size given)
    // This level's base too: the size given, one at the decimation's floor (above its target),
    // or a target this level shares (the topology's floor, automatic_base_vertices()).
    const bool same_base = coarser_base_size != 0 || above.base_vertices > above.target_base_vertices ||
                           base_size(above.density) == above.target_base_vertices;
    // Not refined: a base this level does not share, or the input refined as it is (its rules
    // decide at this level too: one bounds the refinement's size,
    // RemeshOptions::input_refinement_vertices). Its time is listed as one stage.
    if (above.input_refined || !same_base) {
      double seconds = 0;
      for (const auto& stage : above.stage_seconds) seconds += stage.second;
      stages.emplace_back("a level fewer, not refined", seconds);
      progress_from = 0.5;
      return std::nullopt;
    }
    stages.insert(stages.end(), above.stage_seconds.begin(), above.stage_seconds.end());
    StageClock clock(stages);
    // Its folds searched first (search_folds()), so that a fold there is not refined into more:
    // mannequin-devil at L = 5 54 -> 46 folded faces, at L = 6 517 -> 424 (docs/RESULTS.md,
    // "Folds at the input's crossings searched too"). The vertices it moves are rounded to
    // floats; the rest stays in double.
    search_folds(above, find_fold_overs(above.mesh.finest(), surface), surface, options.fold_search, by_crossing_marks);
    clock.lap("search the folds");
    RemeshResult r = refined_once_more(std::move(above), mesh, lines, surface, options.least_squares_rounds, options.snap,
                                       [&](double f) { report(deeper_share * (0.5 + 0.5 * f)); });
    r.target_base_vertices = options.base_vertices != 0 ? options.base_vertices : base_size(r.density);
    clock.lap("refine once more");
    return r;
  }();
  auto placed_from_base = [&]() -> RemeshResult {
    if (options.base_vertices != 0 || options.density != 0) {
      // by_decimation() takes base_vertices first. With feature lines, the remesh with them and
      // the one without: the one that folds nowhere (but at the input's crossings), else the
      // closer (turbine at 4x: 80.1 dB with its lines, 81.9 without; at 16x 78.7 dB and 7
      // folds with them, 86.0 and 10 without; fandisk at 4x 85.1 with, 77.7 without).
      RemeshResult plain = by_decimation(0, lines.empty() ? 1 : 0.5, no_lines);
      if (lines.empty()) return plain;
      RemeshResult lined = by_decimation(0.5, 1, lines);
      const bool lined_fold_free = fold_free(lined), plain_fold_free = fold_free(plain);
      if (lined_fold_free != plain_fold_free) return lined_fold_free ? std::move(lined) : std::move(plain);
      return psnr(lined) >= psnr(plain) ? std::move(lined) : std::move(plain);
    }
    // Automatic density: the sparsest remesh that is close enough to the input and folds
    // nowhere (but where the input passes through itself), 2x, then 3x with a margin, else the
    // closest of the three (turbine: 70.0 dB at 2x, 53.4 at 4x).
    // A candidate that must reach some PSNR to be kept is given up after its first placement
    // where that shows it cannot (remesh_by_decimation): mannequin-devil's 2x remeshes (55.6 dB
    // as first placed, 60.4 finished; 75 needed) cost a placement each instead of a remesh.
    // Same choices as finishing every candidate (docs/RESULTS.md).
    struct Made {
      double density = 0;
      std::optional<RemeshResult> remesh;
      double psnr = 0;  // finished: its PSNR; given up: the most it could have reached
      bool set_aside = false;  // stopped at its first placement or its guides, to try sparser ones first
    };
    // Makes m's remesh with `with`, given up below `abandon_below` dB, or set aside at
    // `set_aside_at` (remesh_by_decimation reports that by a placed PSNR at least that).
    auto make = [&](Made& m, double from, double to, const FeatureLines& with, double abandon_below,
                    double set_aside_at = kNowhere) {
      double placed = 0;
      m.remesh = remesh_base(auto_base(m.density, with), m.density, from, to, with, abandon_below, &placed, set_aside_at);
      m.set_aside = !m.remesh && placed >= set_aside_at;
      m.psnr = m.remesh ? psnr(*m.remesh) : placed + options.give_up_margin;
    };
    // The 2x remesh (`sparse`), or a sparser one: where the 2x remesh is first placed
    // sparsest_density_psnr or closer to the input (a smooth mesh, or a CAD mesh along its
    // feature lines), or has a guide sparsest_guide_psnr or closer (then it is not even
    // placed), it is set aside and the kSparserAutoDensities come first, in turn, the first
    // that qualifies kept (each given up where its placement shows it cannot: the next
    // is made anyway); the 2x one is finished only if none does. Measured (docs/RESULTS.md):
    // bear_bis 84.6 dB at 2x, 83.1 at 1.5x, 80.7 at 1x, BD-rate against Draco -76.8 -> -80.5 %
    // at 1.5x, -82.9 -> -85.1 % at 1x; a 104,002-vertex armadillo (2x guide at 63.3 dB, 1x
    // 87.0 finished) takes 1x in 8.0-8.1 s instead of finishing 2x, 1.5x and 1x in 19-21 s.
    // A decimation stopped above a density's target (at its floor: a deep hierarchy) stops there
    // for every sparser target too, and one base gives one remesh (the bases of one decimation
    // with as many vertices are the same): a sparser density whose base is the one before it is
    // not made again, and a 2x remesh no sparser base differs from is not set aside (cow at L =
    // 5 made the same remesh three times, 37 s instead of 18; docs/RESULTS.md).
    auto sparse_or_sparser = [&](Made& sparse, double from, double to, const FeatureLines& with,
                                 double abandon_below) -> std::optional<RemeshResult> {
      std::size_t before = auto_base(sparse.density, with).base.vertex_count();
      const bool sparser_bases = std::any_of(std::begin(kSparserAutoDensities), std::end(kSparserAutoDensities),
                                             [&](double d) { return auto_base(d, with).base.vertex_count() != before; });
      make(sparse, from, from + 0.5 * (to - from), with, abandon_below,
           sparser_bases ? options.sparsest_density_psnr : kNowhere);
      if (sparse.set_aside) {
        double at = from + 0.5 * (to - from);
        for (const double density : kSparserAutoDensities) {
          const std::size_t base_vertices = auto_base(density, with).base.vertex_count();
          if (base_vertices == std::exchange(before, base_vertices)) continue;
          Made sparser{density, std::nullopt, 0};
          make(sparser, at, at + 0.25 * (to - from), with, options.auto_density_psnr);
          at += 0.25 * (to - from);
          if (sparser.remesh && qualifies(*sparser.remesh, sparser.psnr)) return std::move(sparser.remesh);
        }
        make(sparse, to, to, with, abandon_below);
      }
      if (sparse.remesh && qualifies(*sparse.remesh, sparse.psnr)) return std::move(sparse.remesh);
      return std::nullopt;
    };
    // Feature lines first, where there are any: kept if their 2x remesh (or a sparser one)
    // qualifies; else the remesh goes on without them (they can cost a thin part or fold at a
    // crossing: mannequin-devil 68.8 dB at 4x with them, 76.3 without; docs/RESULTS.md).
    if (!lines.empty()) {
      Made lined{kAutoDensities[0], std::nullopt, 0};
      if (std::optional<RemeshResult> r = sparse_or_sparser(lined, 0, 0.5, lines, options.auto_density_psnr)) return std::move(*r);
    }
    // A decimation that stopped at or above a denser target gives the same base (cow stops at
    // 193 vertices for all three).
    auto same_base_as_denser = [&](std::size_t base_vertices, double denser) {
      return base_vertices >= base_size(denser);
    };
    // The 2x, 3x and 4x remeshes made, in that order: each finished, with its PSNR, or given up
    // after its first placement, with the most it could reach. One is given up only where a
    // later one will be made whatever it reaches: a denser one of the three, or a denser step
    // (below dense_density_psnr). What a candidate that must reach `keep` may be given up below:
    auto give_up_below = [&](std::size_t base_vertices, double keep) {
      if (!same_base_as_denser(base_vertices, kAutoDensities[2])) return keep;
      if (!same_base_as_denser(base_vertices, kDenserAutoDensities[0])) return std::min(keep, options.dense_density_psnr);
      return kNever;
    };
    std::vector<Made> made;
    auto finish = [&](Made& m) { make(m, 0.9, 0.9, no_lines, kNever); };
    // The closest finished so far (-infinity if none): at most the closest made.
    auto closest_finished = [&] {
      double db = kNever;
      for (const Made& m : made)
        if (m.remesh) db = std::max(db, m.psnr);
      return db;
    };
    // Whether every one made has a PSNR for which `holds` (x < X or x <= X) is true; a given-up
    // one is finished only where its bound leaves that open.
    auto all_made = [&](const auto& holds) {
      for (Made& m : made)
        if (m.remesh && !holds(m.psnr)) return false;
      for (Made& m : made)
        if (!m.remesh && !holds(m.psnr)) {
          finish(m);
          if (!holds(m.psnr)) return false;
        }
      return true;
    };
    std::size_t densest_base = auto_base(kAutoDensities[0], no_lines).base.vertex_count();
    {
      Made sparse{kAutoDensities[0], std::nullopt, 0};
      if (std::optional<RemeshResult> r =
              sparse_or_sparser(sparse, 0, 0.5, no_lines, give_up_below(densest_base, options.auto_density_psnr)))
        return std::move(*r);
      made.push_back(std::move(sparse));
    }
    if (!same_base_as_denser(densest_base, kAutoDensities[1])) {
      Made middle{kAutoDensities[1], std::nullopt, 0};
      densest_base = auto_base(middle.density, no_lines).base.vertex_count();
      make(middle, 0.5, 0.75, no_lines, give_up_below(densest_base, options.middle_density_psnr));
      if (middle.remesh && middle.psnr >= options.middle_density_psnr && fold_free(*middle.remesh))
        return std::move(*middle.remesh);
      made.push_back(std::move(middle));
    }
    if (!same_base_as_denser(densest_base, kAutoDensities[2])) {
      // Kept only if at least as close as the closest before it.
      Made dense{kAutoDensities[2], std::nullopt, 0};
      densest_base = auto_base(dense.density, no_lines).base.vertex_count();
      make(dense, 0.75, 0.9, no_lines, closest_finished());
      made.push_back(std::move(dense));
    }
    // Still short of the top of the 55-75 dB range that the codec's files are measured over (a
    // small input whose 4x base is tiny: cow 66.1 dB, elephant 69.9): the codec's curve would
    // flatten below it at every rate. Denser steps while that lasts, each kept if closer and
    // folding nowhere but at the input's crossings (elephant 75.9 dB at 6x, BD-rate against
    // Draco -30.2 -> -39.2 %; cow's 6x remesh folds a face away from its crossings, its 8x one is
    // 74.5 dB, -18.8 -> -32.4 %; docs/RESULTS.md).
    std::optional<RemeshResult> denser;
    double denser_psnr = kNever;
    double from = 0.9;
    for (const double density : kDenserAutoDensities) {
      if (same_base_as_denser(densest_base, density) || denser_psnr >= options.dense_density_psnr ||
          !all_made([&](double db) { return db < options.dense_density_psnr; }))
        break;
      const DecimateResult& base = auto_base(density, no_lines);
      densest_base = base.base.vertex_count();
      // Kept only if at least as close as the closest so far: given up where it cannot be.
      std::optional<RemeshResult> r = remesh_base(base, density, from, from + 0.05, no_lines,
                                                  std::max(denser_psnr, closest_finished()));
      from += 0.05;
      if (!r) continue;
      if (const double db = psnr(*r);
          db >= denser_psnr && fold_free(*r) && all_made([&](double made_db) { return made_db <= db; })) {
        denser = std::move(r);
        denser_psnr = db;
      }
    }
    if (denser) return std::move(*denser);
    // The closest of the 2x, 3x and 4x ones, the later of equals, as if every one had been
    // finished: a given-up one is finished after all if it could still be it (not seen on the
    // corpus).
    for (Made& m : made)
      if (!m.remesh && m.psnr >= closest_finished()) finish(m);
    Made* closest = nullptr;
    for (Made& m : made)
      if (m.remesh && (!closest || m.psnr >= closest->psnr)) closest = &m;
    return std::move(*closest->remesh);
  };
  auto from_base = [&] {
    RemeshResult r = placed_from_base();
    keep_missing_parts(r);  // a deeper one's base kept them already
    return r;
  };
  RemeshResult result = deeper ? std::move(*deeper) : from_base();
  if (deeper && over_floor_base && !fold_free(result)) {
    // Refined a level at a time, fandisk at --density 4, L = 5 folds 6 faces (87.2 dB); placed
    // from its base none (74.1 dB). Kept: the one that folds fewer faces away from the input's
    // crossings, else the closer (docs/RESULTS.md, "Explicit densities a level at a time").
    progress_from = deeper_share;
    RemeshResult direct = from_base();
    auto folds_away = [&](RemeshResult& r) {
      fold_free(r);  // counts those at the crossings
      return r.flipped_triangles - r.flipped_where_input_crosses + r.degenerate_triangles;
    };
    const std::size_t refined_folds = folds_away(result), direct_folds = folds_away(direct);
    if (direct_folds < refined_folds || (direct_folds == refined_folds && psnr(direct) > psnr(result))) {
      result = std::move(direct);
      result.set_aside_refinement_folds = refined_folds;
    }
  }
  // Where the automatic density made no remesh within auto_density_psnr of the input without a
  // fold (but at its crossings), a small input's own midpoint refinement is the closest remesh
  // there is: exact, at most RemeshOptions::input_refinement_vertices vertices, or 16 times as
  // many where the remesh failed, folding away from the input's crossings (boeing: 134 folded
  // faces at 50.7 dB; b9_mesh 145 at 49.5 dB; docs/RESULTS.md, "Small inputs").
  if (options.density == 0 && options.base_vertices == 0 && !result.input_refined) {
    const bool failed = !fold_free(result);
    // About 4^L V vertices: each 1:4 refinement adds a vertex per edge, V + E ≈ 4V (E ≈ 3V).
    const double refinement_vertices = std::ldexp(static_cast<double>(mesh.vertex_count()), 2 * options.levels);
    if (refinement_vertices <= (failed ? 16 : 1) * options.input_refinement_vertices &&
        (failed || !qualifies(result, psnr(result)))) {
      StageClock clock(stages);
      if (std::optional<RemeshResult> exact = input_refinement(mesh, surface, options.levels)) {
        exact->density = result.density;
        result = std::move(*exact);
      }
      clock.lap("the input refined");
    }
  }
  result.stage_seconds = std::move(stages);
  if (options.method == RemeshMethod::best && sphere_parametrization_problem(mesh).empty()) {
    // The octahedron level with the nearest vertex count: 4^(L+1) + 2 vertices.
    const double target = result.mesh.hierarchy.vertex_count(result.mesh.hierarchy.levels());
    int sphere_levels = 0;
    while (sphere_levels < geometry_image_levels(kMaxGeometryImageSize) &&
           std::abs(std::log(std::pow(4.0, sphere_levels + 2) + 2) - std::log(target)) <
               std::abs(std::log(std::pow(4.0, sphere_levels + 1) + 2) - std::log(target)))
      ++sphere_levels;
    RemeshResult sphere = by_sphere(sphere_levels);
    MetricOptions rms_only;
    rms_only.vertices = false;
    const bool sphere_closer = surface_distance(mesh, sphere.mesh.finest(), rms_only).rms <
                               surface_distance(mesh, result.mesh.finest(), rms_only).rms;
    // Both remeshes' times, whichever is kept.
    std::vector<std::pair<std::string, double>> stages = std::move(result.stage_seconds);
    stages.insert(stages.end(), sphere.stage_seconds.begin(), sphere.stage_seconds.end());
    if (sphere_closer) result = std::move(sphere);
    result.stage_seconds = std::move(stages);
  }
  last_step(result);
  note_crossings(result, true);
  report(1);
  return result;
}

}  // namespace

RemeshResult remesh(const TriangleMesh& mesh, const RemeshOptions& options) { return remesh_levels(mesh, options, true); }

}  // namespace meshlift
