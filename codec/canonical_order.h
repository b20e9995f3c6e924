// The canonical order of a semi-regular mesh (codec.h, canonical_order) as a renumbering, for
// the encoder, which reads the positions through it instead of copying them. Internal to codec/.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "meshlift/semi_regular.h"

namespace meshlift {

/// The hierarchy of canonical_order(mesh) (built with the given options, see
/// SemiRegularHierarchy) and, for each of its vertices, that vertex's index in `mesh`.
struct CanonicalHierarchy {
  SemiRegularHierarchy hierarchy;
  std::vector<std::uint32_t> old_vertex;
};

/// With `concurrent`, the hierarchy's topology and the renumbering are built on two threads.
/// \throw MeshError if the positions or a channel do not match the hierarchy's vertex count.
CanonicalHierarchy canonical_hierarchy(const SemiRegularMesh& mesh, bool finest_triangles, bool coefficient_tree,
                                       bool concurrent = false);

/// Whether `mesh` is in canonical order already (a decoded mesh, canonical_order()'s output):
/// its base faces are the connectivity coder's traversal order, turned as it turns them, with the
/// vertices labelled as it labels them, and its base topology is the one the canonical hierarchy
/// builds (so every finer level is too: SemiRegularHierarchy refines the base by one fixed rule).
/// The topology of each level below the finest must be held (the encoder reads them). Costs one
/// traversal of the base. \throw MeshError as canonical_hierarchy().
bool is_canonical(const SemiRegularMesh& mesh);

/// canonical_hierarchy(), or nothing where is_canonical(mesh) (the mesh's own hierarchy is the
/// canonical one): both decided by one traversal of the base. `topology_below_finest` false
/// leaves out the topology of the level below the finest (SemiRegularHierarchy's constructor).
std::optional<CanonicalHierarchy> canonical_hierarchy_if_reordered(const SemiRegularMesh& mesh, bool finest_triangles,
                                                                   bool coefficient_tree, bool concurrent = false,
                                                                   bool topology_below_finest = true);

}  // namespace meshlift
