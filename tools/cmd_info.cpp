// `meshlift info FILE [--json]`: a mesh file's validation report, or a .mlz stream's header,
// levels, chunks and base-mesh share.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "files.h"
#include "meshlift/codec.h"
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

bool is_stream(const std::vector<std::uint8_t>& bytes) {
  return bytes.size() >= 4 && bytes[0] == 'M' && bytes[1] == 'L' && bytes[2] == 'Z' && bytes[3] == 0x1A;
}

int run_stream_info(const InfoOptions& options, const std::vector<std::uint8_t>& bytes) {
  const StreamInfo info = inspect(bytes);
  const std::size_t base_bytes = info.header_and_connectivity_bytes;
  const auto percent = [&](std::size_t n) {
    return bytes.empty() ? 0.0 : 100.0 * static_cast<double>(n) / static_cast<double>(bytes.size());
  };
  const double share = percent(base_bytes);
  if (options.json) {
    std::cout << "{\n  \"status\": \"" << to_string(info.status) << "\",\n  \"bytes\": " << bytes.size()
              << ",\n  \"scheme\": \"" << to_string(info.scheme) << "\",\n  \"mean_preserving_update\": "
              << (info.mean_preserving_update ? "true" : "false") << ",\n  \"levels\": " << info.levels
              << ",\n  \"base_vertices\": " << info.base_vertices << ",\n  \"base_faces\": " << info.base_faces
              << ",\n  \"vertices\": " << info.vertices << ",\n  \"faces\": " << info.faces
              << ",\n  \"step\": " << info.step << ",\n  \"top_plane\": " << info.top_plane << ",\n  \"base_plane\": " << info.base_plane
              << ",\n  \"local_frames\": " << (info.local_frames ? "true" : "false")
              << ",\n  \"tangent_shift\": " << info.tangent_shift << ",\n  \"channels\": [";
    for (std::size_t i = 0; i < info.channels.size(); ++i)
      std::cout << (i ? ", " : "") << "{\"components\": " << info.channels[i].components
                << ", \"step\": " << info.channels[i].step
                << (i == 0 && info.colour ? ", \"colour\": true" : "") << "}";
    std::cout << "],\n  \"base_share_percent\": " << share << ",\n  \"base_part_bytes\": " << info.base_part_bytes
              << ",\n  \"chunks\": [";
    for (std::size_t i = 0; i < info.chunks.size(); ++i)
      std::cout << (i ? ", " : "") << "{\"tag\": \"" << info.chunks[i].tag << "\", \"offset\": " << info.chunks[i].offset
                << ", \"size\": " << info.chunks[i].size << ", \"complete\": " << (info.chunks[i].complete ? "true" : "false")
                << "}";
    std::cout << "]\n}\n";
  } else {
    std::cout << options.file << ": meshlift stream, " << bytes.size() << " bytes\n";
    if (info.status != Status::ok) std::cout << "  status:       " << to_string(info.status) << ": " << info.message << "\n";
    std::cout << "  wavelet:      " << to_string(info.scheme) << (info.mean_preserving_update ? " + mean-preserving update" : "")
              << "\n  levels:       " << info.levels << "\n  base mesh:    " << info.base_vertices << " vertices, "
              << info.base_faces << " faces\n  finest mesh:  " << info.vertices << " vertices, " << info.faces
              << " faces\n  quantization: step " << info.step << " (normalized), top bit plane " << info.top_plane
              << (info.base_plane <= info.top_plane
                      ? ", base planes " + std::to_string(info.top_plane) + ".." + std::to_string(info.base_plane) + " predicted"
                      : std::string())
              << "\n  details:      "
              << (info.local_frames ? "local frames (normal, tangents at step x 2^" + std::to_string(info.tangent_shift) + ")"
                                    : std::string("x, y, z"));
    for (std::size_t i = 0; i < info.channels.size(); ++i)
      std::cout << "\n  channel:      " << info.channels[i].components << " component(s), step " << info.channels[i].step
                << (i == 0 && info.colour ? " (the vertices' colour: red, green, blue)" : "");
    std::cout << "\n  header + base connectivity: " << base_bytes << " bytes (" << share << " % of the file)";
    if (info.base_part_bytes > 0)
      std::cout << "\n  base part:    " << info.base_part_bytes << " bytes (" << percent(info.base_part_bytes)
                << " % of the file: the base positions' top planes, FORMAT.md 5.1)";
    std::cout << "\n  chunks:\n";
    for (const auto& c : info.chunks)
      std::cout << "    " << c.tag << " at " << c.offset << ": " << c.size << " bytes" << (c.complete ? "" : " (incomplete)")
                << "\n";
  }
  if (info.status != Status::ok) {
    std::cerr << "meshlift: " << options.file << ": " << to_string(info.status) << " (error "
              << static_cast<int>(info.status) << "): " << info.message << "\n";
    return kBadInput;
  }
  return kOk;
}

int run_info(const InfoOptions& options) {
  std::vector<std::uint8_t> head;
  std::string error;
  if (lower_extension(options.file) == ".mlz" || (read_bytes(options.file, head, error) && is_stream(head))) {
    if (head.empty() && !read_bytes(options.file, head, error)) {
      std::cerr << "meshlift: " << error << "\n";
      return kBadInput;
    }
    return run_stream_info(options, head);
  }
  const std::optional<PolygonMesh> mesh = load_mesh(options.file);
  if (!mesh) return kBadInput;
  MeshReport report = validate_mesh(*mesh);
  add_self_intersections(*mesh, report);
  std::cout << (options.json ? to_json(report) : to_text(report));
  if (options.json || report.invalid_index_faces > 0) return kOk;
  TriangleMesh triangles;
  MeshReport triangle_report;
  if (report.non_triangle_faces > 0) {
    // What encode and remesh take: the polygons split into triangles (triangulate.h).
    Triangulation t = triangulate(*mesh);
    triangle_report = validate_mesh(t.mesh);
    const std::string problem = first_problem_for_triangle_codec(triangle_report);
    std::cout << "as encode takes it:      " << describe(t) << "; triangle codec "
              << (problem.empty() ? std::string("ok") : problem) << "\n";
    triangles = std::move(t.mesh);
  } else {
    // The same faces: the report above is theirs (validate_mesh of a TriangleMesh validates it
    // as a PolygonMesh).
    triangles = to_triangle_mesh(*mesh);
    triangle_report = std::move(report);
  }
  // Which of remesh's and encode's input repairs would help (coincident vertices, faces turned).
  const RepairAdvice advice = repair_advice(triangles, triangle_report);
  if (!advice.flags.empty())
    std::cout << "with " << advice.flags << ":" << std::string(advice.flags.size() < 19 ? 19 - advice.flags.size() : 1, ' ')
              << "triangle codec " << (advice.problem.empty() ? std::string("ok") : advice.problem)
              << " (remesh, encode and rd take the flag)\n";
  return kOk;
}

}  // namespace

void register_info(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* info = app.add_subcommand("info", "Report a mesh file's topology and defects (obj, off, ply, stl), or a .mlz stream's header and chunks");
  info->add_option("FILE", options->file, "Mesh file to inspect")->required();
  info->add_flag("--json", options->json, "Print the report as JSON");
  info->callback([options, &exit_code] { exit_code = run_info(*options); });
}

}  // namespace meshlift::cli
