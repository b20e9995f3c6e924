#include "remesh_options.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>

#include "commands.h"
#include "meshlift/metric.h"
#include "files.h"
#include "meshlift/validate.h"
#include "progress.h"

namespace meshlift::cli {

namespace {

std::string format_seconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f s", seconds);
  return text;
}

}  // namespace

void add_remesh_options(CLI::App& cmd, RemeshCliOptions& options, const std::string& method_flag) {
  cmd.add_option(method_flag, options.method,
                 "remesher: decimate (any mesh), sphere (closed genus-0: octahedral geometry image, --levels "
                 "refinements of the octahedron), best (sphere when it applies and is closer to the input)")
      ->check(CLI::IsMember({"decimate", "sphere", "best"}))
      ->capture_default_str();
  cmd.add_option("--levels", options.levels, "refinements of the base mesh (when remeshing)")
      ->check(CLI::Range(0, 12))
      ->capture_default_str();
  cmd.add_option("--base-vertices", options.base_vertices, "base mesh size; 0 chooses from the mesh and --levels")
      ->capture_default_str();
  cmd.add_option("--density", options.density,
                 "remesh vertices per input vertex the base size aims at, 1..1024, or auto: 2 if that remesh is "
                 "within 75 dB PSNR of the input (fewer bits at 55-75 dB; 1, else 1.5, where 2 is far within and "
                 "they are within 75 dB too), else 3 or 4 (closer), then 6 and 8 while the closest is still short "
                 "of 75 dB (small inputs)")
      ->check(CLI::IsMember({"auto"}) | (CLI::Range(1.0, 1024.0) & kFinite))
      ->capture_default_str();
  cmd.add_option("--fit", options.fit, "base fitting: loop (Loop limit surface through the base vertices) or none")
      ->check(CLI::IsMember({"loop", "none"}))
      ->capture_default_str();
  cmd.add_option("--least-squares", options.least_squares_rounds,
                 "rounds of least-squares fitting to the input, both ways (0: vertices stay on the input surface)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  cmd.add_flag("--snap", options.snap,
               "last, move the remesh's vertices onto the input's own corners and creases wherever that brings it "
               "closer (0.2-8.6 dB on the development meshes, no fold added); for a remesh used as a mesh: its "
               "details then cost more bits to code");
  cmd.add_option("--feature-angle", options.feature_angle,
                 "feature lines (creases of CAD parts): edges whose faces turn by more than this many degrees, "
                 "in smooth lines of 5 edges or more between smooth sides, are kept by the base and followed by the "
                 "remesh (with --density auto: where their 2x remesh qualifies); 0: none")
      ->check(CLI::Range(0.0, 180.0) & kFinite)
      ->capture_default_str();
  cmd.add_flag("--weld", options.weld,
               "join the input's vertices that sit at exactly the same position first (files whose pieces or UV "
               "seams have vertices of their own: otherwise each side of such a seam stays a boundary)");
  cmd.add_flag("--orient", options.orient,
               "turn faces over until every edge is run opposite ways by its two faces (files whose faces were "
               "written in either turn; closed pieces then face outwards), after --weld");
}

RemeshOptions to_remesh_options(const RemeshCliOptions& options) {
  RemeshOptions o;
  o.levels = options.levels;
  o.base_vertices = options.base_vertices;
  o.density = options.density == "auto" ? 0 : std::stod(options.density);
  o.fit = options.fit == "none" ? BaseFit::none : BaseFit::loop;
  o.least_squares_rounds = options.least_squares_rounds;
  o.snap = options.snap;
  o.feature_angle = options.feature_angle;
  o.method = options.method == "sphere" ? RemeshMethod::sphere
             : options.method == "best" ? RemeshMethod::best
                                        : RemeshMethod::decimate;
  return o;
}

std::optional<RemeshResult> remesh_for_cli(const std::string& path, const TriangleMesh& input,
                                           const RemeshCliOptions& options) {
  RemeshOptions o = to_remesh_options(options);
  ProgressBar bar("remeshing");
  o.progress = [&bar](double f) { bar.update(f); };
  try {
    return remesh(input, o);
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << path << ": " << e.what() << "\n";
    // What to do, where the input is not a mesh the remesher takes: --weld or --orient if that
    // repairs it, else the repair its problem asks for.
    const MeshReport report = validate_mesh(input);
    if (!first_problem_for_triangle_codec(report).empty()) {
      const RepairAdvice advice = repair_advice(input, report);
      const std::string hint = advice.problem.empty() && !advice.flags.empty()
                                   ? advice.flags + " repairs it: run the command again with " + advice.flags
                                   : how_to_repair(report);
      if (!hint.empty()) std::cerr << "meshlift: " << path << ": what to do: " << hint << "\n";
    }
    return std::nullopt;
  }
}

double print_remesh_summary(const std::string& path, const TriangleMesh& input, const RemeshResult& result,
                            double seconds) {
  const SemiRegularHierarchy& h = result.mesh.hierarchy;
  const double out = h.vertex_count(h.levels()), in = static_cast<double>(input.vertex_count());
  if (result.recognized) {
    std::fprintf(stderr, "%s: already semi-regular: %u base vertices, %d levels, taken over as it is\n", path.c_str(),
                 h.vertex_count(0), h.levels());
    return std::numeric_limits<double>::infinity();
  }
  std::fprintf(stderr, "%s: %.0f vertices -> %s remesh: base %zu, %d levels, %.0f vertices (%.2fx the input) in %.2f s\n",
               path.c_str(), in, result.method == RemeshMethod::sphere ? "sphere" : "decimation", result.base_vertices,
               h.levels(), out, out / in, seconds);
  std::string stages;
  for (const auto& [stage, stage_seconds] : result.stage_seconds)
    stages += (stages.empty() ? "" : ", ") + stage + " " + format_seconds(stage_seconds);
  if (!stages.empty()) std::fprintf(stderr, "%s: stages: %s\n", path.c_str(), stages.c_str());
  if (result.feature_vertices > 0)
    std::fprintf(stderr, "%s: feature lines: %zu input edges; %zu remesh vertices placed on them\n", path.c_str(),
                 result.feature_edges, result.feature_vertices);
  if (result.input_refined) {
    std::fprintf(stderr,
                 "%s: the base is the input itself and the remesh its midpoint refinement, on the input (a "
                 "small input: a smaller base would keep most of it, or remesh it short of 75 dB)\n",
                 path.c_str());
  } else if (result.method == RemeshMethod::decimate && result.density >= 1 &&
             out > 2 * std::max(result.density, 4.0) * in) {
    // A hierarchy too deep for the base the decimation can make: the vertex count runs away (cow
    // at L = 5: 67x the input's), which fewer levels avoid.
    const std::size_t asked = result.target_base_vertices;
    char why[128] = "the fewest the automatic base size takes for this mesh's topology";
    if (result.base_vertices > asked)
      std::snprintf(why, sizeof why, "the decimation stops there, above the %zu that ~%gx asks for", asked, result.density);
    std::fprintf(stderr,
                 "%s: note: %d levels over a base of %zu vertices make %.0fx the input's vertices (%s); each level "
                 "fewer divides that by about 4\n",
                 path.c_str(), h.levels(), result.base_vertices, out / in, why);
  }
  if (result.direct_levels > 0 && result.direct_levels + 1 == h.levels())
    std::fprintf(stderr, "%s: level %d placed on the finished remesh of %d levels, which has the same base\n",
                 path.c_str(), h.levels(), result.direct_levels);
  else if (result.direct_levels > 0 && result.direct_levels < h.levels())
    std::fprintf(stderr,
                 "%s: levels %d to %d placed one at a time, each on the finished remesh of the levels below it, which "
                 "has the same base\n",
                 path.c_str(), result.direct_levels + 1, h.levels());
  if (result.set_aside_refinement_folds > 0)
    std::fprintf(stderr,
                 "%s: placed from the base: placed a level at a time, the remesh folded %zu faces away from the "
                 "input's crossings\n",
                 path.c_str(), result.set_aside_refinement_folds);
  if (result.kept_vertices > 0)
    std::fprintf(stderr,
                 "%s: missing parts: the base stopped above its size and the remesh parted from the input; %zu "
                 "input vertices there kept in the base\n",
                 path.c_str(), result.kept_vertices);
  if (result.snapped_to_vertices + result.snapped_to_creases > 0)
    std::fprintf(stderr, "%s: snap: %zu remesh vertices moved onto the input's corners, %zu onto its creases\n",
                 path.c_str(), result.snapped_to_vertices, result.snapped_to_creases);
  std::fprintf(stderr, "%s: peak memory %.0f MiB\n", path.c_str(), peak_rss_mb());
  if (result.folds_searched > 0)
    std::fprintf(stderr,
                 "%s: last resort: searched the vertices around %zu folded faces the untangling left; %zu of "
                 "those searches unfolded them\n",
                 path.c_str(), result.folds_searched, result.folds_mended_by_search);
  // Which flipped faces are folds on the remesh itself (surface_fit.h: count_turned_over).
  const std::size_t turned = result.flipped_turned_over, flipped = result.flipped_triangles;
  const std::string folds = flipped == 0        ? ""
                            : turned == flipped ? " (each turned over against a neighbouring face)"
                            : turned == 0
                                ? " (none turned over against a neighbouring face: each in line with its neighbours, "
                                  "facing away only from the input's closest point)"
                                : " (" + std::to_string(turned) +
                                      " of the flipped ones turned over against a neighbouring face, the others in line "
                                      "with their neighbours but facing away from the input's closest point)";
  std::fprintf(stderr, "%s: %zu flipped and %zu degenerate triangles%s\n", path.c_str(), flipped,
               result.degenerate_triangles, folds.c_str());
  if (result.input_crossing_pairs > 0)
    std::fprintf(stderr, "%s: the input passes through itself: %zu pairs of its faces cross (`meshlift info` names one)%s\n",
                 path.c_str(), result.input_crossing_pairs,
                 result.flipped_triangles == 0 ? ""
                 : ("; " + std::to_string(result.flipped_where_input_crosses) +
                    " of the flipped triangles are there, where no orientation faces both sheets" +
                    (result.flipped_near_input_crossings > 0
                         ? ", and " + std::to_string(result.flipped_near_input_crossings) +
                               " within two faces of the crossing faces"
                         : std::string()))
                       .c_str());
  if (result.coincident_vertices > 0) {
    // Whether --weld would help: joined (and turned to agree, if need be), is the mesh still one
    // the remesher takes?
    const RepairAdvice advice = repair_advice(input, validate_mesh(input));
    std::fprintf(stderr,
                 "%s: note: %zu vertices lie exactly on other vertices without sharing their faces (an unwelded seam "
                 "or pieces, or parts that only touch): the remesh keeps them apart%s%s\n",
                 path.c_str(), result.coincident_vertices,
                 !advice.problem.empty()             ? "; joined they would not make a mesh the remesher takes: "
                 : advice.flags == "--weld"          ? "; --weld joins them first (a seam then closes)"
                                                     : "; --weld --orient joins them and turns the pieces to agree",
                 advice.problem.c_str());
  }
  const SurfaceDistance d = surface_distance(input, result.mesh.finest());
  std::fprintf(stderr, "%s: remesh error: PSNR %.2f dB, RMS %.3e and Hausdorff %.3e of the bounding-box diagonal\n",
               path.c_str(), d.psnr_db(), d.rms_relative(), d.hausdorff_relative());
  return d.psnr_db();
}

}  // namespace meshlift::cli
