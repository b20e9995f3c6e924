// Local frames for the geometry details (issue 3; PGC, Khodakovsky, Schroeder, Sweldens 2000 §4;
// normal meshes, Guskov et al. 2000; V-DMC codes normal-only displacements by default,
// CODEC-NOTES §8). A detail of a remeshed surface points mostly along the surface normal: in
// x, y, z all three components carry it, in a (normal, tangent, tangent) frame one does, and the
// two tangential ones may be quantized more coarsely (FORMAT.md §3, tangent_shift).
//
// The frame of the odd vertex on edge e = (a, b) of level j is computed from the mesh of level
// j alone, which both sides hold before level j + 1 is synthesized (the decoder exactly so at
// full rate, since the encoder quantizes in closed loop, encoder.cpp):
//   n  = normalize(N_a + N_b), N_v = sum over the faces around v of (p1 - p0) x (p2 - p0)
//        (area-weighted vertex normals of level j);
//   t1 = normalize((p_b - p_a) - n ((p_b - p_a) . n)): the edge direction in the tangent plane;
//   t2 = n x t1.
// Degenerate cases fall back deterministically: n = 0 -> the identity frame (x, y, z); an edge
// along n -> t1 from the coordinate axis least aligned with n.
#pragma once

#include <span>

#include "meshlift/semi_regular.h"

namespace meshlift::frames {

enum class Direction {
  to_local,   ///< (x, y, z) -> (n, t1, t2): d_local = R^T d, R = [n t1 t2]
  to_global,  ///< (n, t1, t2) -> (x, y, z): d = R d_local
};

/// Rotates the details of the odd vertices of level `level` + 1 (vertices vertex_count(level) ..
/// vertex_count(level + 1) - 1 of `details`) by the frames of the level-`level` mesh whose
/// positions are the first vertex_count(level) vertices of `coarse`. Both arrays hold `stride`
/// values per vertex, geometry first; only the three geometry values of the odd vertices change.
/// `coarse` and `details` may be the same array (the ranges read and written are disjoint).
void rotate_details(const SemiRegularHierarchy& hierarchy, int level, std::span<const double> coarse,
                    std::span<double> details, int stride, Direction direction);

}  // namespace meshlift::frames
