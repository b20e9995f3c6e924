// The meshlift CLI: one file per command, each registering its subcommand on the app.
// Commands use public headers only.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

#include "meshlift/codec.h"

namespace meshlift::cli {

/// Exit codes shared by every command (docs/CLI.md lists them).
enum Exit : int {
  kOk = 0,
  kUsage = 2,        ///< bad arguments (CLI11 parse errors also exit with this)
  kBadInput = 3,     ///< the input mesh/file is unreadable, malformed or unsuitable
  kOutputError = 4,  ///< the output could not be written, or would overwrite an input
  kInternal = 70,    ///< a bug: please report
};

/// CLI11's Range and PositiveNumber let "nan" through (every comparison with NaN is false): chained
/// after them on an option that takes a real number, this refuses NaN and the infinities.
inline const CLI::Validator kFinite(
    [](std::string& text) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      return end != text.c_str() && *end == '\0' && std::isfinite(value) ? std::string() : "not a finite number: " + text;
    },
    "FINITE");

/// Each register_* adds a subcommand whose callback sets `exit_code`.
void register_info(CLI::App& app, int& exit_code);
void register_subdivide(CLI::App& app, int& exit_code);
void register_limit(CLI::App& app, int& exit_code);
void register_fit(CLI::App& app, int& exit_code);
void register_encode(CLI::App& app, int& exit_code);
void register_decode(CLI::App& app, int& exit_code);
void register_truncate(CLI::App& app, int& exit_code);
void register_stream(CLI::App& app, int& exit_code);
void register_compare(CLI::App& app, int& exit_code);
void register_rd(CLI::App& app, int& exit_code);
void register_remesh(CLI::App& app, int& exit_code);
void register_gim(CLI::App& app, int& exit_code);

/// --tangent-shift when none is given: the library's default, 4x coarser tangents (2) ...
inline constexpr int kDefaultTangentShift = EncodeOptions{}.tangent_shift;
/// ... or, where the remesh follows the input's feature lines (RemeshResult::feature_vertices),
/// this one if it measures closer to the input (choose_tangent_shift).
inline constexpr int kCreaseTangentShift = 1;

/// The codec options `encode` and `rd` share: --frames local|xyz, --tangent-shift N,
/// --no-base-prediction.
struct FrameArgs {
  std::string frames = "local";
  /// -1 where --tangent-shift is not given: kDefaultTangentShift, or what choose_tangent_shift()
  /// measures closer where the remesh follows feature lines.
  int tangent_shift = -1;
  bool no_base_prediction = false;
  bool update = true;  ///< EncodeOptions::mean_preserving_update
};
void add_frame_options(CLI::App& cmd, FrameArgs& args);
/// Sets local_frames, tangent_shift, predict_base and mean_preserving_update of `options` (an
/// EncodeOptions) from `args`.
template <class Options>
void apply_frame_options(const FrameArgs& args, Options& options) {
  options.local_frames = args.frames == "local";
  options.tangent_shift = args.tangent_shift < 0 ? kDefaultTangentShift : args.tangent_shift;
  options.predict_base = !args.no_base_prediction;
  options.mean_preserving_update = args.update;
}

/// What choose_tangent_shift() chose, with the mean PSNR of the prefixes it measured (over the
/// rates both shifts decode at) for it and for the other shift.
struct TangentChoice {
  int shift = kDefaultTangentShift;
  double db = 0;
  int other_shift = kCreaseTangentShift;
  double other_db = 0;
};
/// The tangent shift to code `mesh` with where --tangent-shift is not given and the remesh follows
/// the input's feature lines: kCreaseTangentShift if its stream's prefixes at kTangentChoiceBpv
/// bits per input vertex decode closer to the input, by `psnr` (METRIC.md's PSNR against the
/// input) averaged over the rates, than kDefaultTangentShift's; else the default. Across a crease
/// a tangential error cuts the corner, so CAD parts can pay for finer tangents where smooth
/// surfaces do not: fandisk's BD-rate against Draco -63.8 -> -68.9 %, but blade's would go -71.5
/// -> -70.7 % (so the choice is measured, not taken for every such part), and the smooth meshes
/// of the BD table would move by -0.6 to +0.3 points (docs/RESULTS.md, "Finer tangents where the
/// remesh follows creases"). `options` are the encode's, tangent_shift aside; two encodes and
/// eight decodes.
TangentChoice choose_tangent_shift(const SemiRegularMesh& mesh, EncodeOptions options, std::size_t input_vertices,
                                   const std::function<double(const TriangleMesh&)>& psnr);
/// The rates (bits per input vertex) choose_tangent_shift() compares at: the steep part of the
/// curves, where the two shifts part (fandisk 1.0-2.5 dB at 0.75-3 bpv; blade 0.7-1.9 dB the
/// other way at 1-3); above ~8 bpv the remesh's own error dominates both.
inline constexpr double kTangentChoiceBpv[] = {1, 2, 4, 8};

/// Refuses (returns false and prints why) when `output` names the same file as `input`.
bool check_distinct_output(const std::string& input, const std::string& output);

/// Peak resident set size of this process so far, in MiB (getrusage ru_maxrss, KiB on Linux).
double peak_rss_mb();

}  // namespace meshlift::cli
