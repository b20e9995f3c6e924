// Puts a semi-regular mesh in the order its stream decodes to (codec.h): base faces and vertices
// in the traversal order of the base mesh coder (base_mesh_coder.h), the finer levels renumbered
// to follow. Faces map to faces by the refinement rule, so no geometric search is needed.
#include "canonical_order.h"

#include <algorithm>

#include "base_mesh_coder.h"
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

CanonicalHierarchy build_reordered(const SemiRegularMesh& mesh, const base_mesh::CodingOrder& order,
                                   bool finest_triangles, bool coefficient_tree) {
  const SemiRegularHierarchy& old = mesh.hierarchy;
  const int L = old.levels();
  const std::vector<std::uint32_t>& old_base = old.triangles(0);

  // New base: face k is old face order.face[k] turned so that its corner 0 is old corner rotation[k].
  const std::size_t F = order.face.size();
  std::vector<std::uint32_t> base(3 * F);
  for (std::size_t k = 0; k < F; ++k)
    for (std::uint32_t i = 0; i < 3; ++i)
      base[3 * k + i] = order.label[old_base[3 * order.face[k] + (i + order.rotation[k]) % 3]];
  CanonicalHierarchy out{
      SemiRegularHierarchy(TriangleTopology::build(old.vertex_count(0), base), L, finest_triangles, coefficient_tree), {}};
  const SemiRegularHierarchy& h = out.hierarchy;

  // old_vertex[v]: the old index of new vertex v, level by level. Face k of level j is old face
  // face_map[k] turned by turn[k]; its corner edge i is old corner edge (i + turn) % 3, so their
  // odd vertices correspond. Refinement: new children 4k + i (i < 3) are old 4f + (i + t) % 3
  // unturned, the centre 4k + 3 is old 4f + 3 turned by t.
  std::vector<std::uint32_t>& old_vertex = out.old_vertex;
  assign_large(old_vertex, h.vertex_count(L));
  for (std::uint32_t v = 0; v < old.vertex_count(0); ++v) old_vertex[order.label[v]] = v;
  std::vector<std::uint32_t> face_map = order.face, turn = order.rotation;
  for (int j = 0; j < L; ++j) {
    const TriangleTopology &nt = h.topology(j), &ot = old.topology(j);
    for (std::size_t k = 0; k < face_map.size(); ++k)
      for (std::uint32_t i = 0; i < 3; ++i)
        old_vertex[h.odd_vertex(j, nt.face_edges[3 * k + i])] =
            old.odd_vertex(j, ot.face_edges[3 * face_map[k] + (i + turn[k]) % 3]);
    if (j + 1 == L) break;
    std::vector<std::uint32_t> next_map, next_turn;
    assign_large(next_map, 4 * face_map.size());
    assign_large(next_turn, 4 * face_map.size());
    for (std::size_t k = 0; k < face_map.size(); ++k) {
      for (std::uint32_t i = 0; i < 3; ++i) {
        next_map[4 * k + i] = 4 * face_map[k] + (i + turn[k]) % 3;
        next_turn[4 * k + i] = 0;
      }
      next_map[4 * k + 3] = 4 * face_map[k] + 3;
      next_turn[4 * k + 3] = turn[k];
    }
    face_map = std::move(next_map);
    turn = std::move(next_turn);
  }
  return out;
}

}  // namespace

bool is_canonical(const SemiRegularMesh& mesh) { return in_coding_order(mesh.hierarchy, coding_order(mesh)); }

CanonicalHierarchy canonical_hierarchy(const SemiRegularMesh& mesh, bool finest_triangles, bool coefficient_tree) {
  return build_reordered(mesh, coding_order(mesh), finest_triangles, coefficient_tree);
}

std::optional<CanonicalHierarchy> canonical_hierarchy_if_reordered(const SemiRegularMesh& mesh, bool finest_triangles,
                                                                   bool coefficient_tree) {
  const base_mesh::CodingOrder order = coding_order(mesh);
  if (in_coding_order(mesh.hierarchy, order)) return std::nullopt;
  return build_reordered(mesh, order, finest_triangles, coefficient_tree);
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
  for (const VertexChannel& channel : mesh.channels) out.channels.push_back({channel.components, reorder(channel.values, channel.components)});
  return out;
}

}  // namespace meshlift
