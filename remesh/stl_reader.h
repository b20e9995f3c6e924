// meshlift's own reader of STL (stereolithography triangles, ascii and binary), used by read_mesh
// for .stl files in place of OpenMesh's (5.5 s of a 6.6 M-triangle binary file, merging its
// corners through an ordered map). With it, every format read_mesh takes has a reader of ours.
// Internal to remesh/.
#pragma once

#include <string>
#include <string_view>

#include "meshlift/mesh.h"
#include "meshlift/mesh_io.h"

namespace meshlift {

/// Parses `bytes`, the whole contents of the STL file `path` (used in messages only).
///
/// - Binary: an 80-byte header, a little-endian uint32 triangle count T, then T records of 50
///   bytes (a normal and three corners as little-endian 32-bit floats, and a 16-bit attribute).
///   A file is binary when its size is exactly 84 + 50 T; one that is not, and does not start
///   with `solid`, is an error naming both sizes.
/// - Ascii: `solid [name]`, then facets `facet normal nx ny nz` `outer loop` `vertex x y z` (three
///   of them) `endloop` `endfacet`, then `endsolid [name]` (optional at the end of the file),
///   perhaps followed by further solids (files of several parts: all are read). Keywords in any
///   letter case; words separated by any white space; coordinates parsed as 32-bit floats
///   (file_text.h). A facet of other than three vertices, or a word out of place, is an error.
/// STL stores each triangle's corners apart: corners at exactly the same point (as floats, so
/// -0 and +0 alike) are one vertex, numbered in the order of first use, as OpenMesh's reader
/// numbers them. Normals and attributes are ignored. NaN and infinite binary coordinates are
/// kept, each its own vertex, for validate_mesh to report.
///
/// \throw MeshIOError "path: problem", e.g. "ascii STL facet 12: expected 'vertex', found
///        'endloop'" or "binary STL claims 1000 triangles: 50084 bytes, but the file has 7000".
PolygonMesh read_stl(const std::string& path, std::string_view bytes);

}  // namespace meshlift
