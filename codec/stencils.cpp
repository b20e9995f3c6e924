#include "stencils.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace meshlift::stencils {
namespace {

/// Accumulates one row, merging repeated sources, then appends it to a step.
class RowBuilder {
 public:
  void add(std::uint32_t index, double weight) {
    for (auto& [i, w] : entries_)
      if (i == index) {
        w += weight;
        return;
      }
    entries_.emplace_back(index, weight);
  }
  void finish(LiftingStep& step, double scale = 1.0) {
    sources_.clear();
    weights_.clear();
    for (const auto& [i, w] : entries_) {
      sources_.push_back(i);
      weights_.push_back(w);
    }
    step.append_row(scale, sources_, weights_);
    entries_.clear();
  }

 private:
  std::vector<std::pair<std::uint32_t, double>> entries_;
  std::vector<std::uint32_t> sources_;
  std::vector<double> weights_;
};

LiftingStep empty_step(std::uint32_t first_target, std::size_t rows, std::size_t entries_per_row) {
  LiftingStep step;
  step.first_target = first_target;
  step.row_pattern.reserve(rows);
  step.indices.reserve(rows * entries_per_row);
  return step;
}

std::uint32_t other_face(const TriangleTopology& t, std::uint32_t e, std::uint32_t f) {
  return t.edge_faces[2 * e] == f ? t.edge_faces[2 * e + 1] : t.edge_faces[2 * e];
}

/// The edge of face f joining vertices u and v.
std::uint32_t face_edge(const TriangleTopology& t, std::uint32_t f, std::uint32_t u, std::uint32_t v) {
  for (int i = 0; i < 3; ++i) {
    const std::uint32_t e = t.face_edges[3 * f + i];
    const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
    if ((a == u && b == v) || (a == v && b == u)) return e;
  }
  return kNone;
}

/// The other boundary neighbour of boundary vertex v (not `not_this`), walking its boundary edges.
std::uint32_t boundary_neighbour(const TriangleTopology& t, const VertexEdges& ve, std::uint32_t v,
                                 std::uint32_t not_this) {
  for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k) {
    const std::uint32_t e = ve.edges[k];
    if (!t.is_boundary_edge(e)) continue;
    const std::uint32_t w = t.edge_vertices[2 * e] == v ? t.edge_vertices[2 * e + 1] : t.edge_vertices[2 * e];
    if (w != not_this) return w;
  }
  return kNone;
}

/// Ring of interior vertex `centre` in face order, starting at `start` (an edge neighbour).
std::vector<std::uint32_t> ordered_ring(const TriangleTopology& t, std::uint32_t centre, std::uint32_t start,
                                        std::uint32_t start_edge, unsigned valence) {
  std::vector<std::uint32_t> ring{start};
  std::uint32_t e = start_edge, f = t.edge_faces[2 * start_edge];
  while (ring.size() < valence) {
    const std::uint32_t w = t.opposite_vertex(f, e);
    ring.push_back(w);
    e = face_edge(t, f, centre, w);
    f = other_face(t, e, f);
  }
  return ring;
}

/// Zorin-Schroeder-Sweldens weights s_i on the ring of an extraordinary vertex of valence K
/// (CODEC-NOTES §2): K >= 5: s_i = (1/4 + cos(2 pi i/K) + cos(4 pi i/K)/2) / K; K = 3: 5/12, -1/12,
/// -1/12; K = 4: 3/8, 0, -1/8, 0. The vertex itself gets 3/4 (= 1 - sum s_i, as OpenMesh computes it).
std::vector<double> butterfly_ring_weights(unsigned K) {
  if (K == 3) return {5.0 / 12, -1.0 / 12, -1.0 / 12};
  if (K == 4) return {3.0 / 8, 0.0, -1.0 / 8, 0.0};
  std::vector<double> s(K);
  for (unsigned i = 0; i < K; ++i) {
    const double x = 2.0 * std::numbers::pi * i / K;
    s[i] = (0.25 + std::cos(x) + 0.5 * std::cos(2 * x)) / K;
  }
  return s;
}

void butterfly_row(const TriangleTopology& t, const VertexEdges& ve, std::uint32_t e, RowBuilder& row) {
  const std::uint32_t a0 = t.edge_vertices[2 * e], a1 = t.edge_vertices[2 * e + 1];
  if (t.is_boundary_edge(e)) {
    // Boundary: 4-point rule (-1, 9, 9, -1)/16 along the boundary polyline (Dyn, Levin, Gregory 1987).
    row.add(a0, 9.0 / 16);
    row.add(a1, 9.0 / 16);
    row.add(boundary_neighbour(t, ve, a0, a1), -1.0 / 16);
    row.add(boundary_neighbour(t, ve, a1, a0), -1.0 / 16);
    return;
  }
  auto irregular = [&](std::uint32_t v) { return !ve.boundary[v] && ve.valence(v) != 6; };
  if (!irregular(a0) && !irregular(a1)) {
    // Regular 8-point butterfly: (a0+a1)/2 + (b0+b1)/8 - (c0+c1+c2+c3)/16 (seed 003 §5.3.2).
    // A tip c across a boundary wing edge (x, b) of face (x, b, y) is missing; like OpenMesh's
    // ModifiedButterFlyT we use its reflection x + b - y, which keeps linear reproduction.
    row.add(a0, 0.5);
    row.add(a1, 0.5);
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t f = t.edge_faces[2 * e + side];
      const std::uint32_t b = t.opposite_vertex(f, e);
      row.add(b, 1.0 / 8);
      for (const std::uint32_t x : {a0, a1}) {
        const std::uint32_t y = x == a0 ? a1 : a0;
        const std::uint32_t wing = face_edge(t, f, x, b);
        const std::uint32_t across = other_face(t, wing, f);
        if (across != kNone) {
          row.add(t.opposite_vertex(across, wing), -1.0 / 16);
        } else {
          row.add(x, -1.0 / 16);
          row.add(b, -1.0 / 16);
          row.add(y, 1.0 / 16);
        }
      }
    }
    return;
  }
  // Extraordinary endpoint(s): 3/4 on the vertex and s_i on its ring, ring index 0 at the edge's
  // other endpoint; averaged when both endpoints are extraordinary (Zorin et al. 1996).
  const double share = irregular(a0) && irregular(a1) ? 0.5 : 1.0;
  for (const std::uint32_t x : {a0, a1}) {
    if (!irregular(x)) continue;
    const unsigned K = ve.valence(x);
    const auto ring = ordered_ring(t, x, x == a0 ? a1 : a0, e, K);
    const auto s = butterfly_ring_weights(K);
    row.add(x, share * 0.75);
    for (unsigned i = 0; i < K; ++i) row.add(ring[i], share * s[i]);
  }
}

/// The wing vertices of every edge, 2 per edge: the vertex opposite the edge in edge_faces[2e],
/// then in edge_faces[2e+1] (kNone on a boundary). One pass over the faces.
std::vector<std::uint32_t> wing_vertices(const TriangleTopology& t) {
  std::vector<std::uint32_t> wings(2 * t.edge_count(), kNone);
  for (std::uint32_t f = 0; f < t.face_count(); ++f)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t e = t.face_edges[3 * f + i];
      wings[2 * e + (t.edge_faces[2 * e] == f ? 0 : 1)] = t.triangles[3 * f + (i + 2) % 3];
    }
  return wings;
}

}  // namespace

LiftingStep predict(const TriangleTopology& t, const VertexEdges& ve, Scheme scheme) {
  LiftingStep step = empty_step(t.vertex_count, t.edge_count(), 4);
  RowBuilder row;
  const std::vector<std::uint32_t> wings = scheme == Scheme::loop ? wing_vertices(t) : std::vector<std::uint32_t>{};
  for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
    const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
    switch (scheme) {
      case Scheme::linear:
        // odd = (a + b) / 2
        row.add(a, 0.5);
        row.add(b, 0.5);
        break;
      case Scheme::butterfly:
        butterfly_row(t, ve, e, row);
        break;
      case Scheme::loop:
        if (t.is_boundary_edge(e)) {
          // Boundary edge: odd = (a + b) / 2 (cubic B-spline midpoint rule).
          row.add(a, 0.5);
          row.add(b, 0.5);
        } else {
          // Interior edge: odd = 3/8 (a + b) + 1/8 (c + d), c, d the wing vertices.
          row.add(a, 3.0 / 8);
          row.add(b, 3.0 / 8);
          row.add(wings[2 * e], 1.0 / 8);
          row.add(wings[2 * e + 1], 1.0 / 8);
        }
        break;
    }
    row.finish(step);
  }
  return step;
}

LiftingStep loop_update(const TriangleTopology& t, const VertexEdges& ve) {
  const std::uint32_t V = t.vertex_count;
  LiftingStep step = empty_step(0, V, 6);
  RowBuilder row;
  std::vector<double> w_by_valence;  // w_n, computed once per valence
  for (std::uint32_t v = 0; v < V; ++v) {
    const unsigned n = ve.valence(v);
    double scale = 1.0;  // isolated vertex: nothing to average
    if (n == 0) {
    } else if (ve.boundary[v]) {
      // Boundary even: v' = v/2 + (odd_l + odd_r)/4 over the two boundary-edge odds, which equals
      // Loop's boundary rule 3/4 v + 1/8 (b_l + b_r) since odd = (v + b)/2 there.
      scale = 0.5;
      for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k)
        if (t.is_boundary_edge(ve.edges[k])) row.add(V + ve.edges[k], 0.25);
    } else {
      // Interior even: sum of its n odds = 3n/8 v + 5/8 sum(v_i), so Loop's
      // v' = (1 - n beta) v + beta sum(v_i) = s_n v + w_n sum(odd), w_n = 8 beta / 5, s_n = 1 - n w_n.
      while (w_by_valence.size() <= n) {
        const auto k = static_cast<unsigned>(w_by_valence.size());
        w_by_valence.push_back(k == 0 ? 0.0 : 8.0 * loop_beta(k) / 5.0);
      }
      const double w = w_by_valence[n];
      scale = 1.0 - n * w;
      for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k) row.add(V + ve.edges[k], w);
    }
    row.finish(step, scale);
  }
  return step;
}

LiftingStep mean_preserving_update(const TriangleTopology& t, const VertexEdges& ve, const LiftingStep& predict) {
  const std::uint32_t V = t.vertex_count;
  // c_l = sum over odd k of p(k, l): how much of the fine signal even vertex l predicts.
  std::vector<double> column_sum(V, 0.0);
  const std::uint32_t* source = predict.indices.data();
  for (std::uint32_t pattern : predict.row_pattern) {
    const LiftingStep::Pattern& p = predict.patterns[pattern];
    for (std::uint32_t k = 0; k < p.arity; ++k) column_sum[*source++] += predict.pattern_weights[p.first_weight + k];
  }
  LiftingStep step = empty_step(0, V, 6);
  RowBuilder row;
  for (std::uint32_t v = 0; v < V; ++v) {
    const double mass = 1.0 + column_sum[v];
    const double lambda = mass > 1e-3 ? 1.0 / (2.0 * mass) : 0.0;
    for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k) row.add(V + ve.edges[k], -lambda);
    row.finish(step);
  }
  return step;
}

}  // namespace meshlift::stencils
