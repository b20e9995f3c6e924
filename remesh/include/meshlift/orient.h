// Making a mesh's face orientation consistent: files whose faces were written in either turn
// (some CAD and STL exporters, shuffled test files). validate.h names the first edge that two
// faces traverse the same way; this turns faces over until none does.
#pragma once

#include <cstddef>

#include "meshlift/mesh.h"

namespace meshlift {

struct Orientation {
  TriangleMesh mesh;                 ///< the same vertices and faces, some with their turn reversed
  std::size_t flipped_faces = 0;     ///< faces whose turn was reversed
  std::size_t fixed_components = 0;  ///< components with faces whose turn was reversed
  /// Components whose faces cannot all agree (a Möbius strip) or that have an edge of more than
  /// two faces (no orientation is defined there): left as they were, for the validation to name.
  std::size_t unorientable_components = 0;
};

/// Each connected component (faces joined through edges of exactly two faces) is oriented from
/// its first face on, every face taking the turn that traverses its shared edges opposite to its
/// neighbour's. A component that needs no face turned is left as it is; otherwise a closed one
/// takes the turn of positive signed volume (faces facing outwards) and an open one the turn most
/// of its faces had (fewest flips). Deterministic; a consistently oriented mesh comes back
/// unchanged.
/// \pre every index of `mesh.triangles` is below its vertex count (read_mesh guarantees it).
Orientation orient_consistently(const TriangleMesh& mesh);

}  // namespace meshlift
