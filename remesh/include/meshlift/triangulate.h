// Polygon meshes -> triangle meshes, for the stages that take triangles (remesh, encode, rd,
// compare, gim): quads and larger faces split by ear clipping in their own plane.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

struct Triangulation {
  /// The same vertices; each face of n corners as n − 2 triangles, in face order, oriented as the
  /// face (every triangle's corners in the face's cyclic order).
  TriangleMesh mesh;
  std::size_t quads = 0;     ///< input faces of 4 corners
  std::size_t polygons = 0;  ///< input faces of 5 or more corners
  std::size_t split_triangles = 0;  ///< the triangles those quads and polygons became
  std::size_t dropped = 0;          ///< input faces of fewer than 3 corners, left out
  /// Faces with no ear to clip at some point (self-intersecting, or with no area in any plane):
  /// their remaining corners were split as a fan from one corner.
  std::size_t fans = 0;
};

/// Triangulates every face of `mesh` that is not a triangle by ear clipping (Meisters 1975) in
/// the plane of its Newell normal (the area-weighted normal of a non-planar polygon): an ear is a
/// corner turning the polygon's way whose triangle holds no other corner; among the ears the one
/// whose triangle has the largest smallest angle is clipped first, so a quad is split along the
/// diagonal that makes the better-shaped pair (the shorter one of a rectangle). Faces with fewer
/// than 3 corners (no surface) are left out and counted. Triangles pass through unchanged.
/// Faces of more than 64 corners are split as fans from their first corner (exact for convex
/// ones; a non-convex one is counted in `fans`). \throw MeshError if a face names a vertex that
/// does not exist.
Triangulation triangulate(const PolygonMesh& mesh);

}  // namespace meshlift
