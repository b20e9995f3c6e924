// `meshlift compare REF TEST [--samples N] [--threads T] [--json]`: Metro-style symmetric surface
// distance of TEST from REF (metric.h, docs/METRIC.md), and where both have vertex colours, how far
// TEST's are from REF's.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "json_text.h"
#include "files.h"
#include "meshlift/metric.h"

namespace meshlift::cli {
namespace {

struct CompareOptions {
  std::string reference;
  std::string test;
  std::size_t samples = 0;
  unsigned threads = 0;
  std::uint64_t seed = MetricOptions{}.seed;
  bool json = false;
};

/// JSON has no infinity: an infinite PSNR (identical surfaces) is written as null.
std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

void print_json_side(const char* name, const OneSidedDistance& d, double diagonal, bool last) {
  std::cout << "  \"" << name << "\": {\"rms\": " << json_number(d.rms) << ", \"mean\": " << json_number(d.mean)
            << ", \"max\": " << json_number(d.max) << ", \"rms_relative\": " << json_number(d.rms / diagonal)
            << ", \"mean_relative\": " << json_number(d.mean / diagonal)
            << ", \"max_relative\": " << json_number(d.max / diagonal) << ", \"area_samples\": " << d.area_samples
            << ", \"vertex_samples\": " << d.vertex_samples << "}" << (last ? "\n" : ",\n");
}

/// How far a mesh's vertex colours are from a reference's: at each vertex, the reference's colour
/// at its closest point on the reference (transfer.h) against its own, over all vertices and the
/// three components; colours in [0, 1].
struct ColourError {
  double rms = 0, mean = 0, max = 0;
  /// 20 log10(1 / rms): colours have a peak of 1.
  double psnr_db() const { return 20 * std::log10(1 / rms); }
};

int run_compare(const CompareOptions& options) {
  std::optional<PolygonMesh> reference = load_mesh(options.reference);
  if (!reference) return kBadInput;
  std::optional<PolygonMesh> test = load_mesh(options.test);
  if (!test) return kBadInput;
  const std::optional<InputColours> reference_colours = input_colours(*reference);
  const std::vector<double> test_colours = test->colors;
  const TriangleMesh reference_triangles = triangles_of(options.reference, std::move(*reference));
  const TriangleMesh test_triangles = triangles_of(options.test, std::move(*test));
  if (reference_triangles.face_count() == 0) {
    std::cerr << "meshlift: " << options.reference << ": the mesh has no faces: nothing to compare\n";
    return kBadInput;
  }
  if (test_triangles.face_count() == 0) {
    std::cerr << "meshlift: " << options.test << ": the mesh has no faces: nothing to compare\n";
    return kBadInput;
  }

  MetricOptions metric;
  metric.samples = options.samples;
  metric.threads = options.threads;
  metric.seed = options.seed;
  SurfaceDistance d;
  try {
    d = surface_distance(reference_triangles, test_triangles, metric);
  } catch (const MeshError& e) {
    // The message starts with "reference mesh" or "test mesh".
    std::cerr << "meshlift: compare " << options.reference << " " << options.test << ": " << e.what() << "\n";
    return kBadInput;
  }
  if (!d.warning.empty()) std::cerr << "meshlift: warning: " << d.warning << "\n";
  std::optional<ColourError> colour;
  if (reference_colours && !test_colours.empty()) {
    const std::optional<std::vector<double>> expected = colours_at(options.reference, *reference_colours, test_triangles.positions);
    if (!expected) return kBadInput;
    ColourError e;
    for (std::size_t i = 0; i < test_colours.size(); ++i) {
      const double difference = std::abs(test_colours[i] - (*expected)[i]);
      e.rms += difference * difference;
      e.mean += difference;
      e.max = std::max(e.max, difference);
    }
    e.rms = std::sqrt(e.rms / static_cast<double>(test_colours.size()));
    e.mean /= static_cast<double>(test_colours.size());
    colour = e;
  }

  if (options.json) {
    std::cout << "{\n  \"reference\": " << json_string(options.reference) << ",\n  \"test\": "
              << json_string(options.test) << ",\n  \"diagonal\": " << json_number(d.diagonal) << ",\n";
    print_json_side("reference_to_test", d.reference_to_test, d.diagonal, false);
    print_json_side("test_to_reference", d.test_to_reference, d.diagonal, false);
    std::cout << "  \"rms\": " << json_number(d.rms) << ",\n  \"mean\": " << json_number(d.mean)
              << ",\n  \"hausdorff\": " << json_number(d.hausdorff) << ",\n  \"rms_relative\": "
              << json_number(d.rms_relative()) << ",\n  \"mean_relative\": " << json_number(d.mean_relative())
              << ",\n  \"hausdorff_relative\": " << json_number(d.hausdorff_relative())
              << ",\n  \"psnr_db\": " << json_number(d.psnr_db());
    if (colour)
      std::cout << ",\n  \"colour\": {\"rms\": " << json_number(colour->rms) << ", \"mean\": " << json_number(colour->mean)
                << ", \"max\": " << json_number(colour->max) << ", \"psnr_db\": " << json_number(colour->psnr_db()) << "}";
    std::cout << ",\n  \"warning\": " << json_string(d.warning) << "\n}\n";
    return kOk;
  }
  std::printf("reference: %s (%zu vertices, %zu triangles), bounding-box diagonal %.6g\n", options.reference.c_str(),
              reference_triangles.vertex_count(), reference_triangles.face_count(), d.diagonal);
  std::printf("test:      %s (%zu vertices, %zu triangles)\n", options.test.c_str(), test_triangles.vertex_count(),
              test_triangles.face_count());
  std::printf("samples:   %zu area samples + %zu vertices on the reference, %zu + %zu on the test\n",
              d.reference_to_test.area_samples, d.reference_to_test.vertex_samples, d.test_to_reference.area_samples,
              d.test_to_reference.vertex_samples);
  std::printf("%-18s %14s %14s %14s   (relative to the diagonal: rms, mean, max)\n", "", "RMS", "mean", "max");
  auto row = [&](const char* name, double rms, double mean, double max) {
    std::printf("%-18s %14.6e %14.6e %14.6e   %.3e %.3e %.3e\n", name, rms, mean, max, rms / d.diagonal,
                mean / d.diagonal, max / d.diagonal);
  };
  row("reference -> test", d.reference_to_test.rms, d.reference_to_test.mean, d.reference_to_test.max);
  row("test -> reference", d.test_to_reference.rms, d.test_to_reference.mean, d.test_to_reference.max);
  row("symmetric (max)", d.rms, d.mean, d.hausdorff);
  std::printf("PSNR: %.3f dB (20 log10(diagonal / symmetric RMS))\n", d.psnr_db());
  if (colour)
    std::printf("colour: RMS %.3e, mean %.3e, max %.3e of the range (mean %.2f of 255), PSNR %.2f dB (the reference's "
                "colour at each test vertex's closest point against the test's)\n",
                colour->rms, colour->mean, colour->max, 255 * colour->mean, colour->psnr_db());
  return kOk;
}

}  // namespace

void register_compare(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Symmetric surface distance of TEST from REF (Metro-style RMS, mean, Hausdorff, PSNR)");
  cmd->add_option("REF", options->reference, "Reference mesh (its bounding-box diagonal normalizes)")->required();
  cmd->add_option("TEST", options->test, "Mesh compared with the reference")->required();
  cmd->add_option("--samples", options->samples,
                  "Area samples per surface (default 0: 10 per face of the larger mesh, within 100k..1M)");
  cmd->add_option("--threads", options->threads, "Worker threads (default 0: all cores; results do not depend on it)");
  cmd->add_option("--seed", options->seed, "Seed of the sample positions (default: the metric's fixed seed)");
  cmd->add_flag("--json", options->json, "Print the figures as JSON");
  cmd->callback([options, &exit_code] { exit_code = run_compare(*options); });
}

}  // namespace meshlift::cli
