// Faces of a triangle mesh that cut through each other: the input's self-intersections.
//
// A surface that passes through itself (a scan's tail through its body, two fingers merged by a
// modeller) has no single outward side where its sheets cross: near the crossing curve the
// closest face of one sheet faces one way and the other sheet's another. The remesher's fold
// test compares a face with the input's normal at its closest point (find_fold_overs()), so it
// reports the faces it finds there separately (remesh.h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

/// Pairs {f, g}, f < g, of triangles of `mesh` that intersect other than in the corners they
/// share: two faces with no common corner where an edge of one crosses the other, and two faces
/// with one common corner where the edge opposite it in one crosses the other. Faces that share
/// an edge, coplanar overlaps and touching without crossing are not reported. Candidates come
/// from Embree's BVH-against-BVH query (rtcCollide) on the faces' boxes; each is decided by
/// orientation tests in double precision (a segment pq crosses triangle abc when p and q are on
/// strictly opposite sides of abc's plane and pq passes strictly inside its three edges: the
/// signed volumes [p,q,a,b], [p,q,b,c], [p,q,c,a] have one sign; Möller and Trumbore's test in
/// the form of Shewchuk's orient3d, without exact arithmetic). At most `max_pairs` pairs are
/// returned (the lowest, in order); `total`, if given, receives how many there are.
/// \throw MeshError if an index names no vertex or a coordinate is not finite or beyond ±1e30
///        (float range, which the BVH holds).
std::vector<std::array<std::uint32_t, 2>> self_intersections(const TriangleMesh& mesh, std::size_t max_pairs = SIZE_MAX,
                                                             std::size_t* total = nullptr);

/// The faces of `mesh` within `rings` rings of the faces marked in `marked` (one per face, nonzero:
/// marked) but not marked themselves: 1 for a face that shares a corner with a marked face, or
/// (rings 2 and more) with such a face, and so on; 0 for the others. Where the input passes
/// through itself, the faces next to the crossing faces are where a remesh spanning both sheets
/// turns over too (docs/RESULTS.md: mannequin-devil's folds off the crossings lie within 2 rings).
/// \pre marked.size() == mesh.face_count(), every index names a vertex.
std::vector<std::uint8_t> faces_near_marked(const TriangleMesh& mesh, const std::vector<std::uint8_t>& marked, int rings);

}  // namespace meshlift
