// Puts a semi-regular mesh in the order its stream decodes to (codec.h): base faces and vertices
// in the traversal order of the base mesh coder (base_mesh_coder.h), the finer levels renumbered
// to follow. Faces map to faces by the refinement rule, so no geometric search is needed.
#include "canonical_order.h"

#include <algorithm>
#include <optional>

#include "base_mesh_coder.h"
#include "concurrent.h"
#include "large_array.h"
#include "meshlift/codec.h"

namespace meshlift {

namespace {

void check_sizes(const SemiRegularMesh& mesh) {
  const std::size_t V = mesh.hierarchy.vertex_count(mesh.hierarchy.levels());
  if (mesh.positions.size() != 3 * V) throw MeshError("the positions do not match the hierarchy's vertex count");
  for (const VertexChannel& channel : mesh.channels)
    if (channel.components < 1 || channel.values.size() != static_cast<std::size_t>(channel.components) * V)
      throw MeshError("a channel's values do not match the hierarchy's vertex count");
}

/// Whether `order` (the coder's traversal of h's base) labels and turns nothing, and h's base
/// topology is the one TriangleTopology::build gives its faces (see is_canonical).
bool in_coding_order(const SemiRegularHierarchy& h, const base_mesh::CodingOrder& order) {
  for (int j = 0; j < std::max(h.levels(), 1); ++j)
    if (!h.has_topology(j)) return false;
  for (std::size_t k = 0; k < order.face.size(); ++k)
    if (order.face[k] != k || order.rotation[k] != 0) return false;
  for (std::uint32_t v = 0; v < order.label.size(); ++v)
    if (order.label[v] != v) return false;
  const TriangleTopology& t = h.topology(0);
  const TriangleTopology built = TriangleTopology::build(h.vertex_count(0), h.triangles(0));
  return t.edge_vertices == built.edge_vertices && t.edge_faces == built.edge_faces && t.face_edges == built.face_edges;
}

/// The coder's traversal of the mesh's base, after checking the arrays' sizes.
base_mesh::CodingOrder coding_order(const SemiRegularMesh& mesh) {
  check_sizes(mesh);
  base_mesh::CodingOrder order;
  base_mesh::encode_faces(mesh.hierarchy.triangles(0), mesh.hierarchy.vertex_count(0), &order);
  return order;
}

/// For each vertex of the canonical hierarchy, its index in the old one (`mesh`'s), given the
/// coder's traversal of the old base and the new base's topology. Levels above the base follow by
/// the refinement rule alone (TriangleTopology::refined), reading no topology but the bases':
/// - the odd vertex V_j + e of level j + 1 sits on edge e of level j: new edge e is old edge
///   edge_map[e], and flip[e] says whether they run in opposite directions;
/// - edge e of level j has halves 2e and 2e + 1 at level j + 1, run the same way: new half s is
///   old half s ^ flip[e] of edge_map[e], with e's flip;
/// - face k of level j is old face face_map[k] turned by turn[k] (its corner i is old corner
///   (i + turn) % 3), so its inner edge i (2E + 3k + i, opposite corner i's child) is old inner
///   edge (i + turn) % 3 of face_map[k], run the same way; its children 4k + i (i < 3) are old
///   4 face_map[k] + (i + turn) % 3 unturned, the centre 4k + 3 is old 4 face_map[k] + 3 turned by
///   turn[k].
/// Each level's vertices are written once, in order.
std::vector<std::uint32_t> old_vertices(const SemiRegularHierarchy& old, const TriangleTopology& new_base,
                                        const base_mesh::CodingOrder& order) {
  const int L = old.levels();
  const TriangleTopology& old_base = old.topology(0);
  std::vector<std::uint32_t> old_vertex;
  reserve_large(old_vertex, old.vertex_count(L));  // appended: each written once
  old_vertex.resize(old.vertex_count(0));
  for (std::uint32_t v = 0; v < old.vertex_count(0); ++v) old_vertex[order.label[v]] = v;
  if (L == 0) return old_vertex;

  // The base's edges: new face k's corner edge i is old face order.face[k]'s corner edge
  // (i + rotation) % 3; their directions compared through the labels.
  const std::size_t E0 = new_base.edge_count();
  std::vector<std::uint32_t> edge_map(E0);
  std::vector<std::uint8_t> flip(E0);
  for (std::size_t k = 0; k < order.face.size(); ++k)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t e = new_base.face_edges[3 * k + i];
      const std::uint32_t o = old_base.face_edges[3 * std::size_t{order.face[k]} + (i + order.rotation[k]) % 3];
      edge_map[e] = o;
      flip[e] = order.label[old_base.edge_vertices[2 * o]] != new_base.edge_vertices[2 * e];
    }
  std::vector<std::uint32_t> face_map = order.face, turn = order.rotation;
  for (int j = 0;; ++j) {
    const std::uint32_t old_first = old.vertex_count(j);  // V_j, the same in both hierarchies
    for (const std::uint32_t o : edge_map) old_vertex.push_back(old_first + o);
    if (j + 1 == L) break;
    const std::size_t E = edge_map.size(), F = face_map.size();
    std::vector<std::uint32_t> next_edges, next_faces, next_turn;
    std::vector<std::uint8_t> next_flip;
    reserve_large(next_edges, 2 * E + 3 * F);
    reserve_large(next_flip, 2 * E + 3 * F);
    for (std::size_t e = 0; e < E; ++e) {
      next_edges.push_back(2 * edge_map[e] + flip[e]);
      next_edges.push_back(2 * edge_map[e] + (flip[e] ^ 1u));
      next_flip.push_back(flip[e]);
      next_flip.push_back(flip[e]);
    }
    const auto old_inner = static_cast<std::uint32_t>(2 * E);
    for (std::size_t k = 0; k < F; ++k)
      for (std::uint32_t i = 0; i < 3; ++i) {
        next_edges.push_back(old_inner + 3 * face_map[k] + (i + turn[k]) % 3);
        next_flip.push_back(0);
      }
    edge_map = std::move(next_edges);
    flip = std::move(next_flip);
    if (j + 2 == L) continue;  // the finest faces' map: no edges of theirs are vertices
    reserve_large(next_faces, 4 * F);
    reserve_large(next_turn, 4 * F);
    for (std::size_t k = 0; k < F; ++k) {
      for (std::uint32_t i = 0; i < 3; ++i) {
        next_faces.push_back(4 * face_map[k] + (i + turn[k]) % 3);
        next_turn.push_back(0);
      }
      next_faces.push_back(4 * face_map[k] + 3);
      next_turn.push_back(turn[k]);
    }
    face_map = std::move(next_faces);
    turn = std::move(next_turn);
  }
  return old_vertex;
}

CanonicalHierarchy build_reordered(const SemiRegularMesh& mesh, const base_mesh::CodingOrder& order,
                                   bool finest_triangles, bool coefficient_tree, bool concurrent,
                                   bool topology_below_finest = true) {
  const SemiRegularHierarchy& old = mesh.hierarchy;
  const std::vector<std::uint32_t>& old_base = old.triangles(0);

  // New base: face k is old face order.face[k] turned so that its corner 0 is old corner rotation[k].
  const std::size_t F = order.face.size();
  std::vector<std::uint32_t> base(3 * F);
  for (std::size_t k = 0; k < F; ++k)
    for (std::uint32_t i = 0; i < 3; ++i)
      base[3 * k + i] = order.label[old_base[3 * order.face[k] + (i + order.rotation[k]) % 3]];
  TriangleTopology new_base = TriangleTopology::build(old.vertex_count(0), base);
  // The finer levels' topology and the renumbering are independent: side by side (concurrent.h).
  std::optional<SemiRegularHierarchy> h;
  std::vector<std::uint32_t> old_vertex;
  run_both(
      concurrent, [&] { h.emplace(new_base, old.levels(), finest_triangles, coefficient_tree, topology_below_finest); },
      [&] { old_vertex = old_vertices(old, new_base, order); });
  return {std::move(*h), std::move(old_vertex)};
}

}  // namespace

bool is_canonical(const SemiRegularMesh& mesh) { return in_coding_order(mesh.hierarchy, coding_order(mesh)); }

CanonicalHierarchy canonical_hierarchy(const SemiRegularMesh& mesh, bool finest_triangles, bool coefficient_tree,
                                       bool concurrent) {
  return build_reordered(mesh, coding_order(mesh), finest_triangles, coefficient_tree, concurrent);
}

std::optional<CanonicalHierarchy> canonical_hierarchy_if_reordered(const SemiRegularMesh& mesh, bool finest_triangles,
                                                                   bool coefficient_tree, bool concurrent,
                                                                   bool topology_below_finest) {
  const base_mesh::CodingOrder order = coding_order(mesh);
  if (in_coding_order(mesh.hierarchy, order)) return std::nullopt;
  return build_reordered(mesh, order, finest_triangles, coefficient_tree, concurrent, topology_below_finest);
}

SemiRegularMesh canonical_order(const SemiRegularMesh& mesh) {
  CanonicalHierarchy canonical = canonical_hierarchy(mesh, true, true);
  const std::vector<std::uint32_t>& old_vertex = canonical.old_vertex;
  auto reorder = [&](const std::vector<double>& values, int components) {
    const std::size_t k = static_cast<std::size_t>(components);
    std::vector<double> ordered(values.size());
    for (std::size_t v = 0; v < old_vertex.size(); ++v)
      for (std::size_t c = 0; c < k; ++c) ordered[k * v + c] = values[k * std::size_t{old_vertex[v]} + c];
    return ordered;
  };
  SemiRegularMesh out{std::move(canonical.hierarchy), reorder(mesh.positions, 3), {}};
  for (const VertexChannel& channel : mesh.channels)
    out.channels.push_back({channel.components, reorder(channel.values, channel.components), channel.colour});
  return out;
}

}  // namespace meshlift
