// The meshlift CLI: one file per command, each registering its subcommand on the app.
// Commands use public headers only.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

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

/// The codec options `encode` and `rd` share: --frames local|xyz, --tangent-shift N,
/// --no-base-prediction.
struct FrameArgs {
  std::string frames = "local";
  int tangent_shift = 2;
  bool no_base_prediction = false;
  bool update = true;  ///< EncodeOptions::mean_preserving_update
};
void add_frame_options(CLI::App& cmd, FrameArgs& args);
/// Sets local_frames, tangent_shift, predict_base and mean_preserving_update of `options` (an
/// EncodeOptions) from `args`.
template <class Options>
void apply_frame_options(const FrameArgs& args, Options& options) {
  options.local_frames = args.frames == "local";
  options.tangent_shift = args.tangent_shift;
  options.predict_base = !args.no_base_prediction;
  options.mean_preserving_update = args.update;
}

/// Refuses (returns false and prints why) when `output` names the same file as `input`.
bool check_distinct_output(const std::string& input, const std::string& output);

/// Peak resident set size of this process so far, in MiB (getrusage ru_maxrss, KiB on Linux).
double peak_rss_mb();

}  // namespace meshlift::cli
