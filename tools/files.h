// Byte files for the CLI: whole-file reads, and writes that go to a temporary file in the same
// directory and are renamed into place, so a failed or interrupted run never leaves a partial file.
#pragma once

#include <signal.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/semi_regular.h"
#include "meshlift/triangulate.h"
#include "meshlift/validate.h"
#include "meshlift/orient.h"
#include "meshlift/weld.h"

namespace meshlift::cli {

/// Holds back SIGINT, SIGTERM, SIGHUP and SIGQUIT for its lifetime. Outputs are written to a
/// temporary file and renamed into place inside one of these (write_bytes and save_mesh do it
/// themselves), so a signal that arrives meanwhile is delivered only after the rename, or after
/// the temporary file was removed on failure: an interrupted run leaves the complete output or
/// none, never a partial or temporary file. (SIGKILL cannot be held back.)
class DeferredSignals {
 public:
  DeferredSignals();
  ~DeferredSignals();
  DeferredSignals(const DeferredSignals&) = delete;
  DeferredSignals& operator=(const DeferredSignals&) = delete;

 private:
  sigset_t previous_;
};

/// Reads a whole file; returns false and sets `error` (one line) on failure.
bool read_bytes(const std::string& path, std::vector<std::uint8_t>& bytes, std::string& error);
/// Writes atomically (temporary file + rename); returns false and sets `error` on failure.
bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes, std::string& error);

/// Reads an input mesh; on failure prints `meshlift: PATH: problem` and returns nullopt. What the
/// file held besides positions, faces and vertex colours gets a note (`meshlift: PATH: note: not
/// read: texture coordinates (OBJ vt) (8 lines); ...`, PolygonMesh::not_read).
std::optional<PolygonMesh> load_mesh(const std::string& path);
/// `mesh` as triangles: as it is, or with its other faces split by triangulate() (triangulate.h)
/// and a note on standard error (`meshlift: PATH: 6 quads and 0 larger polygons split into 12
/// triangles`, how many had no ear and were split as fans, and how many faces of fewer than 3
/// corners were left out). Then the repairs asked for, each with a note: `weld`, the vertices at
/// exactly the same position joined (weld.h; `meshlift: PATH: welded: N coincident vertices
/// joined ...`); `orient`, the faces turned to agree (orient.h; `meshlift: PATH: oriented: ...`).
struct InputRepairs {
  bool weld = false, orient = false;
};
/// Takes `mesh` by value: a caller done with it moves it in, and its arrays are taken over.
TriangleMesh triangles_of(const std::string& path, PolygonMesh mesh, InputRepairs repairs = {});
/// `mesh` with the repairs asked for, in that order (weld, then orient); each adds its note.
TriangleMesh repaired(TriangleMesh mesh, InputRepairs repairs, std::vector<std::string>* notes = nullptr);
/// For a mesh whose vertices coincide or whose faces disagree in turn (`report` is its
/// validation): the first of --weld (where vertices coincide), --orient (where faces disagree) and
/// --weld --orient (where vertices coincide) after which it is a mesh the remesher takes, in
/// `flags` with `problem` empty; else the last one tried and the problem it leaves (`flags`
/// empty when neither repair applies).
struct RepairAdvice {
  std::string flags, problem;
};
RepairAdvice repair_advice(const TriangleMesh& mesh, const MeshReport& report);
/// That note's text for a triangulation: `6 quads and 0 larger polygons split into 12 triangles`, ...
std::string describe(const Triangulation& t);

/// Writes an output mesh; on failure prints the one-line error and returns false. `colors`: the
/// vertices' red, green, blue in [0, 1], or empty (mesh_io.h: write_mesh).
bool save_mesh(const std::string& path, const PolygonMesh& mesh, bool binary);
bool save_mesh(const std::string& path, const TriangleMesh& mesh, bool binary, std::span<const double> colors = {});

/// An input's vertex colours (PolygonMesh::colors) and the surface they belong to: the input as
/// read, triangulated, before any repair (which may join or drop vertices).
struct InputColours {
  TriangleMesh mesh;
  std::vector<double> colors;
};
/// `loaded`'s colours, or nullopt if it has none.
std::optional<InputColours> input_colours(const PolygonMesh& loaded);
/// The input's colours at `points` (xyz triples, e.g. a remesh's vertices): those of its surface at
/// each point's closest point (transfer.h). On failure prints the one-line error and returns
/// nullopt.
std::optional<std::vector<double>> colours_at(const std::string& path, const InputColours& input,
                                              std::span<const double> points);
/// A decoded stream's colours: its first channel's values where the stream marks it as the
/// colour (FORMAT.md §3, flag bit 3), else empty.
std::span<const double> decoded_colours(const std::vector<VertexChannel>& channels);

}  // namespace meshlift::cli
