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
  /// Input faces left out: fewer than 3 corners, or fewer than 3 distinct ones in a row.
  std::size_t dropped = 0;
  /// Quads and polygons that name a corner twice in a row ("a b c c": a triangle written as a
  /// quad, as some exporters do); the repeats were merged before splitting.
  std::size_t repeated_corners = 0;
  /// Quads and polygons that come back to a corner further on ("a b c a d e", pinched like an
  /// 8): split there into simple loops ("a b c" and "a d e"), each triangulated on its own.
  std::size_t pinched = 0;
  /// Faces with no ear to clip at some point (self-intersecting, or with no area in any plane):
  /// their remaining corners were split as a fan from one corner.
  std::size_t fans = 0;
};

/// Triangulates every face of `mesh` that is not a triangle by ear clipping (Meisters 1975) in
/// the plane of its Newell normal (the area-weighted normal of a non-planar polygon): an ear is a
/// corner turning the polygon's way whose triangle holds no other corner; among the ears the one
/// whose triangle has the largest smallest angle is clipped first, so a quad is split along the
/// diagonal that makes the better-shaped pair (the shorter one of a rectangle). Before that, a
/// face's corners repeated in a row are merged and the face is cut into simple loops where it
/// comes back to a corner (`repeated_corners`, `pinched`); loops of fewer than 3 corners have no
/// area and are left out, and a face left with none is counted in `dropped`, as are faces of
/// fewer than 3 corners. Triangles pass through unchanged. Loops of more than 64 corners are
/// split as fans from their first corner (exact for convex ones; a non-convex one is counted in
/// `fans`). \throw MeshError if a face names a vertex that does not exist.
Triangulation triangulate(const PolygonMesh& mesh);

}  // namespace meshlift
