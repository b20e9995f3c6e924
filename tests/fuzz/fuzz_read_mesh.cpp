// Fuzz target: one mesh reader through the public API (read_mesh, then validate_mesh as
// `meshlift info` does, then the triangulation and the --weld and --orient repairs). Built once per format; MESHLIFT_FUZZ_EXTENSION names it ("obj", ...).
// read_mesh takes a path with an extension, so each input is written to a per-process file on
// /dev/shm (memory-backed) first.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "fuzz_check.h"
#include "meshlift/mesh_io.h"
#include "meshlift/orient.h"
#include "meshlift/triangulate.h"
#include "meshlift/validate.h"
#include "meshlift/weld.h"

#ifndef MESHLIFT_FUZZ_EXTENSION
#error "define MESHLIFT_FUZZ_EXTENSION"
#endif

namespace {

const std::string& input_path() {
  static const std::string path = [] {
    const char* directory = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    return std::string(directory) + "/meshlift_fuzz_" + std::to_string(getpid()) + "." + MESHLIFT_FUZZ_EXTENSION;
  }();
  return path;
}

struct RemoveAtExit {
  ~RemoveAtExit() { std::remove(input_path().c_str()); }
} remove_at_exit;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace meshlift;
  {
    std::FILE* file = std::fopen(input_path().c_str(), "wb");
    if (!file) fuzz::violated("cannot write the input file");
    if (size > 0 && std::fwrite(data, 1, size, file) != size) fuzz::violated("short write");
    std::fclose(file);
  }
  PolygonMesh mesh;
  try {
    mesh = read_mesh(input_path());
  } catch (const MeshIOError& e) {
    if (std::string(e.what()).rfind(input_path(), 0) != 0) fuzz::violated("MeshIOError does not start with the path");
    return 0;
  }
  if (mesh.vertex_count() == 0) fuzz::violated("read_mesh returned no vertices");
  if (mesh.face_offsets.empty() || mesh.face_offsets.front() != 0 || mesh.face_offsets.back() != mesh.face_indices.size())
    fuzz::violated("face_offsets");
  for (std::uint32_t i : mesh.face_indices)
    if (i >= mesh.vertex_count()) fuzz::violated("face index out of range");
  const MeshReport report = validate_mesh(mesh);
  (void)to_text(report);
  (void)to_json(report);
  (void)first_problem_for_triangle_codec(report);
  // What remesh, encode and rd make of it before the remesher: polygons split (triangulate.h),
  // then the --weld and --orient repairs; each gives a triangle mesh on the same vertex range.
  const Triangulation split = triangulate(mesh);
  if (split.mesh.triangles.size() % 3 != 0) fuzz::violated("triangulate: not triangles");
  for (std::uint32_t i : split.mesh.triangles)
    if (i >= split.mesh.vertex_count()) fuzz::violated("triangulate: index out of range");
  const Welding welded = weld_coincident(split.mesh);
  if (welded.mesh.vertex_count() + welded.joined_vertices != split.mesh.vertex_count())
    fuzz::violated("weld: vertices lost or made");
  if (welded.mesh.face_count() + welded.dropped_faces + welded.duplicate_faces != split.mesh.face_count())
    fuzz::violated("weld: faces lost or made");
  for (std::uint32_t i : welded.mesh.triangles)
    if (i >= welded.mesh.vertex_count()) fuzz::violated("weld: index out of range");
  const Orientation oriented = orient_consistently(welded.mesh);
  if (oriented.mesh.positions.size() != welded.mesh.positions.size() ||
      std::memcmp(oriented.mesh.positions.data(), welded.mesh.positions.data(),
                  welded.mesh.positions.size() * sizeof(double)) != 0 ||
      oriented.mesh.face_count() != welded.mesh.face_count())
    fuzz::violated("orient: changed more than turns");
  (void)validate_mesh(oriented.mesh);
  return 0;
}
