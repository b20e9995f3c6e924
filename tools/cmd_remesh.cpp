// `meshlift remesh IN -o OUT [--levels L] [--base-vertices N] [--fit loop|none]`: writes the
// semi-regular remesh of IN (remesh.h) with its vertices in level order, so that
// `meshlift encode OUT` takes its hierarchy over without remeshing again, and prints what it did.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "files.h"
#include "meshlift/remesh.h"
#include "meshlift/validate.h"
#include "progress.h"
#include "remesh_options.h"

namespace meshlift::cli {
namespace {

struct RemeshArgs {
  std::string input, output;
  RemeshCliOptions remesh;
  bool binary = false;
};

int run_remesh(const RemeshArgs& a) {
  if (!check_distinct_output(a.input, a.output)) return kOutputError;
  std::optional<PolygonMesh> loaded = load_mesh(a.input);
  if (!loaded) return kBadInput;
  const std::optional<InputColours> colours = input_colours(*loaded);
  const TriangleMesh input = triangles_of(a.input, std::move(*loaded), {a.remesh.weld, a.remesh.orient});
  loaded.reset();
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<RemeshResult> result = remesh_for_cli(a.input, input, a.remesh);
  if (!result) return kBadInput;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const TriangleMesh out = result->mesh.finest();
  // The input's vertex colours, read off its surface at each remesh vertex.
  std::optional<std::vector<double>> out_colours;
  if (colours && !(out_colours = colours_at(a.input, *colours, out.positions))) return kBadInput;
  if (!save_mesh(a.output, out, a.binary, out_colours ? std::span<const double>(*out_colours) : std::span<const double>()))
    return kOutputError;
  print_remesh_summary(a.input, input, *result, seconds);
  return kOk;
}

}  // namespace

void register_remesh(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<RemeshArgs>();
  auto* cmd = app.add_subcommand("remesh", "Remesh any triangle mesh to a semi-regular one (vertices in level order)");
  cmd->add_option("input", a->input, "input triangle mesh (obj, off, ply, stl)")->required();
  cmd->add_option("-o,--output", a->output, "output mesh")->required();
  add_remesh_options(*cmd, a->remesh, "--method");
  cmd->add_flag("--binary", a->binary, "binary PLY/STL output");
  cmd->callback([a, &exit_code] { exit_code = run_remesh(*a); });
}

}  // namespace meshlift::cli
