// Recognizing subdivision connectivity in a mesh whose vertices and faces come in any order
// (remesh.h: recover_semi_regular). One 1:4 split is undone at a time, as long as it can be:
//
// In a 1:4 refinement, the even vertices (those of the coarser mesh) are pairwise non-adjacent,
// and every odd vertex u sits on a coarse edge (v, w) with the six-ring v, a, b, w, b', a'
// (interior: valence 6) or the fan v, a, b, w (boundary: valence 4, three faces), so w is the
// vertex three steps from v around u. Hence one even vertex determines its whole component:
// its neighbours are odd, and three steps across each neighbour lies the next even vertex.
// A vertex that cannot be odd (interior valence != 6, boundary valence != 4) is even for sure;
// a component without one (a regular torus) is tried from a vertex and each of its neighbours,
// one of which is even in any 1:4 refinement. Faces with one even corner e, in order (e, o1, o2),
// give the coarse face (e, w(o1), w(o2)); faces with none are the centre faces. Every candidate
// coarse mesh is refined again and must reproduce the finer faces exactly, so a recovery is
// never a guess.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "meshlift/remesh.h"
#include "meshlift/topology.h"

namespace meshlift {
namespace {

constexpr std::uint8_t kUnknown = 0, kEven = 1, kOdd = 2;

/// Each vertex's corners: for every face (v, j, k) around v, the pair (j, k) in face order, so
/// that k follows j counter-clockwise around v.
struct Rings {
  std::vector<std::uint32_t> offsets;
  std::vector<std::array<std::uint32_t, 2>> pairs;

  Rings(std::uint32_t vertices, const std::vector<std::uint32_t>& triangles) : offsets(vertices + 1, 0) {
    for (std::uint32_t v : triangles) ++offsets[v + 1];
    for (std::uint32_t v = 0; v < vertices; ++v) offsets[v + 1] += offsets[v];
    pairs.resize(triangles.size());
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t f = 0; f < triangles.size() / 3; ++f)
      for (int i = 0; i < 3; ++i)
        pairs[fill[triangles[3 * f + i]]++] = {triangles[3 * f + (i + 1) % 3], triangles[3 * f + (i + 2) % 3]};
  }
  std::size_t faces(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
  /// The neighbour after (forward) or before x around v; kNone if there is none.
  std::uint32_t step(std::uint32_t v, std::uint32_t x, bool forward) const {
    for (std::uint32_t c = offsets[v]; c < offsets[v + 1]; ++c)
      if (pairs[c][forward ? 0 : 1] == x) return pairs[c][forward ? 1 : 0];
    return kNone;
  }
  /// Distinct neighbours of v (a closed fan has as many as faces, an open one one more).
  std::size_t valence(std::uint32_t v) const {
    std::size_t open = 0;  // neighbours that start a pair but never end one: fan starts
    for (std::uint32_t c = offsets[v]; c < offsets[v + 1]; ++c)
      if (step(v, pairs[c][0], false) == kNone) ++open;
    return faces(v) + open;
  }
  /// The vertex three steps from x around the odd vertex u (w of the coarse edge (x, w)).
  std::uint32_t across(std::uint32_t u, std::uint32_t x) const {
    const std::size_t faces_u = faces(u), valence_u = valence(u);
    if (!(faces_u == 6 && valence_u == 6) && !(faces_u == 3 && valence_u == 4)) return kNone;
    for (bool forward : {true, false}) {
      std::uint32_t y = x;
      for (int s = 0; s < 3 && y != kNone; ++s) y = step(u, y, forward);
      if (y != kNone) {
        if (faces_u == 6) return y;                                   // interior: either way round
        if (step(u, y, forward) == kNone) return y;  // boundary: from one fan end to the other
      }
    }
    return kNone;
  }
};

/// One undone 1:4 split: the coarse mesh and how its vertices and edges sit in the fine one.
struct CoarseLevel {
  std::uint32_t vertex_count = 0;
  std::vector<std::uint32_t> triangles;
  std::vector<std::uint32_t> fine_vertex;  ///< coarse vertex -> its (even) fine vertex
  /// (min, max) coarse edge endpoints -> the fine odd vertex on it (the splits coarsen() undoes)
  std::unordered_map<std::uint64_t, std::uint32_t> odd_on_edge;
  /// Or, for a level of a level-ordered hierarchy (splits_of), its topology: the odd vertex on
  /// edge e is first_odd + e, the edge found among its endpoints' incident edges.
  const TriangleTopology* topology = nullptr;
  std::optional<VertexEdges> incident;
  std::uint32_t first_odd = 0;

  static std::uint64_t key(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
  }
  std::uint32_t odd(std::uint32_t a, std::uint32_t b) const {
    if (topology != nullptr) {
      for (std::uint32_t k = incident->offsets[a]; k < incident->offsets[a + 1]; ++k) {
        const std::uint32_t e = incident->edges[k];
        if (topology->edge_vertices[2 * e] + topology->edge_vertices[2 * e + 1] - a == b) return first_odd + e;
      }
      return kNone;
    }
    const auto it = odd_on_edge.find(key(a, b));
    return it == odd_on_edge.end() ? kNone : it->second;
  }
};

/// Marks even/odd from `seed` (assumed even) over its component. False on a contradiction.
bool propagate(const Rings& rings, std::uint32_t seed, std::vector<std::uint8_t>& role,
               std::vector<std::array<std::uint32_t, 2>>& ends) {
  std::vector<std::uint32_t> queue{seed};
  role[seed] = kEven;
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const std::uint32_t v = queue[q];
    for (std::uint32_t c = rings.offsets[v]; c < rings.offsets[v + 1]; ++c)
      for (std::uint32_t u : rings.pairs[c]) {
        if (role[u] == kEven) return false;  // two even vertices adjacent
        const std::uint32_t w = rings.across(u, v);
        if (w == kNone || w == v) return false;
        if (role[u] == kOdd) {
          if (!((ends[u][0] == v && ends[u][1] == w) || (ends[u][0] == w && ends[u][1] == v))) return false;
          continue;
        }
        role[u] = kOdd;
        ends[u] = {v, w};
        if (role[w] == kOdd) return false;
        if (role[w] == kUnknown) {
          role[w] = kEven;
          queue.push_back(w);
        }
      }
  }
  return true;
}

/// Faces as sorted, rotation-normalized triples (smallest index first), for comparison.
std::vector<std::array<std::uint32_t, 3>> normalized_faces(const std::vector<std::uint32_t>& triangles) {
  std::vector<std::array<std::uint32_t, 3>> faces(triangles.size() / 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::array<std::uint32_t, 3> t{triangles[3 * f], triangles[3 * f + 1], triangles[3 * f + 2]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    faces[f] = t;
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// Undoes one 1:4 split of (vertices, triangles), or returns nullopt.
std::optional<CoarseLevel> coarsen(std::uint32_t vertices, const std::vector<std::uint32_t>& triangles) {
  const std::size_t faces = triangles.size() / 3;
  if (faces == 0 || faces % 4 != 0) return std::nullopt;
  const Rings rings(vertices, triangles);
  std::vector<std::uint8_t> role(vertices, kUnknown);
  std::vector<std::array<std::uint32_t, 2>> ends(vertices, {kNone, kNone});

  // Components of the vertex graph, each seeded separately.
  std::vector<std::uint8_t> seen(vertices, 0);
  for (std::uint32_t v = 0; v < vertices; ++v) {
    if (seen[v]) continue;
    if (rings.faces(v) == 0) return std::nullopt;  // an isolated vertex is in no refinement
    // A vertex of the same component that must be even, if any (found by a plain flood fill).
    std::vector<std::uint32_t> component{v};
    seen[v] = 1;
    std::uint32_t forced = kNone;
    for (std::size_t q = 0; q < component.size(); ++q) {
      const std::uint32_t x = component[q];
      const std::size_t valence = rings.valence(x);
      const bool boundary = valence != rings.faces(x);
      if (forced == kNone && ((boundary && valence != 4) || (!boundary && valence != 6))) forced = x;
      for (std::uint32_t c = rings.offsets[x]; c < rings.offsets[x + 1]; ++c)
        for (std::uint32_t y : rings.pairs[c])
          if (!seen[y]) seen[y] = 1, component.push_back(y);
    }
    std::vector<std::uint32_t> seeds;
    if (forced != kNone) {
      seeds.push_back(forced);
    } else {
      seeds.push_back(v);
      for (std::uint32_t c = rings.offsets[v]; c < rings.offsets[v + 1]; ++c) seeds.push_back(rings.pairs[c][0]);
    }
    bool ok = false;
    for (std::uint32_t seed : seeds) {
      for (std::uint32_t x : component) role[x] = kUnknown;
      if (propagate(rings, seed, role, ends) &&
          std::all_of(component.begin(), component.end(), [&](std::uint32_t x) { return role[x] != kUnknown; })) {
        ok = true;
        break;
      }
    }
    if (!ok) return std::nullopt;
  }

  CoarseLevel coarse;
  std::vector<std::uint32_t> coarse_of(vertices, kNone);
  for (std::uint32_t v = 0; v < vertices; ++v)
    if (role[v] == kEven) {
      coarse_of[v] = coarse.vertex_count++;
      coarse.fine_vertex.push_back(v);
    }
  for (std::uint32_t u = 0; u < vertices; ++u)
    if (role[u] == kOdd) {
      const std::uint64_t k = CoarseLevel::key(coarse_of[ends[u][0]], coarse_of[ends[u][1]]);
      if (!coarse.odd_on_edge.emplace(k, u).second) return std::nullopt;  // two odd vertices on one edge
    }
  // Coarse faces, each taken from its corner face at its smallest coarse corner.
  for (std::size_t f = 0; f < faces; ++f) {
    int evens = 0, at = 0;
    for (int i = 0; i < 3; ++i)
      if (role[triangles[3 * f + i]] == kEven) ++evens, at = i;
    if (evens > 1) return std::nullopt;
    if (evens == 0) continue;
    const std::uint32_t e = triangles[3 * f + at];
    const std::uint32_t o1 = triangles[3 * f + (at + 1) % 3], o2 = triangles[3 * f + (at + 2) % 3];
    const std::uint32_t w1 = ends[o1][0] == e ? ends[o1][1] : ends[o1][0];
    const std::uint32_t w2 = ends[o2][0] == e ? ends[o2][1] : ends[o2][0];
    const std::uint32_t a = coarse_of[e], b = coarse_of[w1], c = coarse_of[w2];
    if (a < b && a < c) coarse.triangles.insert(coarse.triangles.end(), {a, b, c});
  }
  if (coarse.triangles.size() * 4 != triangles.size()) return std::nullopt;

  // Verification: refining the coarse mesh must give exactly the fine faces.
  TriangleTopology topology;
  try {
    topology = TriangleTopology::build(coarse.vertex_count, coarse.triangles);
  } catch (const MeshError&) {
    return std::nullopt;
  }
  if (topology.vertex_count + topology.edge_count() != vertices) return std::nullopt;
  std::vector<std::uint32_t> to_fine(coarse.fine_vertex);
  for (std::uint32_t e = 0; e < topology.edge_count(); ++e) {
    const std::uint32_t u = coarse.odd(topology.edge_vertices[2 * e], topology.edge_vertices[2 * e + 1]);
    if (u == kNone) return std::nullopt;
    to_fine.push_back(u);
  }
  std::vector<std::uint32_t> refined = topology.refined_triangles();
  for (std::uint32_t& x : refined) x = to_fine[x];
  if (normalized_faces(refined) != normalized_faces(triangles)) return std::nullopt;
  return coarse;
}


/// The splits of a level-ordered hierarchy (recover_level_ordered), finest first, as coarsen()
/// would have undone them: every level numbers its vertices as the mesh does.
std::vector<CoarseLevel> splits_of(const SemiRegularHierarchy& h) {
  std::vector<CoarseLevel> splits;
  for (int j = h.levels() - 1; j >= 0; --j) {
    CoarseLevel split;
    split.vertex_count = h.vertex_count(j);
    split.fine_vertex.resize(split.vertex_count);
    for (std::uint32_t v = 0; v < split.vertex_count; ++v) split.fine_vertex[v] = v;
    split.topology = &h.topology(j);
    split.incident.emplace(h.topology(j));
    split.first_odd = h.vertex_count(j);
    splits.push_back(std::move(split));
  }
  return splits;
}

/// The semi-regular mesh whose splits `levels` undid (finest first; levels.back() holds the
/// base), its vertices numbered level by level.
SemiRegularMesh assemble(const std::vector<CoarseLevel>& levels, const TriangleMesh& mesh) {
  const int L = static_cast<int>(levels.size());
  // Hierarchy numbering -> vertex of each level's mesh, from the base up (level j's mesh is the
  // coarse mesh of levels[L - 1 - j], or the input for j = L).
  SemiRegularHierarchy hierarchy(TriangleTopology::build(levels.back().vertex_count, levels.back().triangles), L);
  std::vector<std::uint32_t> to_mesh(levels.back().vertex_count);
  for (std::uint32_t v = 0; v < to_mesh.size(); ++v) to_mesh[v] = v;
  for (int j = 0; j < L; ++j) {
    const CoarseLevel& split = levels[static_cast<std::size_t>(L - 1 - j)];  // level j -> j + 1
    const TriangleTopology& t = hierarchy.topology(j);
    std::vector<std::uint32_t> next(hierarchy.vertex_count(j + 1));
    for (std::uint32_t v = 0; v < hierarchy.vertex_count(j); ++v) next[v] = split.fine_vertex[to_mesh[v]];
    for (std::uint32_t e = 0; e < t.edge_count(); ++e)
      next[hierarchy.odd_vertex(j, e)] = split.odd(to_mesh[t.edge_vertices[2 * e]], to_mesh[t.edge_vertices[2 * e + 1]]);
    to_mesh = std::move(next);
  }
  SemiRegularMesh result{std::move(hierarchy), std::vector<double>(3 * to_mesh.size()), {}};
  for (std::size_t v = 0; v < to_mesh.size(); ++v)
    for (int k = 0; k < 3; ++k) result.positions[3 * v + k] = mesh.positions[3 * std::size_t{to_mesh[v]} + k];
  return result;
}

/// Whether two faces have the same three corners, in any order: such a base (two triangles
/// glued along their three edges) passes TriangleTopology::build, but the inner edges of their
/// refinements coincide, four faces on each. Any other base build() accepts refines to a
/// manifold mesh: an inner edge joins the midpoints of two edges of one face, which only a face
/// on the same three corners shares.
bool has_twin_faces(const std::vector<std::uint32_t>& triangles) {
  std::vector<std::array<std::uint32_t, 3>> corners(triangles.size() / 3);
  for (std::size_t f = 0; f < corners.size(); ++f) {
    corners[f] = {triangles[3 * f], triangles[3 * f + 1], triangles[3 * f + 2]};
    std::sort(corners[f].begin(), corners[f].end());
  }
  std::sort(corners.begin(), corners.end());
  return std::adjacent_find(corners.begin(), corners.end()) != corners.end();
}

/// Undoes further splits below `levels` (or, if empty, of the mesh itself) while possible.
void coarsen_further(std::vector<CoarseLevel>& levels, const TriangleMesh& mesh) {
  while (static_cast<int>(levels.size()) < kMaxLevels) {
    auto coarse = levels.empty() ? coarsen(static_cast<std::uint32_t>(mesh.vertex_count()), mesh.triangles)
                                 : coarsen(levels.back().vertex_count, levels.back().triangles);
    if (!coarse) break;
    levels.push_back(std::move(*coarse));
  }
}

}  // namespace

std::optional<SemiRegularMesh> recover_in_level_order(const TriangleMesh& mesh) {
  if (mesh.vertex_count() >= kNone) return std::nullopt;
  std::optional<SemiRegularMesh> ordered = recover_level_ordered(mesh);
  if (!ordered || has_twin_faces(ordered->hierarchy.triangles(0))) return std::nullopt;
  // Its base may itself be a refinement numbered otherwise (a semi-regular mesh refined by a
  // tool that numbers the new vertices in its own edge order, as `meshlift subdivide` does): the
  // splits below it are undone as any others (the base passed TriangleTopology::build).
  const SemiRegularHierarchy& h = ordered->hierarchy;
  std::optional<CoarseLevel> below;
  if (h.levels() < kMaxLevels) below = coarsen(h.vertex_count(0), h.triangles(0));
  if (!below) return ordered;
  std::vector<CoarseLevel> levels = splits_of(h);
  levels.push_back(std::move(*below));
  coarsen_further(levels, mesh);
  return assemble(levels, mesh);
}

std::optional<SemiRegularMesh> recover_semi_regular(const TriangleMesh& mesh) {
  if (mesh.vertex_count() >= kNone) return std::nullopt;
  if (auto ordered = recover_in_level_order(mesh)) return ordered;
  // Undo 1:4 splits while possible: levels[0] undoes the finest split.
  std::vector<CoarseLevel> levels;
  coarsen_further(levels, mesh);
  if (levels.empty()) return std::nullopt;
  return assemble(levels, mesh);
}

}  // namespace meshlift
