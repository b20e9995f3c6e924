#include <algorithm>
#include <stdexcept>
#include <string>

#include "large_array.h"
#include "meshlift/semi_regular.h"

namespace meshlift {
namespace {

/// The faces of coarse.refined().refined_triangles(), made without the middle level: each face
/// of `coarse` gives its four children by TriangleTopology::refined()'s rule (corners and face
/// edges, their edges numbered as refined() numbers them), and each child its four faces by
/// refined_triangles()'s rule, in the same order.
void twice_refined_triangles(const TriangleTopology& coarse, std::vector<std::uint32_t>& out) {
  const std::uint32_t V = coarse.vertex_count, E = static_cast<std::uint32_t>(coarse.edge_count());
  const std::uint32_t middle_V = V + E;  // vertices of the middle level
  const std::size_t F = coarse.face_count();
  reserve_large(out, 48 * F);
  for (std::size_t f = 0; f < F; ++f) {
    const std::uint32_t* c = &coarse.triangles[3 * f];
    const std::uint32_t* fe = &coarse.face_edges[3 * f];
    std::uint32_t m[3], half_from[3], half_to[3], inner[3];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t e = fe[i];
      m[i] = V + e;
      const bool forward = coarse.edge_vertices[2 * e] == c[i];
      half_from[i] = forward ? 2 * e : 2 * e + 1;
      half_to[i] = forward ? 2 * e + 1 : 2 * e;
      inner[i] = 2 * E + 3 * static_cast<std::uint32_t>(f) + static_cast<std::uint32_t>(i);
    }
    // Children: corner face i (c_i, m_i, m_{i+2}) with face edges (half of edge i at c_i, inner
    // edge i+1, half of edge i+2 at c_i); the centre (m_0, m_1, m_2) with (inner 2, 0, 1).
    const std::uint32_t child_corners[4][3] = {{c[0], m[0], m[2]}, {c[1], m[1], m[0]}, {c[2], m[2], m[1]}, {m[0], m[1], m[2]}};
    const std::uint32_t child_edges[4][3] = {{half_from[0], inner[1], half_to[2]},
                                             {half_from[1], inner[2], half_to[0]},
                                             {half_from[2], inner[0], half_to[1]},
                                             {inner[2], inner[0], inner[1]}};
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t* cc = child_corners[k];
      const std::uint32_t mm[3] = {middle_V + child_edges[k][0], middle_V + child_edges[k][1], middle_V + child_edges[k][2]};
      const std::uint32_t t[12] = {cc[0], mm[0], mm[2], cc[1], mm[1], mm[0], cc[2], mm[2], mm[1], mm[0], mm[1], mm[2]};
      out.insert(out.end(), t, t + 12);
    }
  }
}

std::vector<std::uint32_t> twice_refined_triangles(const TriangleTopology& coarse) {
  std::vector<std::uint32_t> out;
  twice_refined_triangles(coarse, out);
  return out;
}

}  // namespace

RefinedSize refined_size(const TriangleTopology& base, int levels) {
  RefinedSize s{static_cast<double>(base.vertex_count), static_cast<double>(base.edge_count()),
                static_cast<double>(base.face_count())};
  for (int j = 0; j < levels; ++j) s = {s.vertices + s.edges, 2 * s.edges + 3 * s.faces, 4 * s.faces};
  return s;
}

SemiRegularHierarchy::SemiRegularHierarchy(TriangleTopology base, int levels, bool finest_triangles, bool coefficient_tree,
                                           bool topology_below_finest)
    : has_finest_triangles_(finest_triangles || levels == 0), has_children_(coefficient_tree) {
  if (levels < 0 || levels > kMaxLevels)
    throw MeshError("levels must be between 0 and " + std::to_string(kMaxLevels) + ", got " + std::to_string(levels));
  const RefinedSize size = refined_size(base, levels);
  if (std::max({size.vertices, size.edges, 3 * size.faces}) >= 4294967295.0)
    throw MeshError("refining " + std::to_string(base.face_count()) + " faces " + std::to_string(levels) +
                    " times exceeds 2^32 indices");
  vertex_counts_.push_back(base.vertex_count);
  topologies_.reserve(levels);
  topologies_.push_back(std::move(base));
  for (int j = 0; j < levels; ++j) {
    const TriangleTopology& coarse = topologies_.back();  // level j, or j - 1 if level j is left out
    if (static_cast<int>(topologies_.size()) == j + 1) {
      vertex_counts_.push_back(coarse.vertex_count + static_cast<std::uint32_t>(coarse.edge_count()));
      if (j + 2 < levels || (j + 2 == levels && topology_below_finest))
        topologies_.push_back(coarse.refined());
      else if (j + 1 == levels && finest_triangles)
        finest_triangles_ = coarse.refined_triangles();
    } else {
      // Level L - 1 left out: it has 2E + 3F edges of level L - 2.
      vertex_counts_.push_back(vertex_counts_.back() + static_cast<std::uint32_t>(2 * coarse.edge_count() + 3 * coarse.face_count()));
      if (finest_triangles) finest_triangles_ = twice_refined_triangles(coarse);
    }
  }

  // Coefficient tree (CODEC-NOTES §1): the odd vertex on edge p of level j-1 has as children the
  // odd vertices on the halves 2p, 2p+1 of p and on the inner edges 2E_{j-1} + 3f + i parallel to
  // p (face edge i of f) in the faces f of p, in that (ascending) order.
  if (!coefficient_tree) return;
  if (levels >= 2) assign_large(children_, 4 * std::size_t{vertex_count(levels - 1) - vertex_count(0)}, kNone);
  for (int j = 1; j < levels; ++j) {
    const TriangleTopology& coarse = topologies_[j - 1];
    const auto coarse_edges = static_cast<std::uint32_t>(coarse.edge_count());
    std::uint32_t* slots = children_.data() + 4 * std::size_t{vertex_count(j - 1) - vertex_count(0)};
    for (std::uint32_t p = 0; p < coarse_edges; ++p) {
      slots[4 * p] = odd_vertex(j, 2 * p);
      slots[4 * p + 1] = odd_vertex(j, 2 * p + 1);
    }
    for (std::uint32_t f = 0; f < coarse.face_count(); ++f)
      for (std::uint32_t i = 0; i < 3; ++i) {
        std::uint32_t* slot = slots + 4 * std::size_t{coarse.face_edges[3 * f + i]};
        slot[slot[2] == kNone ? 2 : 3] = odd_vertex(j, 2 * coarse_edges + 3 * f + i);
      }
  }
}

const TriangleTopology& SemiRegularHierarchy::topology(int level) const {
  if (level == levels() - 1 && !has_topology(level))
    throw std::logic_error("SemiRegularHierarchy::topology: this hierarchy was built without level " + std::to_string(level));
  return topologies_.at(static_cast<std::size_t>(level));
}

const std::vector<std::uint32_t>& SemiRegularHierarchy::triangles(int level) const {
  // With levels() == 0 the base is the finest level: its topology holds its faces.
  if (level < static_cast<int>(topologies_.size())) return topologies_.at(static_cast<std::size_t>(level)).triangles;
  if (level == levels() - 1)
    throw std::logic_error("SemiRegularHierarchy::triangles: this hierarchy was built without level " + std::to_string(level));
  if (level != levels()) throw std::out_of_range("SemiRegularHierarchy::triangles: no level " + std::to_string(level));
  if (!has_finest_triangles_)
    throw std::logic_error("SemiRegularHierarchy::triangles: this hierarchy was built without its finest faces");
  return finest_triangles_;
}

std::vector<std::uint32_t> SemiRegularHierarchy::copy_triangles(int level) const {
  std::vector<std::uint32_t> faces;
  copy_triangles(level, faces);
  return faces;
}

void SemiRegularHierarchy::copy_triangles(int level, std::vector<std::uint32_t>& out) const {
  const bool below_finest_held = has_topology(levels() - 1);
  if (level == levels() - 1 && !below_finest_held) return topologies_.back().refined_triangles(out);
  if (level == levels() && !has_finest_triangles_)
    return below_finest_held ? topologies_.back().refined_triangles(out) : twice_refined_triangles(topologies_.back(), out);
  const std::vector<std::uint32_t>& faces = triangles(level);
  reserve_large(out, faces.size());
  out.insert(out.end(), faces.begin(), faces.end());
}

std::vector<std::uint32_t> SemiRegularHierarchy::release_finest_triangles() && {
  std::vector<std::uint32_t> faces;
  std::move(*this).release_finest_triangles(faces);
  return faces;
}

void SemiRegularHierarchy::release_finest_triangles(std::vector<std::uint32_t>& out) && {
  if (levels() == 0 || has_finest_triangles_) {
    // Held already: handed over (the caller's storage goes with the hierarchy).
    std::vector<std::uint32_t>& held = levels() == 0 ? topologies_.back().triangles : finest_triangles_;
    out.swap(held);
  } else if (!has_topology(levels() - 1)) {
    // twice_refined_triangles() reads only the corners, edges and face edges of level L - 2.
    TriangleTopology last;
    last.vertex_count = topologies_.back().vertex_count;
    last.triangles = std::move(topologies_.back().triangles);
    last.edge_vertices = std::move(topologies_.back().edge_vertices);
    last.face_edges = std::move(topologies_.back().face_edges);
    topologies_.clear();
    children_ = std::vector<std::uint32_t>();
    twice_refined_triangles(last, out);
  } else {
    // refined_triangles() reads only the corners and face edges of level L - 1.
    TriangleTopology last;
    last.vertex_count = topologies_.back().vertex_count;
    last.triangles = std::move(topologies_.back().triangles);
    last.face_edges = std::move(topologies_.back().face_edges);
    topologies_.clear();
    children_ = std::vector<std::uint32_t>();
    last.refined_triangles(out);
  }
  vertex_counts_.clear();
  topologies_.clear();
  finest_triangles_ = std::vector<std::uint32_t>();
  children_ = std::vector<std::uint32_t>();
}

int SemiRegularHierarchy::level_of(std::uint32_t vertex) const {
  for (int j = 0; j <= levels(); ++j)
    if (vertex < vertex_count(j)) return j;
  return -1;
}

std::uint32_t SemiRegularHierarchy::parent(std::uint32_t vertex) const {
  // A vertex of level j >= 2 lies on edge e of level j-1, which came from edge p of level j-2:
  // its half if e < 2 E_{j-2}, else inner edge e - 2 E_{j-2} = 3f + i, parallel to face edge i of f.
  const int j = level_of(vertex);
  if (j < 2) return kNone;
  const TriangleTopology& coarse = topologies_[j - 2];
  const std::uint32_t e = vertex - vertex_count(j - 1);
  const auto coarse_edges = static_cast<std::uint32_t>(coarse.edge_count());
  return odd_vertex(j - 2, e < 2 * coarse_edges ? e / 2 : coarse.face_edges[e - 2 * coarse_edges]);
}

std::span<const std::uint32_t> SemiRegularHierarchy::children(std::uint32_t vertex) const {
  if (!has_children_)
    throw std::logic_error("SemiRegularHierarchy::children: this hierarchy was built without its coefficient tree");
  if (vertex < vertex_count(0) || levels() < 2 || vertex >= vertex_count(levels() - 1)) return {};
  const std::uint32_t* slots = children_.data() + 4 * std::size_t{vertex - vertex_count(0)};
  return {slots, slots[3] == kNone ? 3u : 4u};
}

std::size_t SemiRegularHierarchy::memory_bytes() const {
  std::size_t bytes = children_.capacity() * sizeof(std::uint32_t);
  for (const auto& t : topologies_)
    bytes += (t.triangles.capacity() + t.edge_vertices.capacity() + t.edge_faces.capacity() + t.face_edges.capacity()) *
             sizeof(std::uint32_t);
  return bytes + finest_triangles_.capacity() * sizeof(std::uint32_t);
}

TriangleMesh SemiRegularMesh::mesh_at(int level, std::span<const double> values) const {
  TriangleMesh m;
  const std::size_t n = 3 * static_cast<std::size_t>(hierarchy.vertex_count(level));
  if (values.size() < n) throw MeshError("mesh_at: values hold fewer vertices than the level needs");
  m.positions.assign(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n));
  m.triangles = hierarchy.triangles(level);
  return m;
}

SemiRegularMesh refine_linear(const TriangleMesh& base, int levels) {
  SemiRegularMesh m{SemiRegularHierarchy(
                        TriangleTopology::build(static_cast<std::uint32_t>(base.vertex_count()), base.triangles), levels),
                    {},
                    {}};
  m.positions = base.positions;
  m.positions.resize(3 * static_cast<std::size_t>(m.hierarchy.vertex_count(levels)));
  for (int j = 0; j < levels; ++j) {
    const TriangleTopology& t = m.hierarchy.topology(j);
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
      const std::uint32_t v = m.hierarchy.odd_vertex(j, e), a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
      for (int k = 0; k < 3; ++k) m.positions[3 * v + k] = 0.5 * (m.positions[3 * a + k] + m.positions[3 * b + k]);
    }
  }
  return m;
}

}  // namespace meshlift

namespace meshlift {

std::optional<SemiRegularMesh> recover_level_ordered(const TriangleMesh& mesh) {
  if (mesh.positions.size() % 3 != 0) return std::nullopt;  // no whole vertex count
  const std::size_t faces = mesh.face_count();
  const std::size_t vertices = mesh.vertex_count();
  // Face f of the base becomes faces 4f..4f+3, corner face i first; so base corner i of face f
  // is the first corner of finest face 4^L f + 4^(L-1) i.
  int max_levels = 0;
  while (max_levels < kMaxLevels && faces % (std::size_t{1} << (2 * (max_levels + 1))) == 0) ++max_levels;
  for (int L = max_levels; L >= 1; --L) {
    const std::size_t block = std::size_t{1} << (2 * L), sub = block / 4;
    const std::size_t base_faces = faces / block;
    std::vector<std::uint32_t> base(3 * base_faces);
    std::uint32_t base_vertices = 0;
    for (std::size_t f = 0; f < base_faces; ++f)
      for (std::size_t i = 0; i < 3; ++i) {
        base[3 * f + i] = mesh.triangles[3 * (block * f + sub * i)];
        base_vertices = std::max(base_vertices, base[3 * f + i] + 1);
      }
    if (base_vertices > vertices) continue;
    try {
      SemiRegularHierarchy h(TriangleTopology::build(base_vertices, base), L);
      if (h.vertex_count(L) != vertices || h.triangles(L) != mesh.triangles) continue;
      return SemiRegularMesh{std::move(h), mesh.positions, {}};
    } catch (const MeshError&) {
    }
  }
  return std::nullopt;
}

}  // namespace meshlift
