// Mesh files in and out (OBJ, OFF, PLY, STL): OFF is read by meshlift's own reader
// (remesh/off_reader.h), the other formats and every writer go through OpenMesh.
#pragma once

#include <stdexcept>
#include <string>

#include "meshlift/mesh.h"

namespace meshlift {

/// A mesh file could not be read or written. what() is one line naming the file and the problem.
class MeshIOError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads an .obj, .off, .ply (ascii or binary) or .stl (ascii or binary) file; the extension
/// (case-insensitive) picks the format.
///
/// Vertices and faces are kept exactly as the file lists them, in file order, even when the
/// mesh is non-manifold, has repeated or isolated vertices or degenerate faces: validate_mesh()
/// is the place that judges them. Three exceptions come from the OpenMesh readers themselves:
/// - the STL reader merges bit-identical points into one vertex;
/// - the OBJ reader removes repeated corners from a face and drops the face if fewer than three
///   remain (OFF and PLY keep such faces);
/// - every reader parses coordinates as 32-bit floats (OpenMesh 9's OBJ/PLY/STL readers have no
///   double path, and the OFF reader rounds the same way), so positions carry float precision
///   whatever the file holds.
///
/// OFF: ascii `[ST][C][N][4][n]OFF` with comments anywhere; binary OFF is refused. Errors name
/// the element and the line. Before OpenMesh sees an OBJ, PLY or STL file, it is checked for what
/// makes OpenMesh's readers loop forever, exhaust memory or hit an assertion (element or list
/// counts larger than the file, malformed PLY headers, OBJ corners without a vertex index); such
/// files are rejected.
///
/// \throw MeshIOError if the file is missing or unreadable, the extension is unknown, the
///        pre-check or the reader rejects the contents, a face has no corners or references a
///        vertex that does not exist, the file holds no vertex, or the contents claim more
///        elements than the file has bytes.
/// \note  Not thread-safe for OBJ, PLY and STL: OpenMesh's IOManager and its log streams are
///        process-wide.
PolygonMesh read_mesh(const std::string& path);

/// Writes `mesh` to `path`, the format chosen by the extension (.obj, .off, .ply, .stl);
/// `binary` selects binary PLY/STL and is ignored for OBJ and OFF.
///
/// The file is written to `path + ".tmp-XXXXXXXX"` in the same directory and renamed over
/// `path` only when complete, so an interrupted write never leaves a partial file at `path`.
/// Written straight from the arrays, faces as given (non-manifold ones too). Coordinates are
/// stored as 32-bit floats (PLY's `property float`, binary STL's), in the ascii formats as the
/// shortest digits that read back to the same float. PLY face lists count corners in a uchar,
/// or an int where a face has more than 255; STL gets each triangle's unit normal.
///
/// \pre   face_offsets is consistent and every index names an existing vertex.
/// \throw MeshIOError if the extension is unknown, the mesh breaks the precondition, a face has
///        fewer than 3 corners or repeats one, a coordinate is outside the float range, STL is
///        asked to store a non-triangle face, or the file cannot be written or renamed.
void write_mesh(const std::string& path, const PolygonMesh& mesh, bool binary = false);

/// Same as the PolygonMesh overload, for a triangle mesh.
void write_mesh(const std::string& path, const TriangleMesh& mesh, bool binary = false);

}  // namespace meshlift
