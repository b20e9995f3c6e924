// The remeshing options and steps that `meshlift remesh` and `meshlift encode` share.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "meshlift/remesh.h"

namespace meshlift::cli {

struct RemeshCliOptions {
  std::string method = "decimate";
  int levels = 3;
  std::size_t base_vertices = 0;
  std::string density = "auto";
  std::string fit = "loop";
  int least_squares_rounds = RemeshOptions{}.least_squares_rounds;
  bool snap = false;
  double feature_angle = RemeshOptions{}.feature_angle;
  bool weld = false, orient = false;
};

/// Adds `method_flag` (--method for remesh, --remesh for encode), --levels, --base-vertices and
/// --density, --fit, --least-squares, --snap, --feature-angle, --weld and --orient to `cmd`.
void add_remesh_options(CLI::App& cmd, RemeshCliOptions& options, const std::string& method_flag);

/// The library options the command-line ones stand for (no progress callback).
RemeshOptions to_remesh_options(const RemeshCliOptions& options);

/// Remeshes `input` (read from `path`, triangulated by triangles_of()) with a progress bar; on
/// failure prints `meshlift: PATH: problem` and returns nullopt.
std::optional<RemeshResult> remesh_for_cli(const std::string& path, const TriangleMesh& input,
                                           const RemeshCliOptions& options);

/// Prints what the remesh did: vertex counts, levels, fold-overs, time (one line each); returns
/// the remesh's PSNR against the input (metric.h), infinity for an input taken over as it is.
double print_remesh_summary(const std::string& path, const TriangleMesh& input, const RemeshResult& result,
                            double seconds);

}  // namespace meshlift::cli
