// `meshlift fit IN -o OUT --scheme loop|catmull-clark [--iterations N] [--tolerance T]`: writes a
// control mesh whose limit surface passes through the input vertices (interpolate.h).
// One stderr line per iteration (its residual), then a summary. If the residual has not reached
// the tolerance within the iterations, the last control mesh is still written, the summary says
// "not converged", and the exit code is 0: the result is valid, only less exact than asked.
// Mesh files store 32-bit float coordinates (mesh_io.h), so the written mesh interpolates
// only to about 1e-7 x diagonal; the summary also prints the residual of the written positions.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "files.h"
#include "meshlift/interpolate.h"
#include "meshlift/limit.h"
#include "meshlift/polygon_subdivision.h"

namespace meshlift::cli {
namespace {

struct FitCommandOptions {
  std::string input;
  std::string output;
  std::string scheme_name = "loop";
  FitOptions fit;
  bool binary = false;
};

void print_residuals(const FitResult& result) {
  char line[128];
  for (std::size_t k = 0; k < result.residuals.size(); ++k) {
    const double relative = result.diagonal > 0 ? result.residuals[k] / result.diagonal : 0.0;
    std::snprintf(line, sizeof line, "iteration %zu: max residual %.3e (%.3e x diagonal)\n", k, result.residuals[k],
                  relative);
    std::cerr << line;
  }
}

void print_summary(const std::string& input, const FitResult& result, double tolerance) {
  const double relative = result.diagonal > 0 ? result.residuals.back() / result.diagonal : 0.0;
  char line[256];
  if (result.converged)
    std::snprintf(line, sizeof line, "converged after %d iterations: max residual %.3e x diagonal <= %.3e\n",
                  result.iterations(), relative, tolerance);
  else
    std::snprintf(line, sizeof line,
                  "not converged after %d iterations: max residual %.3e x diagonal > %.3e; writing the last control "
                  "mesh (more --iterations or a larger --tolerance)\n",
                  result.iterations(), relative, tolerance);
  std::cerr << "meshlift: " << input << ": " << line;
}

/// max |P - A C| with C rounded to float as the writers store it; `targets` are the points fitted.
double written_residual(const FitResult& result, const std::vector<double>& targets, bool loop) {
  std::vector<double> rounded(result.control.positions.size()), limit(rounded.size());
  for (std::size_t i = 0; i < rounded.size(); ++i) rounded[i] = static_cast<float>(result.control.positions[i]);
  if (loop)
    apply_loop_limit(to_triangle_mesh(result.control), rounded, limit);
  else
    apply_catmull_clark_limit(result.control, rounded, limit);
  double worst = 0;
  for (std::size_t v = 0; 3 * v < limit.size(); ++v)
    worst = std::max(worst, std::hypot(targets[3 * v] - limit[3 * v], targets[3 * v + 1] - limit[3 * v + 1],
                                       targets[3 * v + 2] - limit[3 * v + 2]));
  return worst;
}

int run_fit(const FitCommandOptions& options) {
  if (!check_distinct_output(options.input, options.output)) return kOutputError;
  const std::optional<PolygonMesh> loaded = load_mesh(options.input);
  if (!loaded) return kBadInput;
  const PolygonMesh& mesh = *loaded;

  const bool loop = options.scheme_name == "loop";
  FitResult result;
  double written = 0;
  try {
    if (loop) {
      if (!mesh.is_triangle_mesh()) {
        std::cerr << "meshlift: " << options.input
                  << ": the Loop fit needs a triangle mesh (use --scheme catmull-clark for polygons)\n";
        return kBadInput;
      }
      result = fit_loop(to_triangle_mesh(mesh), options.fit);
    } else {
      result = fit_catmull_clark(mesh, options.fit);
      if (result.subdivided_first)
        std::cerr << "meshlift: " << options.input
                  << ": not all faces are quads; fitting the vertices of the mesh after one Catmull-Clark step\n";
    }
    written = written_residual(result, result.subdivided_first ? catmull_clark(mesh, 1).positions : mesh.positions, loop);
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << options.input << ": " << e.what() << "\n";
    return kBadInput;
  }

  print_residuals(result);
  print_summary(options.input, result, options.fit.tolerance);
  if (result.diagonal > 0) {
    char line[128];
    std::snprintf(line, sizeof line, "written as 32-bit floats: max residual %.3e x diagonal\n", written / result.diagonal);
    std::cerr << "meshlift: " << options.output << ": " << line;
  }
  return save_mesh(options.output, result.control, options.binary) ? kOk : kOutputError;
}

}  // namespace

void register_fit(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<FitCommandOptions>();
  CLI::App* fit = app.add_subcommand(
      "fit", "Write a control mesh whose Loop or Catmull-Clark limit surface passes through the input vertices");
  fit->add_option("IN", options->input, "Input mesh file (obj, off, ply, stl)")->required();
  fit->add_option("-o,--output", options->output, "Output control mesh file")->required();
  fit->add_option("--scheme", options->scheme_name, "Subdivision scheme: loop (triangles) or catmull-clark")
      ->check(CLI::IsMember({"loop", "catmull-clark"}))
      ->capture_default_str();
  fit->add_option("--iterations", options->fit.max_iterations, "Most iterations")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  fit->add_option("--tolerance", options->fit.tolerance,
                  "Stop when the max distance of a limit point from its input vertex is at most this x the "
                  "bounding-box diagonal")
      ->check(CLI::Range(0.0, 1.0) & kFinite)
      ->capture_default_str();
  fit->add_flag("--binary", options->binary, "Write binary PLY/STL");
  fit->callback([options, &exit_code] { exit_code = run_fit(*options); });
}

}  // namespace meshlift::cli
