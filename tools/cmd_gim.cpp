// `meshlift gim IN -o OUT.png|OUT.gim [--size n]`: the spherical geometry image of a closed genus-0
// mesh (spherical parametrization, octahedral unfolding, n × n samples; geometry_image.h).
// `meshlift gim --to-mesh IMG -o OUT`: the image back as the semi-regular mesh it is (the
// octahedron refined L times, n = 2^(L+1) + 1), vertices in level order.
// File formats: geometry_image_file.h and docs/CLI.md.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "files.h"
#include "meshlift/geometry_image.h"
#include "meshlift/geometry_image_file.h"
#include "meshlift/mesh_io.h"
#include "meshlift/spherical_parametrization.h"

namespace meshlift::cli {
namespace {

struct GimCommandOptions {
  std::string input;
  std::string to_mesh;
  std::string output;
  int size = 257;
  bool binary = false;
};

int run_to_mesh(const GimCommandOptions& options) {
  if (!check_distinct_output(options.to_mesh, options.output)) return kOutputError;
  GeometryImage image;
  try {
    image = read_geometry_image(options.to_mesh);
  } catch (const MeshIOError& e) {
    std::cerr << "meshlift: " << e.what() << "\n";
    return kBadInput;
  }
  const SemiRegularMesh mesh = image_to_mesh(image);
  std::cerr << "meshlift: " << options.to_mesh << ": " << image.size << " x " << image.size << " image -> "
            << mesh.hierarchy.vertex_count(mesh.hierarchy.levels()) << " vertices (octahedron refined "
            << mesh.hierarchy.levels() << " times)\n";
  return save_mesh(options.output, mesh.finest(), options.binary) ? kOk : kOutputError;
}

int run_gim(const GimCommandOptions& options) {
  if (!options.to_mesh.empty() && !options.input.empty()) {
    std::cerr << "meshlift gim: give either an input mesh or --to-mesh IMG, not both\n";
    return kUsage;
  }
  if (!options.to_mesh.empty()) return run_to_mesh(options);
  if (options.input.empty()) {
    std::cerr << "meshlift gim: give an input mesh, or --to-mesh IMG\n";
    return kUsage;
  }
  int levels = 0;
  try {
    levels = geometry_image_levels(options.size);
  } catch (const MeshError& e) {
    std::cerr << "meshlift gim: --size: " << e.what() << "\n";
    return kUsage;
  }
  if (!check_distinct_output(options.input, options.output)) return kOutputError;
  std::optional<PolygonMesh> loaded = load_mesh(options.input);
  if (!loaded) return kBadInput;
  const TriangleMesh mesh = triangles_of(options.input, std::move(*loaded));
  loaded.reset();
  SphereRemesh remesh{refine_linear(octahedron(), 0), {}};
  const auto start = std::chrono::steady_clock::now();
  try {
    remesh = remesh_sphere_detailed(mesh, levels);
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << options.input << ": " << e.what() << "\n";
    return kBadInput;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SphericalParametrization& p = remesh.parametrization;
  char line[256];
  std::snprintf(line, sizeof line,
                "%zu vertices on the sphere in %.2f s: stretch %.4f, %zu flipped and %zu degenerate triangles, "
                "coverage %.9f\n",
                mesh.vertex_count(), seconds, p.stretch, p.check.flipped_triangles, p.check.degenerate_triangles,
                p.check.coverage);
  std::cerr << "meshlift: " << options.input << ": " << line;
  try {
    const DeferredSignals deferred;  // the image is written to a temporary file and renamed
    write_geometry_image(options.output, mesh_to_image(remesh.mesh));
  } catch (const MeshIOError& e) {
    std::cerr << "meshlift: " << e.what() << "\n";
    return kOutputError;
  }
  return kOk;
}

}  // namespace

void register_gim(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<GimCommandOptions>();
  CLI::App* gim = app.add_subcommand(
      "gim", "Write the spherical geometry image of a closed genus-0 mesh (.png 16-bit or .gim float), or turn one "
             "back into a mesh with --to-mesh");
  gim->add_option("IN", options->input, "Input mesh file (obj, off, ply, stl): closed, manifold, genus 0");
  gim->add_option("--to-mesh", options->to_mesh, "Geometry image (.png or .gim) to write out as a mesh instead");
  gim->add_option("-o,--output", options->output, "Output image (.png or .gim), or mesh with --to-mesh")->required();
  gim->add_option("--size", options->size, "Image side n = 2^(L+1) + 1: 3, 5, 9, ..., 65, 129, 257, 513, ..., 4097")
      ->capture_default_str();
  gim->add_flag("--binary", options->binary, "Write binary PLY/STL (with --to-mesh)");
  gim->callback([options, &exit_code] { exit_code = run_gim(*options); });
}

}  // namespace meshlift::cli
