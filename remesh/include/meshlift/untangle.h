// Untangling the folds a remesh has left (the fitting stage has no fold-free guarantee,
// surface_fit.h): each connected patch of folded faces, grown by a few rings, is flattened onto
// the plane of the input's normals there, its inner vertices re-embedded by Tutte's barycentric
// mapping with the patch's rim fixed (Tutte 1963; Floater 1997: a convex rim gives an embedding
// without fold-overs), and lifted back onto the input along that normal. A patch is kept only
// if it has fewer folded faces than before; else it grows (1, 2, 3, 5, 8 rings) and is tried again.
#pragma once

#include <cstddef>

#include "meshlift/closest_point.h"
#include "meshlift/semi_regular.h"

namespace meshlift {

struct UntangleOptions {
  /// Rings of faces added around a patch of folded faces at the first try (>= 1) and at most
  /// (>= first_rings); each failed try adds half as many again (1, 2, 3, 5, 8). Measured on the
  /// corpus (L = 3, ~4x): one ring more per try left camel 28 folded faces, cow 52, turbine 71,
  /// mannequin-devil 70 in 2-2.5x the time; doubling (1, 2, 4, 8) left 20, 53, 88, 67 but one
  /// on armadillo at ~2x; this sequence leaves 27, 52, 63, 78 and none on armadillo.
  int first_rings = 1;
  int max_rings = 8;
  /// Passes over all patches (>= 0); they stop early when a pass keeps no patch.
  int passes = 8;
};

struct UntangleReport {
  std::size_t folded_before = 0, folded_after = 0;
  std::size_t patches_tried = 0, patches_kept = 0;
};

/// Untangles the finest level of `mesh` (all its vertices may move, boundary vertices of the
/// mesh excepted) against the input `surface`. A face counts as folded as find_fold_overs()
/// judges: its normal more than 90° from the input's normal at the closest point of its
/// centroid. \throw std::invalid_argument if an option is out of range.
UntangleReport untangle(SemiRegularMesh& mesh, const SurfaceQuery& surface, const UntangleOptions& options = {});

}  // namespace meshlift
