// Per-vertex values (a colour) carried from a mesh onto another one that follows its surface, as
// a remesh follows its input: each new vertex takes the values of the input's surface at its
// closest point.
#pragma once

#include <span>
#include <vector>

#include "meshlift/closest_point.h"

namespace meshlift {

/// For each point of `points` (xyz triples), the values of the surface of `surface` at the
/// point's closest point (SurfaceQuery::closest): the values of that face's three corners
/// weighted by the closest point's barycentric coordinates. `values` holds `components` values
/// per vertex of surface.mesh(). A point that is a vertex of the surface gets that vertex's
/// values (its weights are 1, 0, 0); a point on an edge, the blend of the edge's two ends. The
/// result has `components` values per point, the same for any thread count (0: all cores).
/// \throw MeshError if `values` is not `components` per surface vertex, components < 1, or a
/// point is not finite.
std::vector<double> transfer_vertex_values(const SurfaceQuery& surface, std::span<const double> values, int components,
                                           std::span<const double> points, unsigned threads = 0);

}  // namespace meshlift
