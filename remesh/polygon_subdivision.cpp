// Catmull-Clark and Doo-Sabin subdivision on flat polygon meshes, over a half-edge view
// (PolygonTopology) built from the index arrays.
#include "meshlift/polygon_subdivision.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace meshlift {

namespace {

constexpr std::uint64_t kMaxOutputVertices = std::uint64_t{1} << 31;
constexpr std::uint64_t kMaxOutputCorners = kNone - 1;  // face_offsets are 32-bit

void check_levels(const char* scheme, int levels) {
  if (levels < 0 || levels > kMaxSubdivisionLevels)
    throw MeshError(std::string(scheme) + ": levels must be in [0, " + std::to_string(kMaxSubdivisionLevels) +
                    "], got " + std::to_string(levels));
}

void check_output_size(const char* scheme, std::uint64_t vertices, std::uint64_t corners) {
  if (vertices > kMaxOutputVertices || corners > kMaxOutputCorners)
    throw MeshError(std::string(scheme) + ": output would have " + std::to_string(vertices) + " vertices and " +
                    std::to_string(corners) + " face corners, over the 2^31 / 2^32-1 limit");
}

// Valence-dependent Catmull-Clark vertex weights, computed once per valence met.
class CatmullClarkWeights {
 public:
  struct Weights {
    double self;  // (n-2)/n
    double ring;  // 1/n², for each neighbouring vertex and each face point
  };
  const Weights& operator()(std::uint32_t n) {
    while (table_.size() <= n) {
      const double k = static_cast<double>(table_.size());
      table_.push_back(k == 0 ? Weights{0, 0} : Weights{(k - 2) / k, 1 / (k * k)});
    }
    return table_[n];
  }

 private:
  std::vector<Weights> table_;
};

PolygonMesh catmull_clark_step(const PolygonMesh& mesh, const PolygonTopology& topology, BoundaryVertexRule rule,
                               CatmullClarkWeights& weights) {
  const std::size_t vertex_count = mesh.vertex_count();
  const std::size_t edge_count = topology.edge_count();
  const std::size_t face_count = mesh.face_count();
  const std::size_t corner_count = mesh.face_indices.size();
  check_output_size("catmull_clark", std::uint64_t{vertex_count} + edge_count + face_count,
                    std::uint64_t{4} * corner_count);
  const std::size_t first_edge_point = vertex_count;
  const std::size_t first_face_point = vertex_count + edge_count;

  PolygonMesh out;
  out.positions.assign(3 * (vertex_count + edge_count + face_count), 0.0);
  const double* p = mesh.positions.data();
  double* q = out.positions.data();
  const auto& index = mesh.face_indices;

  // Face point: f = (1/m) Σ v_j, the centroid of the face's m corners.
  for (std::size_t f = 0; f < face_count; ++f) {
    double* fp = q + 3 * (first_face_point + f);
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t c = begin; c < end; ++c)
      for (int k = 0; k < 3; ++k) fp[k] += p[3 * index[c] + k];
    const double m = static_cast<double>(end - begin);
    for (int k = 0; k < 3; ++k) fp[k] /= m;
  }

  // Edge point (seed 000 eq. 4): interior e = (V + E + f_1 + f_2) / 4 over the edge's ends and
  // the face points of its two faces; boundary e = (V + E) / 2.
  for (std::size_t e = 0; e < edge_count; ++e) {
    const std::uint32_t h = topology.edge_halfedge[e], o = topology.opposite[h];
    const double* a = p + 3 * index[h];
    const double* b = p + 3 * index[topology.next[h]];
    double* ep = q + 3 * (first_edge_point + e);
    if (o == kNone) {
      for (int k = 0; k < 3; ++k) ep[k] = (a[k] + b[k]) * 0.5;
    } else {
      const double* f1 = q + 3 * (first_face_point + topology.face[h]);
      const double* f2 = q + 3 * (first_face_point + topology.face[o]);
      for (int k = 0; k < 3; ++k) ep[k] = (a[k] + b[k] + f1[k] + f2[k]) * 0.25;
    }
  }

  // Vertex point.
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const std::uint32_t start = topology.outgoing[v];
    const double* pv = p + 3 * v;
    double* vp = q + 3 * v;
    if (start == kNone) {  // isolated vertex: no rule applies, carried over
      for (int k = 0; k < 3; ++k) vp[k] = pv[k];
      continue;
    }
    if (topology.boundary[v]) {
      std::uint32_t last = start;
      while (topology.rotate(last) != kNone) last = topology.rotate(last);
      const double* b1 = p + 3 * index[topology.next[start]];
      const double* b2 = p + 3 * index[topology.prev[last]];
      if (rule == BoundaryVertexRule::cubic_bspline) {
        // Cubic B-spline (seed 004): v' = (b1 + 6 v + b2) / 8.
        for (int k = 0; k < 3; ++k) vp[k] = (b1[k] + 6 * pv[k] + b2[k]) / 8;
      } else {
        // OpenMesh 9 CatmullClarkT::update_vertex: v' = (v + m1 + m2) / 3 over the two boundary
        // edge midpoints m_i = (v + b_i)/2, i.e. (b1 + 4 v + b2) / 6.
        for (int k = 0; k < 3; ++k) vp[k] = (pv[k] + (pv[k] + b1[k]) * 0.5 + (pv[k] + b2[k]) * 0.5) / 3;
      }
      continue;
    }
    // Interior (seed 000 eq. 4): v' = ((n-2)/n) V + (1/n²) Σ E_i + (1/n²) Σ f_i, with E_i the n
    // neighbouring vertices and f_i the n new face points around V.
    const auto& w = weights(topology.face_count_at[v]);
    double ring[3] = {0, 0, 0};
    std::uint32_t h = start;
    do {
      const double* neighbour = p + 3 * index[topology.next[h]];
      const double* fp = q + 3 * (first_face_point + topology.face[h]);
      for (int k = 0; k < 3; ++k) ring[k] += neighbour[k] + fp[k];
      h = topology.rotate(h);
    } while (h != start);
    for (int k = 0; k < 3; ++k) vp[k] = w.self * pv[k] + w.ring * ring[k];
  }

  // Face f with corners c_0..c_{m-1} -> quads (v_i, e(c_i), f, e(c_{i-1})).
  out.face_indices.reserve(4 * corner_count);
  out.face_offsets.reserve(corner_count + 1);
  for (std::size_t f = 0; f < face_count; ++f)
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
      out.face_indices.insert(out.face_indices.end(),
                              {index[c], static_cast<std::uint32_t>(first_edge_point + topology.edge[c]),
                               static_cast<std::uint32_t>(first_face_point + f),
                               static_cast<std::uint32_t>(first_edge_point + topology.edge[topology.prev[c]])});
      out.face_offsets.push_back(static_cast<std::uint32_t>(out.face_indices.size()));
    }
  return out;
}

// Doo-Sabin weights α_d = α_{i,i-d} of an n-gon (seed 004), computed once per face size:
// α_0 = (n+5)/(4n), α_d = (3 + 2 cos(2πd/n)) / (4n).
class DooSabinWeights {
 public:
  const std::vector<double>& operator()(std::uint32_t n) {
    if (table_.size() <= n) table_.resize(n + 1);
    auto& alpha = table_[n];
    if (alpha.empty()) {
      const double dn = static_cast<double>(n);
      alpha.resize(n);
      alpha[0] = (dn + 5) / (4 * dn);
      for (std::uint32_t d = 1; d < n; ++d) alpha[d] = (3 + 2 * std::cos(2 * M_PI * d / dn)) / (4 * dn);
    }
    return alpha;
  }

 private:
  std::vector<std::vector<double>> table_;
};

// Above this face size the O(n²) direct sum is replaced by its O(n) factorisation.
constexpr std::uint32_t kDooSabinDirectMaxCorners = 64;

PolygonMesh doo_sabin_step(const PolygonMesh& mesh, const PolygonTopology& topology, DooSabinWeights& weights) {
  const std::size_t corner_count = mesh.face_indices.size();
  const std::size_t face_count = mesh.face_count();
  std::uint64_t interior_edges = 0, interior_vertices = 0, v_face_corners = 0;
  for (std::size_t e = 0; e < topology.edge_count(); ++e)
    interior_edges += topology.opposite[topology.edge_halfedge[e]] != kNone;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    if (topology.outgoing[v] != kNone && !topology.boundary[v]) {
      ++interior_vertices;
      v_face_corners += topology.face_count_at[v];
    }
  check_output_size("doo_sabin", corner_count, corner_count + 4 * interior_edges + v_face_corners);

  PolygonMesh out;
  out.positions.assign(3 * corner_count, 0.0);
  const double* p = mesh.positions.data();
  const auto& index = mesh.face_indices;
  for (std::size_t f = 0; f < face_count; ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], n = mesh.face_offsets[f + 1] - begin;
    if (n <= kDooSabinDirectMaxCorners) {
      // v_i' = Σ_j α_ij v_j, α_ij = α_{(i-j) mod n} (seed 004).
      const auto& alpha = weights(n);
      for (std::uint32_t i = 0; i < n; ++i) {
        double* out_i = out.positions.data() + 3 * (begin + i);
        for (std::uint32_t j = 0; j < n; ++j) {
          const double a = alpha[(i + n - j) % n];
          for (int k = 0; k < 3; ++k) out_i[k] += a * p[3 * index[begin + j] + k];
        }
      }
    } else {
      // The same rule regrouped: v_i' = v_i/4 + (3/(4n)) Σ v_j + (1/(2n)) (cos θ_i C + sin θ_i S),
      // θ_j = 2πj/n, C = Σ cos θ_j v_j, S = Σ sin θ_j v_j (since cos(θ_i - θ_j) expands).
      const double dn = n;
      double sum[3] = {0, 0, 0}, c_sum[3] = {0, 0, 0}, s_sum[3] = {0, 0, 0};
      for (std::uint32_t j = 0; j < n; ++j) {
        const double theta = 2 * M_PI * j / dn, c = std::cos(theta), s = std::sin(theta);
        for (int k = 0; k < 3; ++k) {
          const double x = p[3 * index[begin + j] + k];
          sum[k] += x;
          c_sum[k] += c * x;
          s_sum[k] += s * x;
        }
      }
      for (std::uint32_t i = 0; i < n; ++i) {
        const double theta = 2 * M_PI * i / dn, c = std::cos(theta), s = std::sin(theta);
        for (int k = 0; k < 3; ++k)
          out.positions[3 * (begin + i) + k] = 0.25 * p[3 * index[begin + i] + k] + 3 / (4 * dn) * sum[k] +
                                               (c * c_sum[k] + s * s_sum[k]) / (2 * dn);
      }
    }
  }

  out.face_indices.reserve(corner_count + 4 * interior_edges + v_face_corners);
  out.face_offsets.reserve(face_count + interior_edges + interior_vertices + 1);
  auto close_face = [&out] { out.face_offsets.push_back(static_cast<std::uint32_t>(out.face_indices.size())); };
  // F-faces: the face's own new corners, same orientation.
  for (std::size_t f = 0; f < face_count; ++f) {
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) out.face_indices.push_back(c);
    close_face();
  }
  // E-faces: edge h = (v -> w) in face f, o = (w -> v) in face g; the quad runs w_f, v_f, v_g, w_g.
  for (std::size_t e = 0; e < topology.edge_count(); ++e) {
    const std::uint32_t h = topology.edge_halfedge[e], o = topology.opposite[h];
    if (o == kNone) continue;
    out.face_indices.insert(out.face_indices.end(), {topology.next[h], h, topology.next[o], o});
    close_face();
  }
  // V-faces: the corners at v of its faces, counter-clockwise.
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const std::uint32_t start = topology.outgoing[v];
    if (start == kNone || topology.boundary[v]) continue;
    std::uint32_t h = start;
    do {
      out.face_indices.push_back(h);
      h = topology.rotate(h);
    } while (h != start);
    close_face();
  }
  return out;
}

}  // namespace

PolygonTopology build_topology(const PolygonMesh& mesh) {
  if (mesh.positions.size() % 3 != 0) throw MeshError("mesh: position array length is not a multiple of 3");
  if (mesh.face_offsets.empty() || mesh.face_offsets.front() != 0 ||
      mesh.face_offsets.back() != mesh.face_indices.size())
    throw MeshError("mesh: face_offsets do not span face_indices");
  const std::size_t vertex_count = mesh.vertex_count();
  const std::size_t corner_count = mesh.face_indices.size();
  if (vertex_count >= kNone || corner_count >= kNone) throw MeshError("mesh: more than 2^32-2 vertices or corners");

  PolygonTopology t;
  t.face.resize(corner_count);
  t.next.resize(corner_count);
  t.prev.resize(corner_count);
  const auto& index = mesh.face_indices;
  std::vector<std::uint32_t> seen_in_face(vertex_count, kNone);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    if (end < begin || end - begin < 3)
      throw MeshError("mesh: face " + std::to_string(f) + " has fewer than 3 corners");
    for (std::uint32_t c = begin; c < end; ++c) {
      const std::uint32_t v = index[c];
      if (v >= vertex_count)
        throw MeshError("mesh: face " + std::to_string(f) + " names vertex " + std::to_string(v) + ", which does not exist");
      if (seen_in_face[v] == f)
        throw MeshError("mesh: face " + std::to_string(f) + " repeats vertex " + std::to_string(v));
      seen_in_face[v] = static_cast<std::uint32_t>(f);
      t.face[c] = static_cast<std::uint32_t>(f);
      t.next[c] = c + 1 == end ? begin : c + 1;
      t.prev[c] = c == begin ? end - 1 : c - 1;
    }
  }

  // Opposites: sort the directed edges (from, to); a repeated one means an edge with more than
  // two faces or two faces of opposite orientation.
  auto key = [](std::uint32_t from, std::uint32_t to) { return (std::uint64_t{from} << 32) | to; };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> directed(corner_count);
  for (std::uint32_t h = 0; h < corner_count; ++h) directed[h] = {key(index[h], index[t.next[h]]), h};
  std::sort(directed.begin(), directed.end());
  for (std::size_t i = 1; i < directed.size(); ++i)
    if (directed[i].first == directed[i - 1].first)
      throw MeshError("mesh: non-manifold edge (" + std::to_string(directed[i].first >> 32) + ", " +
                      std::to_string(directed[i].first & 0xffffffffu) +
                      "): more than two faces or inconsistent orientation");
  t.opposite.assign(corner_count, kNone);
  for (std::uint32_t h = 0; h < corner_count; ++h) {
    const std::uint64_t twin = key(index[t.next[h]], index[h]);
    const auto it = std::lower_bound(directed.begin(), directed.end(), std::make_pair(twin, std::uint32_t{0}));
    if (it != directed.end() && it->first == twin) t.opposite[h] = it->second;
  }

  t.edge.resize(corner_count);
  for (std::uint32_t h = 0; h < corner_count; ++h) {
    const std::uint32_t o = t.opposite[h];
    if (o != kNone && o < h) continue;
    t.edge[h] = static_cast<std::uint32_t>(t.edge_halfedge.size());
    if (o != kNone) t.edge[o] = t.edge[h];
    t.edge_halfedge.push_back(h);
  }

  // Vertex fans: at most one outgoing boundary half-edge, and one walk must see every face.
  t.outgoing.assign(vertex_count, kNone);
  t.face_count_at.assign(vertex_count, 0);
  t.boundary.assign(vertex_count, 0);
  for (std::uint32_t h = 0; h < corner_count; ++h) {
    const std::uint32_t v = index[h];
    ++t.face_count_at[v];
    if (t.opposite[h] == kNone) {
      if (t.boundary[v]) throw MeshError("mesh: non-manifold vertex " + std::to_string(v) + " (two boundary fans)");
      t.boundary[v] = 1;
      t.outgoing[v] = h;
    } else if (t.outgoing[v] == kNone) {
      t.outgoing[v] = h;
    }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const std::uint32_t start = t.outgoing[v];
    if (start == kNone) continue;
    std::uint32_t visited = 0, h = start;
    do {
      ++visited;
      h = t.rotate(h);
    } while (h != kNone && h != start && visited <= t.face_count_at[v]);
    if (visited != t.face_count_at[v] || (h == kNone) != (t.boundary[v] != 0))
      throw MeshError("mesh: non-manifold vertex " + std::to_string(v) + " (its faces form more than one fan)");
  }
  return t;
}

PolygonMesh catmull_clark(const PolygonMesh& mesh, int levels, BoundaryVertexRule boundary) {
  check_levels("catmull_clark", levels);
  PolygonMesh current = mesh;
  PolygonTopology topology = build_topology(current);
  CatmullClarkWeights weights;
  for (int level = 0; level < levels; ++level) {
    current = catmull_clark_step(current, topology, boundary, weights);
    if (level + 1 < levels) topology = build_topology(current);
  }
  return current;
}

PolygonMesh doo_sabin(const PolygonMesh& mesh, int levels) {
  check_levels("doo_sabin", levels);
  PolygonMesh current = mesh;
  PolygonTopology topology = build_topology(current);
  DooSabinWeights weights;
  for (int level = 0; level < levels; ++level) {
    current = doo_sabin_step(current, topology, weights);
    if (level + 1 < levels) topology = build_topology(current);
  }
  return current;
}

}  // namespace meshlift
