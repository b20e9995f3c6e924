// `meshlift info FILE [--json]`: reads a mesh file and prints its validation report.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "meshlift/mesh_io.h"
#include "meshlift/validate.h"

namespace meshlift::cli {
namespace {

struct InfoOptions {
  std::string file;
  bool json = false;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

int run_info(const InfoOptions& options) {
  if (lower_extension(options.file) == ".mlz") {
    // Compressed streams: the container reader is not built yet; `info` will report the header here.
    std::cerr << "meshlift: " << options.file << ": .mlz files are not supported by info yet\n";
    return kBadInput;
  }
  MeshReport report;
  try {
    report = validate_mesh(read_mesh(options.file));
  } catch (const MeshIOError& e) {
    // MeshIOError messages already start with the file name.
    std::cerr << "meshlift: " << e.what() << "\n";
    return kBadInput;
  }
  std::cout << (options.json ? to_json(report) : to_text(report));
  return kOk;
}

}  // namespace

void register_info(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* info = app.add_subcommand("info", "Read a mesh file (obj, off, ply, stl) and report its topology and defects");
  info->add_option("FILE", options->file, "Mesh file to inspect")->required();
  info->add_flag("--json", options->json, "Print the report as JSON");
  info->callback([options, &exit_code] { exit_code = run_info(*options); });
}

}  // namespace meshlift::cli
