// `meshlift limit IN -o OUT --scheme loop|catmull-clark`: moves every vertex to its limit point.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "meshlift/limit.h"
#include "files.h"

namespace meshlift::cli {
namespace {

struct LimitOptions {
  std::string input;
  std::string output;
  std::string scheme_name = "loop";
  bool binary = false;
};

int run_limit(const LimitOptions& options) {
  if (!check_distinct_output(options.input, options.output)) return kOutputError;
  const std::optional<PolygonMesh> loaded = load_mesh(options.input);
  if (!loaded) return kBadInput;
  const PolygonMesh& mesh = *loaded;

  PolygonMesh result;
  try {
    if (options.scheme_name == "loop") {
      if (!mesh.is_triangle_mesh()) {
        std::cerr << "meshlift: " << options.input
                  << ": the Loop limit needs a triangle mesh (use --scheme catmull-clark for polygons)\n";
        return kBadInput;
      }
      result = to_polygon_mesh(loop_limit(to_triangle_mesh(mesh)));
    } else {
      bool all_quads = true;
      for (std::size_t f = 0; f < mesh.face_count() && all_quads; ++f) all_quads = mesh.face_size(f) == 4;
      result = catmull_clark_limit(mesh);
      if (!all_quads)
        std::cerr << "meshlift: " << options.input
                  << ": not all faces are quads; writing the limit of the mesh after one Catmull-Clark step\n";
    }
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << options.input << ": " << e.what() << "\n";
    return kBadInput;
  }

  return save_mesh(options.output, result, options.binary) ? kOk : kOutputError;
}

}  // namespace

void register_limit(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<LimitOptions>();
  CLI::App* limit = app.add_subcommand(
      "limit", "Move every vertex to its limit position under Loop (triangles) or Catmull-Clark subdivision");
  limit->add_option("IN", options->input, "Input mesh file (obj, off, ply, stl)")->required();
  limit->add_option("-o,--output", options->output, "Output mesh file")->required();
  limit->add_option("--scheme", options->scheme_name, "Subdivision scheme: loop (triangles) or catmull-clark")
      ->check(CLI::IsMember({"loop", "catmull-clark"}))
      ->capture_default_str();
  limit->add_flag("--binary", options->binary, "Write binary PLY/STL");
  limit->callback([options, &exit_code] { exit_code = run_limit(*options); });
}

}  // namespace meshlift::cli
