// Feature lines: detection, the base's feature edges, and the semi-regular vertices on them.
// See features.h.
#include "meshlift/features.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "meshlift/topology.h"
#include "vec3.h"

namespace meshlift {

namespace {

using vec3::Vec3;

/// The edge of `topology` between vertices u and w (kNone if there is none), by u's incident edges.
std::uint32_t edge_between(const TriangleTopology& topology, const VertexEdges& incident, std::uint32_t u, std::uint32_t w) {
  for (std::uint32_t k = incident.offsets[u]; k < incident.offsets[u + 1]; ++k) {
    const std::uint32_t e = incident.edges[k];
    if (topology.edge_vertices[2 * e] + topology.edge_vertices[2 * e + 1] - u == w) return e;
  }
  return kNone;
}

/// The neighbour of w along its line other than `from` (w inside a line: degree 2).
std::uint32_t other_neighbour(const FeatureLines& g, std::uint32_t w, std::uint32_t from) {
  const std::uint32_t first = g.neighbours[g.offsets[w]];
  return first != from ? first : g.neighbours[g.offsets[w] + 1];
}

}  // namespace

FeatureLines FeatureLines::from_edges(std::size_t vertices, const std::vector<std::array<std::uint32_t, 2>>& edges) {
  FeatureLines g;
  if (edges.empty()) return g;
  g.offsets.assign(vertices + 1, 0);
  for (const auto& [a, b] : edges) ++g.offsets[a + 1], ++g.offsets[b + 1];
  for (std::size_t v = 0; v < vertices; ++v) g.offsets[v + 1] += g.offsets[v];
  g.neighbours.resize(g.offsets.back());
  std::vector<std::uint32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& [a, b] : edges) g.neighbours[fill[a]++] = b, g.neighbours[fill[b]++] = a;
  for (std::size_t v = 0; v < vertices; ++v) std::sort(g.neighbours.begin() + g.offsets[v], g.neighbours.begin() + g.offsets[v + 1]);
  return g;
}

std::size_t FeaturePlacement::count() const { return static_cast<std::size_t>(std::count(fixed.begin(), fixed.end(), 1)); }

std::vector<double> edge_turn_cosines(const TriangleMesh& mesh, const TriangleTopology& topology) {
  // Unit face normals (zero for a degenerate face).
  std::vector<Vec3> normal(mesh.face_count());
  for (std::size_t f = 0; f < normal.size(); ++f) normal[f] = vec3::unit(vec3::face_normal(mesh.positions, &mesh.triangles[3 * f]));
  std::vector<double> cosines(topology.edge_count(), 1.0);
  for (std::size_t e = 0; e < cosines.size(); ++e) {
    if (topology.is_boundary_edge(static_cast<std::uint32_t>(e))) continue;
    const Vec3 &m = normal[topology.edge_faces[2 * e]], &n = normal[topology.edge_faces[2 * e + 1]];
    if (vec3::dot(m, m) > 0 && vec3::dot(n, n) > 0) cosines[e] = vec3::dot(m, n);
  }
  return cosines;
}

FeatureLines find_feature_lines(const TriangleMesh& mesh, double min_angle_degrees, std::size_t min_chain_edges,
                                double max_turn_degrees, double max_side_degrees) {
  if (!(min_angle_degrees > 0 && min_angle_degrees < 180)) return {};
  const TriangleTopology topology = TriangleTopology::build(static_cast<std::uint32_t>(mesh.vertex_count()), mesh.triangles);
  const std::vector<double> turn_cos = edge_turn_cosines(mesh, topology);
  // Sharp: the normals' angle above the threshold, cos(angle) < cos(threshold).
  const double cos_limit = std::cos(min_angle_degrees * std::numbers::pi / 180);
  std::vector<std::uint8_t> sharp(topology.edge_count(), 0);
  std::vector<std::array<std::uint32_t, 2>> sharp_edges;
  for (std::size_t e = 0; e < topology.edge_count(); ++e)
    if (turn_cos[e] < cos_limit) {
      sharp[e] = 1;
      sharp_edges.push_back({topology.edge_vertices[2 * e], topology.edge_vertices[2 * e + 1]});
    }
  const FeatureLines all = FeatureLines::from_edges(mesh.vertex_count(), sharp_edges);
  if (all.empty()) return all;
  const VertexEdges incident(topology);
  // The sides of sharp edge e: the smallest cosine of the turn across the other edges of its two
  // faces that are not sharp themselves. A crease between smooth parts has sides near 1.
  auto side_cos = [&](std::uint32_t e) {
    double smallest = 1;
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t other = topology.face_edges[3 * std::size_t{topology.edge_faces[2 * e + side]} + i];
        if (other != e && !sharp[other]) smallest = std::min(smallest, turn_cos[other]);
      }
    return smallest;
  };
  const double cos_side = std::cos(max_side_degrees * std::numbers::pi / 180);

  // Chains end at corners and at kinks: vertices inside a line where it turns by more than
  // max_turn_degrees (a crease of a CAD part is a smooth curve; the sharp edges of a coarse or
  // scanned organic mesh zigzag). Measured on the corpus (docs/RESULTS.md): with the angle and
  // length tests alone camel, cow, elephant, lion-head, turbine and mannequin-devil got lines that
  // made their remeshes fold or lose 6-16 dB; the kinks alone did not keep them out, the sides
  // (below) did.
  const double cos_turn = std::cos(max_turn_degrees * std::numbers::pi / 180);
  std::vector<std::uint8_t> stop(mesh.vertex_count(), 0);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (all.degree(v) == 0) continue;
    if (all.is_corner(v)) {
      stop[v] = 1;
      continue;
    }
    const Vec3 p = vec3::at(mesh.positions, all.neighbours[all.offsets[v]]), q = vec3::at(mesh.positions, all.neighbours[all.offsets[v] + 1]);
    const Vec3 in = vec3::unit(vec3::sub(vec3::at(mesh.positions, v), p)), out = vec3::unit(vec3::sub(q, vec3::at(mesh.positions, v)));
    stop[v] = vec3::dot(in, out) < cos_turn;
  }
  // From each stop along each of its edges to the next stop; then the closed loops with no stop
  // that no walk reached. Short chains are left out.
  std::vector<std::array<std::uint32_t, 2>> kept;
  std::vector<std::uint8_t> visited(mesh.vertex_count(), 0);  // vertices inside lines, walked
  auto walk = [&](std::uint32_t start, std::uint32_t next) {
    std::vector<std::array<std::uint32_t, 2>> chain{{start, next}};
    std::uint32_t previous = start, at = next;
    while (!stop[at] && at != start) {
      visited[at] = 1;
      const std::uint32_t step = other_neighbour(all, at, previous);
      chain.push_back({at, step});
      previous = at, at = step;
    }
    // A chain between corners is walked from both ends (a loop through one corner, both ways
    // round): keep it once. A loop with no corner is walked once.
    if (chain.size() < min_chain_edges || (stop[start] && std::pair(at, previous) < std::pair(start, next))) return;
    // Its sides: the median over its edges must be within max_side_degrees.
    std::vector<double> sides;
    for (const auto& [u, w] : chain) sides.push_back(side_cos(edge_between(topology, incident, u, w)));
    std::nth_element(sides.begin(), sides.begin() + std::ptrdiff_t(sides.size() / 2), sides.end());
    if (sides[sides.size() / 2] >= cos_side) kept.insert(kept.end(), chain.begin(), chain.end());
  };
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (stop[v])
      for (std::uint32_t k = all.offsets[v]; k < all.offsets[v + 1]; ++k) walk(v, all.neighbours[k]);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (all.degree(v) == 2 && !stop[v] && !visited[v]) {
      visited[v] = 1;
      walk(v, all.neighbours[all.offsets[v]]);
    }
  FeatureLines lines = FeatureLines::from_edges(mesh.vertex_count(), kept);
  if (!lines.empty()) {
    lines.kink.assign(mesh.vertex_count(), 0);
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) lines.kink[v] = stop[v] && lines.degree(v) == 2;
  }
  return lines;
}

std::vector<BaseFeatureEdge> base_feature_edges(const FeatureLines& lines, const std::vector<std::uint32_t>& original_vertex) {
  std::vector<BaseFeatureEdge> edges;
  if (lines.empty()) return edges;
  std::unordered_map<std::uint32_t, std::uint32_t> base_of;  // input vertex -> base vertex
  for (std::uint32_t b = 0; b < original_vertex.size(); ++b) base_of.emplace(original_vertex[b], b);
  for (std::uint32_t a = 0; a < original_vertex.size(); ++a) {
    const std::uint32_t start = original_vertex[a];
    for (std::uint32_t k = lines.offsets[start]; k < lines.offsets[start + 1]; ++k) {
      // Along the line to the next vertex the base kept; the vertices between were collapsed
      // along it, so they are inside the line (corners stay in the base).
      std::vector<std::uint32_t> path{start, lines.neighbours[k]};
      while (!base_of.contains(path.back()) && lines.degree(path.back()) == 2)
        path.push_back(other_neighbour(lines, path.back(), path[path.size() - 2]));
      const auto end = base_of.find(path.back());
      if (end == base_of.end()) continue;  // a removed corner: cannot happen with decimate()'s rule
      if (a < end->second) edges.push_back({a, end->second, std::move(path)});
    }
  }
  return edges;
}

FeaturePlacement place_on_features(const SemiRegularHierarchy& h, const TriangleMesh& input, const TriangleMesh& base,
                                   const std::vector<BaseFeatureEdge>& edges) {
  const int levels = h.levels();
  const std::uint32_t total = h.vertex_count(levels);
  FeaturePlacement placement;
  placement.fixed.assign(total, 0);
  placement.positions.assign(3 * std::size_t{total}, 0.0);
  if (edges.empty()) return placement;

  // Each base feature edge's polyline as arc lengths, oriented as the level-0 edge is (the
  // refinement's halves 2e = (a, m), 2e + 1 = (m, b) count from its first vertex).
  const TriangleTopology& coarse = h.topology(0);
  const VertexEdges incident(coarse);
  struct Polyline {
    std::vector<Vec3> points;
    std::vector<double> length;  // cumulative, from points[0]
  };
  std::vector<Polyline> line_of(coarse.edge_count());
  for (const BaseFeatureEdge& edge : edges) {
    const std::uint32_t e = edge_between(coarse, incident, edge.a, edge.b);
    if (e == kNone) continue;  // not an edge of the base (cannot happen with decimate())
    Polyline& line = line_of[e];
    const bool reversed = coarse.edge_vertices[2 * e] != edge.a;
    for (std::size_t i = 0; i < edge.path.size(); ++i)
      line.points.push_back(vec3::at(input.positions, edge.path[reversed ? edge.path.size() - 1 - i : i]));
    line.length.assign(1, 0.0);
    for (std::size_t i = 1; i < line.points.size(); ++i) {
      const Vec3 d = vec3::sub(line.points[i], line.points[i - 1]);
      line.length.push_back(line.length.back() + std::sqrt(vec3::dot(d, d)));
    }
    for (const std::uint32_t v : {edge.a, edge.b}) {
      placement.fixed[v] = 1;
      std::copy_n(base.positions.begin() + 3 * std::ptrdiff_t{v}, 3, placement.positions.begin() + 3 * std::ptrdiff_t{v});
    }
  }
  // The point at fraction t of a polyline's length.
  auto point_at = [](const Polyline& line, double t) {
    const double s = t * line.length.back();
    const std::size_t i = std::min<std::size_t>(
        std::upper_bound(line.length.begin(), line.length.end(), s) - line.length.begin(), line.length.size() - 1);
    const double span = line.length[i] - line.length[i - 1];
    const double u = span > 0 ? (s - line.length[i - 1]) / span : 0.0;
    const Vec3 &p = line.points[i - 1], &q = line.points[i];
    return Vec3{p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1]), p[2] + u * (q[2] - p[2])};
  };
  // The odd vertex of level j on edge e of level j − 1: e descends from level-0 edge e >> (j − 1)
  // when each of its ancestors is a half of an edge (index below twice the coarser edge count;
  // the inner edges come after the halves), and is then its part k = e − (e0 << (j − 1)).
  for (int j = 1; j <= levels; ++j)
    for (std::uint32_t v = h.vertex_count(j - 1); v < h.vertex_count(j); ++v) {
      std::uint32_t e = v - h.vertex_count(j - 1);
      bool on_base_edge = true;
      for (int i = j - 1; on_base_edge && i >= 1; --i) {
        on_base_edge = e < 2 * (h.vertex_count(i) - h.vertex_count(i - 1));  // E_{i-1} = V_i − V_{i-1}
        e >>= 1;
      }
      if (!on_base_edge || line_of[e].points.empty()) continue;
      const std::uint32_t k = v - h.vertex_count(j - 1) - (e << (j - 1));
      const Vec3 p = point_at(line_of[e], std::ldexp(2.0 * k + 1, -j));
      placement.fixed[v] = 1;
      std::copy(p.begin(), p.end(), placement.positions.begin() + 3 * std::ptrdiff_t{v});
    }
  return placement;
}

}  // namespace meshlift
