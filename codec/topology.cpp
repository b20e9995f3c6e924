#include "meshlift/topology.h"

#include "large_array.h"

#include <algorithm>
#include <array>
#include <string>

namespace meshlift {

std::uint32_t TriangleTopology::opposite_vertex(std::uint32_t f, std::uint32_t e) const {
  const std::uint32_t a = edge_vertices[2 * e], b = edge_vertices[2 * e + 1];
  for (int i = 0; i < 3; ++i) {
    const std::uint32_t v = triangles[3 * f + i];
    if (v != a && v != b) return v;
  }
  return kNone;
}

TriangleTopology TriangleTopology::build(std::uint32_t vertex_count, std::span<const std::uint32_t> triangles) {
  if (triangles.size() % 3 != 0) throw MeshError("triangle index array length is not a multiple of 3");
  const std::size_t face_count = triangles.size() / 3;
  if (face_count >= (std::size_t{1} << 30)) throw MeshError("too many faces");
  TriangleTopology t;
  t.vertex_count = vertex_count;
  t.triangles.assign(triangles.begin(), triangles.end());
  for (std::size_t f = 0; f < face_count; ++f) {
    const std::uint32_t a = triangles[3 * f], b = triangles[3 * f + 1], c = triangles[3 * f + 2];
    if (a >= vertex_count || b >= vertex_count || c >= vertex_count)
      throw MeshError("face " + std::to_string(f) + " refers to a vertex that does not exist");
    if (a == b || b == c || c == a) throw MeshError("face " + std::to_string(f) + " repeats a vertex");
  }

  // Directed corner edges sorted by their undirected key; each key must occur once (boundary)
  // or twice in opposite directions (interior, consistently oriented).
  struct Corner {
    std::uint32_t lo, hi, face, corner;
  };
  // Sorted by (lo, hi, face), all keys distinct: a counting sort by lo (face order kept), then
  // each vertex's few corners by (hi, face). (std::sort of all corners took most of a large
  // base's build.)
  std::vector<std::uint32_t> first_of(std::size_t{vertex_count} + 1, 0);
  for (std::size_t c = 0; c < 3 * face_count; ++c) {
    const std::uint32_t a = triangles[c], b = triangles[c - c % 3 + (c + 1) % 3];
    ++first_of[std::size_t{std::min(a, b)} + 1];
  }
  for (std::uint32_t v = 0; v < vertex_count; ++v) first_of[v + 1] += first_of[v];
  std::vector<Corner> corners(3 * face_count);
  {
    std::vector<std::uint32_t> fill(first_of.begin(), first_of.end() - 1);
    for (std::uint32_t f = 0; f < face_count; ++f)
      for (std::uint32_t i = 0; i < 3; ++i) {
        const std::uint32_t a = triangles[3 * f + i], b = triangles[3 * f + (i + 1) % 3];
        corners[fill[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), f, i};
      }
  }
  for (std::uint32_t v = 0; v < vertex_count; ++v)
    std::sort(corners.begin() + first_of[v], corners.begin() + first_of[v + 1], [](const Corner& x, const Corner& y) {
      return x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
    });
  t.face_edges.assign(3 * face_count, kNone);
  t.edge_vertices.reserve(3 * face_count);  // exact for a closed mesh (E = 3F/2)
  t.edge_faces.reserve(3 * face_count);
  for (std::size_t i = 0; i < corners.size();) {
    std::size_t j = i + 1;
    while (j < corners.size() && corners[j].lo == corners[i].lo && corners[j].hi == corners[i].hi) ++j;
    auto where = [&] { return "edge (" + std::to_string(corners[i].lo) + ", " + std::to_string(corners[i].hi) + ")"; };
    if (j - i > 2) throw MeshError("non-manifold " + where() + ": " + std::to_string(j - i) + " faces share it");
    const auto e = static_cast<std::uint32_t>(t.edge_count());
    const Corner& first = corners[i];
    const std::uint32_t a = triangles[3 * first.face + first.corner];
    const std::uint32_t b = triangles[3 * first.face + (first.corner + 1) % 3];
    t.edge_vertices.insert(t.edge_vertices.end(), {a, b});
    t.edge_faces.insert(t.edge_faces.end(), {first.face, kNone});
    t.face_edges[3 * first.face + first.corner] = e;
    if (j - i == 2) {
      const Corner& second = corners[i + 1];
      if (triangles[3 * second.face + second.corner] == a)
        throw MeshError("inconsistent orientation at " + where() + ": faces " + std::to_string(first.face) +
                        " and " + std::to_string(second.face) + " run it the same way");
      t.edge_faces[2 * e + 1] = second.face;
      t.face_edges[3 * second.face + second.corner] = e;
    }
    i = j;
  }

  // Pinched vertices: the faces around each vertex must form a single fan. Walk the fan from
  // one face in both directions across the vertex's edges and compare with the face count.
  std::vector<std::uint32_t> face_count_at(vertex_count, 0), first_face(vertex_count, kNone);
  for (std::uint32_t f = 0; f < face_count; ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = triangles[3 * f + i];
      ++face_count_at[v];
      if (first_face[v] == kNone) first_face[v] = f;
    }
  auto corner_of = [&](std::uint32_t f, std::uint32_t v) {
    for (std::uint32_t i = 0; i < 3; ++i)
      if (t.triangles[3 * f + i] == v) return i;
    return 3u;
  };
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    if (first_face[v] == kNone) continue;
    std::uint32_t visited = 1;
    // Direction 0 leaves each face through the edge entering v (corner i-1 -> i), direction 1
    // through the edge leaving v (corner i -> i+1). A closed fan is walked by direction 0 alone.
    for (int direction = 0; direction < 2; ++direction) {
      std::uint32_t f = first_face[v];
      bool closed = false;
      while (visited <= face_count_at[v]) {
        const std::uint32_t i = corner_of(f, v);
        const std::uint32_t e = t.face_edges[3 * f + (direction == 0 ? (i + 2) % 3 : i)];
        const std::uint32_t next = t.edge_faces[2 * e] == f ? t.edge_faces[2 * e + 1] : t.edge_faces[2 * e];
        if (next == kNone) break;
        if (next == first_face[v]) {
          closed = true;
          break;
        }
        f = next;
        ++visited;
      }
      if (closed) break;
    }
    if (visited != face_count_at[v])
      throw MeshError("non-manifold vertex " + std::to_string(v) + ": its " + std::to_string(face_count_at[v]) +
                      " faces form more than one fan");
  }
  return t;
}

std::vector<std::uint32_t> TriangleTopology::refined_triangles() const {
  std::vector<std::uint32_t> out;
  refined_triangles(out);
  return out;
}

void TriangleTopology::refined_triangles(std::vector<std::uint32_t>& out) const {
  const std::uint32_t V = vertex_count;
  reserve_large(out, 12 * face_count());
  for (std::size_t f = 0; f < face_count(); ++f) {
    // Corner c_i keeps face (c_i, m_i, m_{i+2}); the centre face is (m_0, m_1, m_2), where m_i is
    // the odd vertex V + e on face edge i (c_i -> c_{i+1}).
    const std::uint32_t* c = &triangles[3 * f];
    const std::uint32_t m[3] = {V + face_edges[3 * f], V + face_edges[3 * f + 1], V + face_edges[3 * f + 2]};
    const std::uint32_t t[12] = {c[0], m[0], m[2], c[1], m[1], m[0], c[2], m[2], m[1], m[0], m[1], m[2]};
    out.insert(out.end(), t, t + 12);
  }
}

TriangleTopology TriangleTopology::refined() const {
  const auto V = vertex_count;
  const auto E = static_cast<std::uint32_t>(edge_count());
  const auto F = static_cast<std::uint32_t>(face_count());
  TriangleTopology r;
  r.vertex_count = V + E;
  r.triangles = refined_triangles();
  assign_large(r.edge_vertices, 2 * (2 * std::size_t{E} + 3 * F));
  assign_large(r.edge_faces, 2 * (2 * std::size_t{E} + 3 * F));
  assign_large(r.face_edges, 3 * 4 * std::size_t{F});

  // Halves: edge e = (a, b) with midpoint m becomes 2e = (a, m) and 2e+1 = (m, b), same direction;
  // the halves of a boundary edge are boundary edges (their second face is set below otherwise).
  for (std::uint32_t e = 0; e < E; ++e) {
    const std::uint32_t a = edge_vertices[2 * e], b = edge_vertices[2 * e + 1], m = V + e;
    r.edge_vertices[4 * e + 0] = a;
    r.edge_vertices[4 * e + 1] = m;
    r.edge_vertices[4 * e + 2] = m;
    r.edge_vertices[4 * e + 3] = b;
    if (is_boundary_edge(e)) r.edge_faces[4 * e + 1] = r.edge_faces[4 * e + 3] = kNone;
  }
  for (std::uint32_t f = 0; f < F; ++f) {
    std::uint32_t m[3], half_from[3], half_to[3], inner[3], slot[3];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t e = face_edges[3 * f + i];
      m[i] = V + e;
      // The half of edge i that touches corner i, and the half that touches corner i+1. Face f
      // runs edge i as stored iff it is the edge's first face; its corner faces then run both
      // halves as stored too, so they are the halves' first faces (slot 0), else their second.
      const bool forward = edge_vertices[2 * e] == triangles[3 * f + i];
      half_from[i] = forward ? 2 * e : 2 * e + 1;
      half_to[i] = forward ? 2 * e + 1 : 2 * e;
      slot[i] = forward ? 0 : 1;
    }
    // Inner edge i joins m[i+2] -> m[i+1] (parallel to face edge i, run this way by a corner face).
    for (int i = 0; i < 3; ++i) {
      inner[i] = 2 * E + 3 * f + i;
      r.edge_vertices[2 * inner[i]] = m[(i + 2) % 3];
      r.edge_vertices[2 * inner[i] + 1] = m[(i + 1) % 3];
    }
    // Corner face i (c_i, m_i, m_{i+2}): half of edge i at c_i, inner edge i+1, half of edge i+2
    // at c_i. Centre face (m0, m1, m2): inner edges 2, 0, 1, each run backwards.
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t face = 4 * f + i;
      std::uint32_t* fe = &r.face_edges[3 * face];
      fe[0] = half_from[i];
      fe[1] = inner[(i + 1) % 3];
      fe[2] = half_to[(i + 2) % 3];
      r.edge_faces[2 * half_from[i] + slot[i]] = face;
      r.edge_faces[2 * inner[(i + 1) % 3]] = face;
      r.edge_faces[2 * half_to[(i + 2) % 3] + slot[(i + 2) % 3]] = face;
    }
    std::uint32_t* centre = &r.face_edges[3 * (4 * f + 3)];
    centre[0] = inner[2];
    centre[1] = inner[0];
    centre[2] = inner[1];
    for (int i = 0; i < 3; ++i) r.edge_faces[2 * inner[i] + 1] = 4 * f + 3;
  }
  return r;
}

VertexEdges::VertexEdges(const TriangleTopology& topology) {
  const std::uint32_t V = topology.vertex_count;
  assign_large(offsets, std::size_t{V} + 1, 0u);
  assign_large(boundary, V, std::uint8_t{0});
  for (std::size_t e = 0; e < topology.edge_count(); ++e) {
    ++offsets[topology.edge_vertices[2 * e] + 1];
    ++offsets[topology.edge_vertices[2 * e + 1] + 1];
  }
  for (std::uint32_t v = 0; v < V; ++v) offsets[v + 1] += offsets[v];
  assign_large(edges, offsets[V], 0u);
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::uint32_t e = 0; e < topology.edge_count(); ++e) {
    const std::uint32_t a = topology.edge_vertices[2 * e], b = topology.edge_vertices[2 * e + 1];
    edges[fill[a]++] = e;
    edges[fill[b]++] = e;
    if (topology.is_boundary_edge(e)) boundary[a] = boundary[b] = 1;
  }
}

}  // namespace meshlift
