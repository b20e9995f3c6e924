#include "files.h"

#include <pthread.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "meshlift/mesh_io.h"
#include "meshlift/transfer.h"

namespace meshlift::cli {

DeferredSignals::DeferredSignals() {
  sigset_t set;
  sigemptyset(&set);
  for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&set, signal);
  pthread_sigmask(SIG_BLOCK, &set, &previous_);
}

DeferredSignals::~DeferredSignals() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

bool read_bytes(const std::string& path, std::vector<std::uint8_t>& bytes, std::string& error) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    error = path + ": no such file";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) {
    error = path + ": cannot read the file";
    return false;
  }
  return true;
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes, std::string& error) {
  const DeferredSignals deferred;
  const std::string temporary = path + ".tmp-" + std::to_string(std::random_device{}());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      error = path + ": cannot write the file";
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::remove(temporary.c_str());
    error = path + ": cannot move the temporary file into place: " + ec.message();
    return false;
  }
  return true;
}

std::optional<PolygonMesh> load_mesh(const std::string& path) {
  try {
    PolygonMesh mesh = read_mesh(path);
    if (!mesh.not_read.empty()) {
      std::string kinds;
      for (const std::string& kind : mesh.not_read) kinds += (kinds.empty() ? "" : "; ") + kind;
      std::cerr << "meshlift: " << path << ": note: not read: " << kinds
                << " (meshlift keeps the positions, faces and vertex colours)\n";
    }
    return mesh;
  } catch (const MeshIOError& e) {
    std::cerr << "meshlift: " << e.what() << "\n";  // what() starts with the path
    return std::nullopt;
  }
}

TriangleMesh triangles_of(const std::string& path, PolygonMesh mesh, InputRepairs repairs) {
  TriangleMesh triangles;
  if (mesh.is_triangle_mesh()) {
    triangles = to_triangle_mesh(std::move(mesh));
  } else {
    Triangulation t = triangulate(mesh);
    std::cerr << "meshlift: " << path << ": " << describe(t) << "\n";
    triangles = std::move(t.mesh);
  }
  std::vector<std::string> notes;
  triangles = repaired(std::move(triangles), repairs, &notes);
  for (const std::string& note : notes) std::cerr << "meshlift: " << path << ": " << note << "\n";
  return triangles;
}

TriangleMesh repaired(TriangleMesh mesh, InputRepairs repairs, std::vector<std::string>* notes) {
  auto say = [&](const std::string& note) {
    if (notes) notes->push_back(note);
  };
  if (repairs.weld) {
    Welding w = weld_coincident(mesh);
    std::string note = "welded: " + std::to_string(w.joined_vertices) + " coincident vertices joined";
    if (w.dropped_faces > 0) note += "; " + std::to_string(w.dropped_faces) + " faces left with no area dropped";
    if (w.duplicate_faces > 0)
      note += "; " + std::to_string(w.duplicate_faces) + " faces that became copies of others dropped";
    say(note);
    mesh = std::move(w.mesh);
  }
  if (repairs.orient) {
    Orientation o = orient_consistently(mesh);
    std::string note = "oriented: " + std::to_string(o.flipped_faces) + " faces turned over in " +
                       std::to_string(o.fixed_components) + " components";
    if (o.unorientable_components > 0)
      note += "; " + std::to_string(o.unorientable_components) +
              " components cannot be oriented (a Moebius strip, or an edge of three or more faces): left as they were";
    say(note);
    mesh = std::move(o.mesh);
  }
  return mesh;
}

RepairAdvice repair_advice(const TriangleMesh& mesh, const MeshReport& report) {
  const bool coincident = report.duplicate_vertices > 0, turned = report.inconsistent_edges > 0;
  std::vector<InputRepairs> tries;
  if (coincident) tries.push_back({true, false});
  if (turned) tries.push_back({false, true});
  if (coincident) tries.push_back({true, true});
  RepairAdvice advice;
  for (const InputRepairs r : tries) {
    advice.flags = r.weld && r.orient ? "--weld --orient" : r.weld ? "--weld" : "--orient";
    advice.problem = first_problem_for_triangle_codec(validate_mesh(repaired(mesh, r)));
    if (advice.problem.empty()) break;
  }
  return advice;
}

std::string describe(const Triangulation& t) {
  std::string text = std::to_string(t.quads) + " quads and " + std::to_string(t.polygons) +
                     " larger polygons split into " + std::to_string(t.split_triangles) + " triangles";
  if (t.fans > 0)
    text += " (" + std::to_string(t.fans) + " of them with no ear to clip, self-intersecting or flat: split as fans)";
  if (t.repeated_corners > 0)
    text += "; " + std::to_string(t.repeated_corners) + " of them named a corner twice in a row (merged: a triangle written as a quad)";
  if (t.pinched > 0)
    text += "; " + std::to_string(t.pinched) + " came back to a corner (split there into simple loops)";
  if (t.dropped > 0) text += "; " + std::to_string(t.dropped) + " faces of fewer than 3 distinct corners left out";
  return text;
}

namespace {
template <class Mesh, class... Colours>
bool save(const std::string& path, const Mesh& mesh, bool binary, Colours... colors) {
  const DeferredSignals deferred;  // write_mesh writes a temporary file and renames it
  try {
    write_mesh(path, mesh, binary, colors...);
    return true;
  } catch (const MeshIOError& e) {
    std::cerr << "meshlift: " << e.what() << "\n";
    return false;
  }
}
}  // namespace

bool save_mesh(const std::string& path, const PolygonMesh& mesh, bool binary) { return save(path, mesh, binary); }
bool save_mesh(const std::string& path, const TriangleMesh& mesh, bool binary, std::span<const double> colors) {
  return save(path, mesh, binary, colors);
}

std::optional<InputColours> input_colours(const PolygonMesh& loaded) {
  if (loaded.colors.empty()) return std::nullopt;
  InputColours c{loaded.is_triangle_mesh() ? to_triangle_mesh(loaded) : triangulate(loaded).mesh, loaded.colors};
  return c;
}

std::optional<std::vector<double>> colours_at(const std::string& path, const InputColours& input,
                                              std::span<const double> points) {
  try {
    return transfer_vertex_values(SurfaceQuery(input.mesh), input.colors, 3, points);
  } catch (const MeshError& e) {
    std::cerr << "meshlift: " << path << ": the vertex colours: " << e.what() << "\n";
    return std::nullopt;
  }
}

std::span<const double> decoded_colours(const std::vector<VertexChannel>& channels) {
  if (channels.empty() || !channels.front().colour) return {};
  return channels.front().values;
}

}  // namespace meshlift::cli
