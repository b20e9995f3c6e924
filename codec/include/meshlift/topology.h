// Edge-based connectivity of a manifold, consistently oriented triangle mesh, as flat arrays.
// No half-edge objects: the hot paths only ever see the stencil tables built from this.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

struct TriangleTopology {
  std::uint32_t vertex_count = 0;
  /// 3 per face, counter-clockwise.
  std::vector<std::uint32_t> triangles;
  /// 2 per edge: (a, b), oriented as face edge_faces[2e] traverses it.
  std::vector<std::uint32_t> edge_vertices;
  /// 2 per edge: the face that runs a->b, then the face that runs b->a (kNone on a boundary edge).
  std::vector<std::uint32_t> edge_faces;
  /// 3 per face: face_edges[3f+i] is the edge from corner i to corner i+1.
  std::vector<std::uint32_t> face_edges;

  std::size_t face_count() const { return triangles.size() / 3; }
  std::size_t edge_count() const { return edge_vertices.size() / 2; }
  bool is_boundary_edge(std::uint32_t e) const { return edge_faces[2 * e + 1] == kNone; }
  /// The vertex of face f that is not on edge e (f must contain e).
  std::uint32_t opposite_vertex(std::uint32_t f, std::uint32_t e) const;

  /// Builds the connectivity of `triangles` over `vertex_count` vertices.
  /// \throw MeshError naming the first offending element if an index is out of range, a face
  ///        repeats a vertex, an edge has more than two faces, two faces disagree on orientation,
  ///        or a vertex's faces form more than one fan (pinched vertex).
  static TriangleTopology build(std::uint32_t vertex_count, std::span<const std::uint32_t> triangles);

  /// One 1:4 split. The new (odd) vertex on edge e gets index vertex_count + e; edge e becomes
  /// edges 2e (a side) and 2e+1 (b side); face f's three inner edges are 2E + 3f + i, inner edge i
  /// parallel to face edge i; face f becomes faces 4f..4f+3 (corner a, corner b, corner c, centre).
  TriangleTopology refined() const;
  /// The ends (a, b) of edge e of refined(), read off this level without building it, as
  /// refined() stores them: edge p = (x, y) with midpoint m = vertex_count + p gives the halves
  /// 2p = (x, m) and 2p + 1 = (m, y); face f's inner edge 2E + 3f + i joins the midpoints of its
  /// edges i + 2 and i + 1.
  void refined_edge(std::uint32_t e, std::uint32_t& a, std::uint32_t& b) const {
    const std::uint32_t V = vertex_count, E = static_cast<std::uint32_t>(edge_count());
    if (e < 2 * E) {
      const std::uint32_t p = e / 2, m = V + p;
      a = e % 2 == 0 ? edge_vertices[2 * std::size_t{p}] : m;
      b = e % 2 == 0 ? m : edge_vertices[2 * std::size_t{p} + 1];
    } else {
      const std::uint32_t f = (e - 2 * E) / 3, i = (e - 2 * E) % 3;
      a = V + face_edges[3 * std::size_t{f} + (i + 2) % 3];
      b = V + face_edges[3 * std::size_t{f} + (i + 1) % 3];
    }
  }
  /// The faces of refined() alone (the same numbering), without its edges.
  std::vector<std::uint32_t> refined_triangles() const;
  /// The same in `out`, whose storage is kept if it can hold them (for a caller that reuses it).
  void refined_triangles(std::vector<std::uint32_t>& out) const;
};

/// Per-vertex facts derived from a topology: valence, boundary flag, incident edges (CSR).
struct VertexEdges {
  std::vector<std::uint32_t> offsets;  ///< vertex_count + 1 entries
  std::vector<std::uint32_t> edges;    ///< incident edge ids, grouped by vertex
  std::vector<std::uint8_t> boundary;  ///< 1 if the vertex lies on a boundary edge

  explicit VertexEdges(const TriangleTopology& topology);
  std::uint32_t valence(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
};

}  // namespace meshlift
