// meshlift's own reader of Wavefront OBJ geometry, used by read_mesh for .obj files in place of
// OpenMesh's, which parsed each line through a string stream (13.7 s of a 3.3 M-vertex file's
// 15 s) after a pre-scan of its own, and dropped faces that repeat a corner. Internal to remesh/.
#pragma once

#include <string>
#include <string_view>

#include "meshlift/mesh.h"
#include "meshlift/mesh_io.h"

namespace meshlift {

/// Parses `text`, the whole contents of the OBJ file `path` (used in messages only).
///
/// Read line by line (LF, CRLF or a lone CR end a line); `#` starts a comment to the end of
/// its line. What is kept:
/// - `v x y z [...]`: a vertex; the three coordinates are parsed as 32-bit floats, rounded as
///   strtof rounds (as OpenMesh's reader did). Exactly three more numbers after them are the
///   vertex's colour, red, green, blue in [0, 1] (`v x y z r g b`, as MeshLab writes it), kept
///   (PolygonMesh::colors, clamped to [0, 1]) where every vertex has one; anything else after
///   them (w) is ignored. A missing coordinate, NaN, an infinity or a value beyond the float
///   range is an error.
/// - `f c_1 c_2 ...`: a face, its corners as written (repeated ones included: validate_mesh
///   judges them). A corner is `v`, `v/vt`, `v//vn` or `v/vt/vn`; only v is read: a positive
///   index counts from 1, a negative one back from the last vertex read so far (-1 is the last),
///   and 0 or one beyond the vertices becomes an out-of-range index, which read_mesh reports by
///   face. A corner without a vertex index, or an index that is not an integer, is an error.
/// - Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is skipped.
/// Memory stays within a small multiple of the file size: every vertex and corner kept takes
/// two bytes of the file at least.
///
/// \throw MeshIOError "path: OBJ line L: problem", e.g. "OBJ line 12: a vertex coordinate is
///        missing or not a finite number", or "path: face F has no corners" for an `f` alone.
PolygonMesh read_obj(const std::string& path, std::string_view text);

}  // namespace meshlift
