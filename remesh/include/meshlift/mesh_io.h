// Mesh files in and out (OBJ, OFF, PLY, STL), by meshlift's own readers (remesh/off_reader.h,
// ply_reader.h, obj_reader.h, stl_reader.h) and writers (mesh_io.cpp).
#pragma once

#include <stdexcept>
#include <span>
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
/// mesh is non-manifold, has repeated or isolated vertices or degenerate faces (repeated
/// corners included): validate_mesh() is the place that judges them. STL stores each triangle's
/// corners apart: its reader merges corners at the same point into one vertex. Coordinates of
/// the text formats and of PLY `float` properties are parsed as 32-bit floats (rounded as strtof
/// rounds); PLY `double` properties are kept as doubles.
///
/// Positions, faces and vertex colours are read; what else the file holds is read past and
/// listed in PolygonMesh::not_read (OBJ texture coordinates, normals, materials, points, lines
/// and free-form geometry, by lines; PLY vertex and face properties by name, other elements with
/// their counts; OFF normals and texture coordinates its header declares).
///
/// Each reader checks every count against the bytes of the file before it reserves anything,
/// and names the element, line or item of a problem; the grammars they accept are in their
/// headers. Readers hold no shared state: any number may run at once.
///
/// \throw MeshIOError if the file is missing or unreadable, the extension is unknown, the reader
///        rejects the contents, a face has no corners or references a vertex that does not
///        exist, or the file holds no vertex.
PolygonMesh read_mesh(const std::string& path);

/// Writes `mesh` to `path`, the format chosen by the extension (.obj, .off, .ply, .stl);
/// `binary` selects binary PLY/STL and is ignored for OBJ and OFF.
///
/// The file is written to `path + ".tmp-XXXXXXXX"` in the same directory and renamed over
/// `path` only when complete, so an interrupted write never leaves a partial file at `path`.
/// Written straight from the arrays, faces as given (non-manifold ones too). Coordinates are
/// stored as 32-bit floats (PLY's `property float`, binary STL's), in the ascii formats as the
/// shortest digits that read back to the same float. PLY face lists count corners in a uchar,
/// or an int where a face has more than 255; STL gets each triangle's unit normal. Vertex colours
/// (PolygonMesh::colors, if any) are stored as bytes, round(255 c): PLY `uchar red, green, blue`,
/// OFF as `COFF` with 0-255 integers, OBJ as `v x y z r g b` with r = byte / 255; STL has none.
///
/// \pre   face_offsets is consistent and every index names an existing vertex.
/// \throw MeshIOError if the extension is unknown, the mesh breaks the precondition, a face has
///        fewer than 3 corners or repeats one, a coordinate is outside the float range, STL is
///        asked to store a non-triangle face, colours are not 3 per vertex, or the file cannot be
///        written or renamed.
void write_mesh(const std::string& path, const PolygonMesh& mesh, bool binary = false);

/// The same for a triangle mesh, with `colors` (red, green, blue per vertex in [0, 1], or empty)
/// as write_mesh(PolygonMesh) writes PolygonMesh::colors.
void write_mesh(const std::string& path, const TriangleMesh& mesh, bool binary = false,
                std::span<const double> colors = {});

}  // namespace meshlift
