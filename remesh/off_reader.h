// meshlift's own reader of ascii OFF (Geomview's Object File Format), used by read_mesh for
// .off files in place of OpenMesh's, whose mixed token and line reading trusted every count
// (docs/HARDENING.md). Internal to remesh/.
#pragma once

#include <string>
#include <string_view>

#include "meshlift/mesh.h"
#include "meshlift/mesh_io.h"

namespace meshlift {

/// Parses `text`, the whole contents of the OFF file `path` (used in messages only).
///
/// The grammar (Geomview manual, "OFF"), read as one stream of tokens separated by white space;
/// `#` starts a comment that runs to the end of its line, anywhere (also right after a number:
/// `0.9 0 0#red`). Lines end with LF, CRLF or a lone CR. A leading UTF-8 byte-order mark is skipped.
/// - Header keyword `[ST][C][N][4][n]OFF`, optional (a file may start with its counts). `nOFF`
///   is followed by the vertex dimension, which must be 3. `OFF BINARY` is refused: binary OFF
///   is not read.
/// - Counts `V F [E]`: they may share the keyword's line (`OFF 8 12 0`); E, whatever else is on
///   F's line, is ignored.
/// - V vertices: 3 coordinates (4 with `4`: x y z w, stored as x/w y/w z/w), then on the same
///   line the extras the prefixes declare, at least: N a normal (3 numbers), C a colour (3 or 4),
///   ST texture coordinates (2), in that order. Too few extras is an error. Of them only the
///   colour is kept (PolygonMesh::colors: red, green, blue; three integers are 0-255, else the
///   three are decimals 0-1, Geomview's two forms; each clamped to [0, 1]); anything after them
///   on the line is ignored.
/// - F faces: `n i_1 .. i_n` with 3 <= n <= V and 0 <= i_k < V; the rest of the line of i_n
///   (the face colour, present with or without the C prefix) is ignored.
/// - Anything after the last face is ignored.
/// So each record is its required tokens, which may run across lines as the spec allows, and
/// an optional tail to the end of the line of its last required token: the one rule that makes
/// colours of any arity harmless. Coordinates are parsed as 32-bit floats, rounded as strtof
/// rounds (as OpenMesh's reader did; every libcgal-demo file reads identically, see
/// tests/remesh/test_off_reader.cpp); NaN, infinities and values beyond the float range are
/// refused, values below it become zero.
///
/// Before anything is reserved, V and F are checked against the bytes after the counts (each
/// token takes at least 2 bytes: a vertex its 3 or 4 coordinates, a face at least its corner
/// count), and each face's n against V and the bytes left (2 per corner): memory stays within a
/// small multiple of the file size.
///
/// \return the vertices and faces in file order, kept as they are (repeated corners included:
///         validate_mesh judges them).
/// \throw MeshIOError "path: problem (line L)", naming the vertex or face and the offending
///        token, e.g. "face 12 references vertex 99 but the file has 24 vertices (line 40)".
PolygonMesh read_off(const std::string& path, std::string_view text);

}  // namespace meshlift
