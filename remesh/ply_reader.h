// meshlift's own reader of PLY (Turk's polygon file format, ascii and binary), used by read_mesh
// for .ply files in place of OpenMesh's, which read a value at a time through a stream and
// trusted every count (docs/HARDENING.md): 2.2 s of a 3.3 M-vertex binary file's 2.5 s went
// there. Internal to remesh/.
#pragma once

#include <string>
#include <string_view>

#include "meshlift/mesh.h"
#include "meshlift/mesh_io.h"

namespace meshlift {

/// Parses `bytes`, the whole contents of the PLY file `path` (used in messages only).
///
/// The format (Turk 1994; Bourke's "PLY - Polygon File Format"):
/// - Header, one item per line (LF or CRLF): `ply`; `format ascii|binary_little_endian|
///   binary_big_endian 1.0`; `comment ...` and `obj_info ...` (skipped); `element NAME COUNT`
///   (COUNT plain digits); `property TYPE NAME` or `property list COUNT_TYPE TYPE NAME`, each
///   for the element above it; `end_header`. TYPE is one of char uchar short ushort int uint
///   float double, or int8 uint8 int16 uint16 int32 uint32 float32 float64. Anything else is an
///   error naming the line.
/// - Body: the elements in header order, each item its properties in order: in binary, packed
///   values in the stated byte order (a list: its count, then that many values); in ascii,
///   numbers separated by white space, integers for integer types (an optional sign and digits),
///   decimals for float types (no `nan`, `inf`, hexadecimal, or values beyond the type's range).
/// - What is kept: element `vertex`, whose scalar properties `x`, `y`, `z` (any numeric type)
///   are the positions, kept as the file's values (a float exactly, a double exactly); element
///   `face`, whose list `vertex_indices` (or `vertex_index`) of integers are its corners, kept
///   as they are (a negative index becomes an out-of-range one, for read_mesh to report); and the
///   vertex colours, where element `vertex` has scalar properties `red`, `green` and `blue` (or
///   `diffuse_red`, ...), each once: an integer type's value over its largest (uchar 255), a
///   float's as it is (NaN or an infinity is an error naming the vertex), each clamped to [0, 1]
///   (PolygonMesh::colors); none where the file has several vertex elements and not all have
///   them. Every other element and property is read past.
/// - Before anything is reserved, each element's count is checked against the body's bytes (a
///   binary item takes its fixed part's bytes, an ascii item a byte per property, at least), and
///   each list's count against the bytes left: memory stays within a small multiple of the file
///   size. An element of no properties takes no bytes, whatever its count: nothing is read.
/// - Ascii numbers are read by file_text.h (shared with the other text formats).
///
/// \throw MeshIOError "path: problem", naming the element, the item and the offending value,
///        e.g. "PLY face 12: a list claims 4294967295 entries, more than the 1000 bytes left in the file", or
///        the file ending inside an element.
PolygonMesh read_ply(const std::string& path, std::string_view bytes);

}  // namespace meshlift
