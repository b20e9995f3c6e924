// The canonical order of a semi-regular mesh (codec.h, canonical_order) as a renumbering, for
// the encoder, which reads the positions through it instead of copying them. Internal to codec/.
#pragma once

#include <cstdint>
#include <vector>

#include "meshlift/semi_regular.h"

namespace meshlift {

/// The hierarchy of canonical_order(mesh) (built with the given options, see
/// SemiRegularHierarchy) and, for each of its vertices, that vertex's index in `mesh`.
struct CanonicalHierarchy {
  SemiRegularHierarchy hierarchy;
  std::vector<std::uint32_t> old_vertex;
};

/// \throw MeshError if the positions or a channel do not match the hierarchy's vertex count.
CanonicalHierarchy canonical_hierarchy(const SemiRegularMesh& mesh, bool finest_triangles, bool coefficient_tree);

}  // namespace meshlift
