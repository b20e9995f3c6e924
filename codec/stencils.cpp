#include "stencils.h"

#include "concurrent.h"
#include "large_array.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace meshlift::stencils {
namespace {

/// Accumulates one row, merging repeated sources (a vertex reached twice, as near a valence-3
/// vertex or across a reflected tip, gets the sum of its weights, added in first-seen order).
class RowBuilder {
 public:
  void add(std::uint32_t index, double weight) {
    for (std::size_t k = 0; k < sources_.size(); ++k)
      if (sources_[k] == index) {
        weights_[k] += weight;
        return;
      }
    sources_.push_back(index);
    weights_.push_back(weight);
  }
  std::span<const std::uint32_t> sources() const { return sources_; }
  std::span<const double> weights() const { return weights_; }
  void clear() {
    sources_.clear();
    weights_.clear();
  }

 private:
  std::vector<std::uint32_t> sources_;
  std::vector<double> weights_;
};

/// Writes the rows of one step, in target order, into an index array sized once from an estimate
/// of its entries (exact for closed meshes), and groups them into runs of one pattern. Rows of a
/// pattern the caller already holds (the regular ones) cost a copy of their sources; other rows
/// find their pattern by value.
class StepWriter {
 public:
  StepWriter(std::uint32_t first_target, std::size_t expected_entries) {
    step_.first_target = first_target;
    assign_large(step_.indices, expected_entries + LiftingStep::kPadding);
  }
  /// The same writing into `buffer` (a block's step: the indices of an earlier one, handed back),
  /// grown if it is short, never shrunk.
  StepWriter(std::uint32_t first_target, std::size_t expected_entries, std::vector<std::uint32_t>&& buffer)
      : recycled_(true) {
    step_.first_target = first_target;
    step_.indices = std::move(buffer);
    const std::size_t needed = expected_entries + LiftingStep::kPadding;
    if (step_.indices.capacity() < needed)
      assign_large(step_.indices, needed);  // fresh storage: advised and made resident at once
    else if (step_.indices.size() < needed)
      step_.indices.resize(needed);
  }

  /// The pattern with exactly this scale and these weights (compared as values, as the rows that
  /// share it are computed with them), added if there is none.
  std::uint32_t pattern(double scale, std::span<const double> weights) {
    const auto arity = static_cast<std::uint32_t>(weights.size());
    auto matches = [&](std::uint32_t p) {
      const LiftingStep::Pattern& candidate = step_.patterns[p];
      return candidate.arity == arity && candidate.scale == scale &&
             std::equal(weights.begin(), weights.end(), step_.pattern_weights.begin() + candidate.first_weight);
    };
    // Consecutive rows mostly repeat the previous row's pattern: try it before hashing.
    if (!step_.runs.empty() && matches(step_.runs.back().pattern)) return step_.runs.back().pattern;
    const std::uint64_t key = hash(scale, weights);
    const auto [first, last] = by_hash_.equal_range(key);
    for (auto it = first; it != last; ++it)
      if (matches(it->second)) return it->second;
    const auto p = static_cast<std::uint32_t>(step_.patterns.size());
    step_.patterns.push_back({arity, static_cast<std::uint32_t>(step_.pattern_weights.size()), scale});
    step_.pattern_weights.insert(step_.pattern_weights.end(), weights.begin(), weights.end());
    by_hash_.emplace(key, p);
    return p;
  }

  /// A row of `pattern`; its sources are distinct and in the pattern's weight order.
  void row(std::uint32_t pattern, std::span<const std::uint32_t> sources) {
    std::uint32_t* out = room(sources.size());
    for (std::size_t k = 0; k < sources.size(); ++k) out[k] = sources[k];
    used_ += sources.size();
    count(pattern);
  }
  /// The same with the arity known at compile time (the regular rows).
  template <std::size_t N>
  void row(std::uint32_t pattern, const std::uint32_t (&sources)[N]) {
    std::uint32_t* out = room(N);
    for (std::size_t k = 0; k < N; ++k) out[k] = sources[k];
    used_ += N;
    count(pattern);
  }
  void row(const RowBuilder& builder, double scale = 1.0) { row(pattern(scale, builder.weights()), builder.sources()); }
  /// A row of `pattern` whose `arity` sources the caller writes later, at its offset in indices().
  void reserve_row(std::uint32_t pattern, std::uint32_t arity) {
    room(arity);
    used_ += arity;
    count(pattern);
  }
  /// Room for `n` more entries, so that rows reserved now are not moved by later ones.
  void reserve(std::size_t n) { room(n); }
  std::uint32_t* indices() { return step_.indices.data(); }
  std::size_t entries() const { return used_; }

  LiftingStep finish() {
    // Keep the padding; give back a large overestimate (boundary rows are shorter than interior ones).
    step_.indices.resize(used_ + LiftingStep::kPadding);
    if (recycled_)  // the padding may hold an earlier block's sources; the buffer is kept whole
      std::fill(step_.indices.begin() + static_cast<std::ptrdiff_t>(used_), step_.indices.end(), 0u);
    else if (step_.indices.capacity() > step_.indices.size() + step_.indices.size() / 8)
      step_.indices.shrink_to_fit();
    step_.runs.shrink_to_fit();
    return std::move(step_);
  }

 private:
  std::uint32_t* room(std::size_t n) {
    // Only rows beyond the estimate get here (butterfly's longer rows near extraordinary vertices).
    if (used_ + n + LiftingStep::kPadding > step_.indices.size())
      step_.indices.resize(2 * (used_ + n) + LiftingStep::kPadding);
    return step_.indices.data() + used_;
  }
  void count(std::uint32_t pattern) {
    if (step_.runs.empty() || step_.runs.back().pattern != pattern) step_.runs.push_back({pattern, 0});
    ++step_.runs.back().rows;
    ++step_.row_count;
  }
  // FNV-1a over the values; +0.0 and -0.0 compare equal, so they hash alike.
  static std::uint64_t hash(double scale, std::span<const double> weights) {
    std::uint64_t h = 14695981039346656037ull;
    auto mix = [&h](double x) {
      std::uint64_t bits;
      x = x == 0.0 ? 0.0 : x;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    };
    mix(scale);
    for (double w : weights) mix(w);
    return h ^ weights.size();
  }

  LiftingStep step_;
  std::size_t used_ = 0;
  bool recycled_ = false;
  std::unordered_multimap<std::uint64_t, std::uint32_t> by_hash_;
};

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

/// Ring of interior vertex `centre` in face order, starting at `start` (an edge neighbour),
/// written into `ring` (reused from row to row).
void ordered_ring(const TriangleTopology& t, std::uint32_t centre, std::uint32_t start, std::uint32_t start_edge,
                  unsigned valence, std::vector<std::uint32_t>& ring) {
  ring.assign(1, start);
  std::uint32_t e = start_edge, f = t.edge_faces[2 * start_edge];
  while (ring.size() < valence) {
    const std::uint32_t w = t.opposite_vertex(f, e);
    ring.push_back(w);
    e = face_edge(t, f, centre, w);
    f = other_face(t, e, f);
  }
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

/// What butterfly's rows need to know of a level's vertices: valence and boundary flag from one
/// pass over the edges; the incident edges (VertexEdges) only if the level has a boundary, where
/// the 4-point rule walks them. The ring weights of each extraordinary valence, made once.
class ButterflyVertices {
 public:
  explicit ButterflyVertices(const TriangleTopology& t) : valence_(t.vertex_count, 0), boundary_(t.vertex_count, 0) {
    bool any_boundary = false;
    for (std::size_t e = 0; e < t.edge_count(); ++e) {
      const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
      ++valence_[a];
      ++valence_[b];
      if (t.edge_faces[2 * e + 1] == kNone) boundary_[a] = boundary_[b] = 1, any_boundary = true;
    }
    if (any_boundary) edges_.emplace(t);
    // The ring weights of every interior valence present, made here so that nothing changes once
    // built: two threads may read rows off one ButterflyVertices (RefinedPredictRows::synthesize).
    for (std::uint32_t v = 0; v < t.vertex_count; ++v)
      if (irregular(v)) {
        const std::uint32_t K = valence_[v];
        if (ring_weights_.size() <= K) ring_weights_.resize(K + 1);
        if (ring_weights_[K].empty()) ring_weights_[K] = butterfly_ring_weights(K);
      }
  }
  std::uint32_t valence(std::uint32_t v) const { return valence_[v]; }
  bool irregular(std::uint32_t v) const { return !boundary_[v] && valence_[v] != 6; }
  bool on_boundary(std::uint32_t v) const { return boundary_[v] != 0; }
  const VertexEdges& edges() const { return *edges_; }
  /// Those of an irregular vertex's valence K (made by the constructor).
  const std::vector<double>& ring_weights(unsigned K) const { return ring_weights_[K]; }

 private:
  std::vector<std::uint32_t> valence_;
  std::vector<std::uint8_t> boundary_;
  std::optional<VertexEdges> edges_;
  std::vector<std::vector<double>> ring_weights_;
};

/// Appends one row per vertex v < `vertices`: the sources source(e, k) of the edges e of
/// `topology` with v as endpoint k (edge_vertices[2e + k]), in ascending e; all of them, or for a
/// vertex on the boundary, if `boundary_rows_take_boundary_edges`, only its boundary edges.
/// row_pattern(v, arity, on_boundary) gives the pattern of v's row. A counting sort over the
/// edges writes the sources straight into the table, with no per-vertex edge list.
template <class Source, class RowPattern>
void append_vertex_rows(StepWriter& step, const TriangleTopology& topology, std::uint32_t vertices,
                        bool boundary_rows_take_boundary_edges, Source&& source, RowPattern&& row_pattern) {
  const auto E = static_cast<std::uint32_t>(topology.edge_count());
  std::vector<std::uint32_t> valence, boundary_edges;
  assign_large(valence, vertices);
  assign_large(boundary_edges, vertices);
  for (std::uint32_t e = 0; e < E; ++e) {
    const std::uint32_t a = topology.edge_vertices[2 * e], b = topology.edge_vertices[2 * e + 1];
    ++valence[a];
    ++valence[b];
    if (topology.is_boundary_edge(e)) ++boundary_edges[a], ++boundary_edges[b];
  }
  auto arity = [&](std::uint32_t v) {
    return boundary_rows_take_boundary_edges && boundary_edges[v] > 0 ? boundary_edges[v] : valence[v];
  };
  std::size_t entries = 0;
  for (std::uint32_t v = 0; v < vertices; ++v) entries += arity(v);
  step.reserve(entries);
  std::vector<std::size_t> position;  // where v's next source goes (2E may pass 2^32)
  assign_large(position, vertices);
  for (std::uint32_t v = 0; v < vertices; ++v) {
    const std::uint32_t n = arity(v);
    position[v] = step.entries();
    step.reserve_row(row_pattern(v, n, boundary_edges[v] > 0), n);
  }
  std::uint32_t* indices = step.indices();
  for (std::uint32_t e = 0; e < E; ++e) {
    const bool boundary = topology.is_boundary_edge(e);
    for (std::uint32_t k = 0; k < 2; ++k) {
      const std::uint32_t v = topology.edge_vertices[2 * e + k];
      if (boundary || !boundary_rows_take_boundary_edges || boundary_edges[v] == 0) indices[position[v]++] = source(e, k);
    }
  }
}

/// Loop's vertex rule over the odd vertices (CODEC-NOTES §3) for a vertex with n of them: the
/// row's scale, and its weight, the same on every source.
struct LoopVertexRule {
  double scale, weight;
};
LoopVertexRule loop_vertex_rule(std::uint32_t n, bool on_boundary) {
  // Isolated vertex: nothing to average.
  if (n == 0) return {1.0, 0.0};
  // Boundary even: v' = v/2 + (odd_l + odd_r)/4 over the two boundary-edge odds, which equals
  // Loop's boundary rule 3/4 v + 1/8 (b_l + b_r) since odd = (v + b)/2 there.
  if (on_boundary) return {0.5, 0.25};
  // Interior even: sum of its n odds = 3n/8 v + 5/8 sum(v_i), so Loop's
  // v' = (1 - n beta) v + beta sum(v_i) = s_n v + w_n sum(odd), w_n = 8 beta / 5, s_n = 1 - n w_n.
  const double w = 8.0 * loop_beta(n) / 5.0;
  return {1.0 - n * w, w};
}

/// The patterns of loop_vertex_rule(), each made once.
class LoopUpdatePatterns {
 public:
  explicit LoopUpdatePatterns(StepWriter& step) : step_(step) {}
  std::uint32_t operator()(std::uint32_t n, bool on_boundary) {
    auto make = [&] {
      const LoopVertexRule rule = loop_vertex_rule(n, on_boundary);
      return step_.pattern(rule.scale, std::vector<double>(n, rule.weight));
    };
    if (n == 0) {
      if (isolated_ == kNone) isolated_ = make();
      return isolated_;
    }
    if (on_boundary) {
      if (n != 2) return make();
      if (boundary_ == kNone) boundary_ = make();
      return boundary_;
    }
    if (of_valence_.size() <= n) of_valence_.resize(n + 1, kNone);
    if (of_valence_[n] == kNone) of_valence_[n] = make();
    return of_valence_[n];
  }

 private:
  StepWriter& step_;
  std::vector<std::uint32_t> of_valence_;
  std::uint32_t boundary_ = kNone, isolated_ = kNone;
};

/// The vertex of face f opposite its edge e.
std::uint32_t opposite(const TriangleTopology& t, std::uint32_t f, std::uint32_t e) {
  return t.triangles[3 * f + (edge_in_face(t, f, e) + 2) % 3];
}

/// The edge of face f other than e at its corner x (an endpoint of e): edge i runs c_i -> c_{i+1},
/// so at c_i the other edge is i+2, at c_{i+1} it is i+1.
std::uint32_t other_edge_at(const TriangleTopology& t, std::uint32_t f, std::uint32_t e, std::uint32_t x) {
  const std::uint32_t i = edge_in_face(t, f, e);
  return t.face_edges[3 * f + (t.triangles[3 * f + i] == x ? (i + 2) % 3 : (i + 1) % 3)];
}

// Butterfly's rules (CODEC-NOTES §2), each stated once, for the rows read off a level's own
// topology (butterfly_rows) and off the level below (ButterflyRefinedRows), which gather their
// sources differently and hand them over here in the same order.

/// One side of an interior edge (a0, a1): b, the vertex of that face opposite the edge, then the
/// tips across its wings (b, a0) and (a1, b), the third vertices of the faces beyond them (kNone
/// where a wing is on the boundary).
struct ButterflySide {
  std::uint32_t b, tip_a0, tip_a1;
};

/// The regular 8-point row (a0+a1)/2 + (b0+b1)/8 - (c0+c1+c2+c3)/16 (seed 003 §5.3.2), sources
/// a0, a1, then each side's b, tip_a0, tip_a1.
template <class Step>
std::uint32_t butterfly_regular_pattern(Step& step) {
  const double weights[] = {0.5, 0.5, 1.0 / 8, -1.0 / 16, -1.0 / 16, 1.0 / 8, -1.0 / 16, -1.0 / 16};
  return step.pattern(1.0, weights);
}

/// A boundary edge: the 4-point rule (-1, 9, 9, -1)/16 along the boundary polyline (Dyn, Levin,
/// Gregory 1987); beyond_a0 and beyond_a1 are the boundary neighbours of a0 and a1 other than each
/// other.
template <class Step>
void butterfly_boundary_row(Step& step, RowBuilder& row, std::uint32_t a0, std::uint32_t a1, std::uint32_t beyond_a0,
                            std::uint32_t beyond_a1) {
  row.add(a0, 9.0 / 16);
  row.add(a1, 9.0 / 16);
  row.add(beyond_a0, -1.0 / 16);
  row.add(beyond_a1, -1.0 / 16);
  step.row(row);
  row.clear();
}

/// The regular rule source by source where the row cannot be written straight: a tip c missing
/// across a boundary wing (x, b) of face (x, b, y) is replaced, like OpenMesh's
/// ModifiedButterFlyT, by its reflection x + b - y, which keeps linear reproduction; repeated
/// sources are merged.
template <class Step>
[[gnu::noinline]] void butterfly_reflected_row(Step& step, RowBuilder& row, std::uint32_t a0, std::uint32_t a1,
                                               const ButterflySide& first, const ButterflySide& second) {
  row.add(a0, 0.5);
  row.add(a1, 0.5);
  for (const ButterflySide& side : {first, second}) {
    row.add(side.b, 1.0 / 8);
    for (const std::uint32_t x : {a0, a1}) {
      const std::uint32_t tip = x == a0 ? side.tip_a0 : side.tip_a1;
      if (tip != kNone) {
        row.add(tip, -1.0 / 16);
      } else {
        row.add(x, -1.0 / 16);
        row.add(side.b, -1.0 / 16);
        row.add(x == a0 ? a1 : a0, 1.0 / 16);
      }
    }
  }
  step.row(row);
  row.clear();
}

/// An interior edge between two vertices that are not extraordinary: the regular row, written
/// straight (`regular`: butterfly_regular_pattern) where its eight sources exist and are distinct
/// (all but the smallest meshes), else butterfly_reflected_row.
template <class Step>
[[gnu::always_inline]] inline void butterfly_regular_row(Step& step, std::uint32_t regular, RowBuilder& row,
                                                         std::uint32_t a0, std::uint32_t a1, const ButterflySide& first,
                                                         const ButterflySide& second) {
  const std::uint32_t sources[8] = {a0, a1, first.b, first.tip_a0, first.tip_a1, second.b, second.tip_a0, second.tip_a1};
  bool straight = true;
  for (int i = 2; i < 8; ++i) straight &= sources[i] != kNone;
  for (int i = 1; i < 8; ++i)
    for (int k = 0; k < i; ++k) straight &= sources[i] != sources[k];
  if (straight) [[likely]]
    step.row(regular, sources);
  else
    butterfly_reflected_row(step, row, a0, a1, first, second);
}

/// The terms of an extraordinary endpoint x (interior, valence K != 6): 3/4 on x and s_i
/// (butterfly_ring_weights(K)) on its ring, ring[0] at the edge's other endpoint, in face order
/// (Zorin, Schroeder, Sweldens 1996); `share` 1/2 each where both endpoints are extraordinary.
void butterfly_extraordinary_terms(RowBuilder& row, std::uint32_t x, std::span<const std::uint32_t> ring, double share,
                                   const std::vector<double>& s) {
  row.add(x, share * 0.75);
  for (std::size_t i = 0; i < ring.size(); ++i) row.add(ring[i], share * s[i]);
}

/// The rows of predict(t, Scheme::butterfly) for edges [begin, end), read off t: a boundary edge
/// by the 4-point rule, an edge with an extraordinary endpoint by the ring rule, any other by
/// butterfly_regular_row.
void butterfly_rows(StepWriter& step, const TriangleTopology& t, const ButterflyVertices& vertices, std::uint32_t begin,
                    std::uint32_t end) {
  const std::uint32_t regular = butterfly_regular_pattern(step);
  RowBuilder row;
  std::vector<std::uint32_t> ring;
  for (std::uint32_t e = begin; e < end; ++e) {
    const std::uint32_t a0 = t.edge_vertices[2 * e], a1 = t.edge_vertices[2 * e + 1];
    if (t.is_boundary_edge(e)) [[unlikely]] {
      butterfly_boundary_row(step, row, a0, a1, boundary_neighbour(t, vertices.edges(), a0, a1),
                             boundary_neighbour(t, vertices.edges(), a1, a0));
      continue;
    }
    if (vertices.irregular(a0) || vertices.irregular(a1)) [[unlikely]] {
      const double share = vertices.irregular(a0) && vertices.irregular(a1) ? 0.5 : 1.0;
      for (const std::uint32_t x : {a0, a1}) {
        if (!vertices.irregular(x)) continue;
        const unsigned K = vertices.valence(x);
        ordered_ring(t, x, x == a0 ? a1 : a0, e, K, ring);
        butterfly_extraordinary_terms(row, x, ring, share, vertices.ring_weights(K));
      }
      step.row(row);
      row.clear();
      continue;
    }
    ButterflySide sides[2];
    for (std::uint32_t side = 0; side < 2; ++side) {
      // Face f has e as its edge i, corners c_i -> c_{i+1}: (a0, a1) on side 0, (a1, a0) on
      // side 1. Face edge i+1 joins c_{i+1} and b = c_{i+2}, face edge i+2 joins b and c_i.
      const std::uint32_t f = t.edge_faces[2 * e + side], i = edge_in_face(t, f, e);
      const std::uint32_t next = 3 * f + (i + 1) % 3, previous = 3 * f + (i + 2) % 3;
      const std::uint32_t wings[2] = {t.face_edges[side == 0 ? previous : next], t.face_edges[side == 0 ? next : previous]};
      std::uint32_t tips[2];
      for (std::uint32_t k = 0; k < 2; ++k) {
        const std::uint32_t across = other_face(t, wings[k], f);
        tips[k] = across == kNone ? kNone : opposite(t, across, wings[k]);
      }
      sides[side] = {t.triangles[previous], tips[0], tips[1]};
    }
    butterfly_regular_row(step, regular, row, a0, a1, sides[0], sides[1]);
  }
}

/// The rows of predict(t, Scheme::linear) for edges [begin, end): odd = (a + b) / 2.
void linear_rows(StepWriter& step, const TriangleTopology& t, std::uint32_t begin, std::uint32_t end) {
  const double midpoint[] = {0.5, 0.5};
  const std::uint32_t pattern = step.pattern(1.0, midpoint);
  for (std::uint32_t e = begin; e < end; ++e) step.row(pattern, {t.edge_vertices[2 * e], t.edge_vertices[2 * e + 1]});
}

/// Loop's interior edge row (a, b, c, d) with weights 3/8, 3/8, 1/8, 1/8; c == d (both faces of
/// the edge share their third vertex, a two-face "pillow") merges into one source of weight 1/4.
template <class Step>
[[gnu::noinline]] void merged_row(Step& step, const std::uint32_t (&sources)[4], const double* weights) {
  RowBuilder row;
  for (int k = 0; k < 4; ++k) row.add(sources[k], weights[k]);
  step.row(row);
}
template <class Step>
inline void loop_edge_row(Step& step, std::uint32_t interior, const std::uint32_t (&sources)[4], const double* weights) {
  if (sources[2] != sources[3]) [[likely]]
    step.row(interior, sources);
  else
    merged_row(step, sources, weights);
}

}  // namespace

namespace {

/// Expected index entries per predict row (exact for closed meshes but for butterfly's
/// extraordinary rows, which the writer grows for).
std::size_t predict_arity(Scheme scheme) { return scheme == Scheme::butterfly ? 8u : scheme == Scheme::loop ? 4u : 2u; }

}  // namespace

LiftingStep predict(const TriangleTopology& t, Scheme scheme) {
  const auto E = static_cast<std::uint32_t>(t.edge_count());
  StepWriter step(t.vertex_count, predict_arity(scheme) * E);
  // odd = (a + b) / 2: linear everywhere, and Loop on a boundary edge (cubic B-spline midpoint rule).
  const double midpoint[] = {0.5, 0.5};
  // Loop on an interior edge: odd = 3/8 (a + b) + 1/8 (c + d), c, d the wing vertices.
  const double loop_interior[] = {3.0 / 8, 3.0 / 8, 1.0 / 8, 1.0 / 8};
  switch (scheme) {
    case Scheme::linear:
      linear_rows(step, t, 0, E);
      break;
    case Scheme::butterfly: {
      ButterflyVertices vertices(t);
      butterfly_rows(step, t, vertices, 0, E);
      break;
    }
    case Scheme::loop: {
      const std::uint32_t boundary = step.pattern(1.0, midpoint), interior = step.pattern(1.0, loop_interior);
      for (std::uint32_t e = 0; e < E; ++e) {
        const std::uint32_t a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
        if (t.is_boundary_edge(e))
          step.row(boundary, {a, b});
        else
          loop_edge_row(step, interior, {a, b, opposite(t, t.edge_faces[2 * e], e), opposite(t, t.edge_faces[2 * e + 1], e)},
                        loop_interior);
      }
      break;
    }
  }
  return step.finish();
}

void predict_blocks(const TriangleTopology& t, Scheme scheme, std::uint32_t block_rows,
                    const std::function<void(const LiftingStep&)>& apply) {
  if (scheme == Scheme::loop) throw std::invalid_argument("predict_blocks: linear or butterfly only");
  const auto E = static_cast<std::uint32_t>(t.edge_count());
  std::optional<ButterflyVertices> vertices;
  if (scheme == Scheme::butterfly) vertices.emplace(t);
  std::vector<std::uint32_t> buffer;
  for (std::uint32_t begin = 0; begin < E; begin += block_rows) {
    const std::uint32_t end = begin + std::min(block_rows, E - begin);
    StepWriter step(t.vertex_count + begin, predict_arity(scheme) * (end - begin), std::move(buffer));
    if (vertices)
      butterfly_rows(step, t, *vertices, begin, end);
    else
      linear_rows(step, t, begin, end);
    LiftingStep block = step.finish();
    apply(block);
    buffer = std::move(block.indices);
  }
}

LiftingStep loop_update(const TriangleTopology& t) {
  // Each vertex lists at most its valence: at most 2E sources (exactly, on a closed mesh).
  StepWriter step(0, 2 * t.edge_count());
  LoopUpdatePatterns pattern(step);
  append_vertex_rows(
      step, t, t.vertex_count, true, [V = t.vertex_count](std::uint32_t e, std::uint32_t) { return V + e; },
      [&](std::uint32_t, std::uint32_t n, bool on_boundary) { return pattern(n, on_boundary); });
  return step.finish();
}

// The refined level's rows read off the coarse level by the 1:4 rule of TriangleTopology::refined()
// (coarse edge e = (a, b) with odd vertex m = V + e becomes halves 2e = (a, m) and 2e+1 = (m, b);
// coarse face f with corners c_i, face edges e_i (c_i -> c_{i+1}) and m_i = V + e_i becomes corner
// faces (c_i, m_i, m_{i+2}) and the centre (m_0, m_1, m_2); inner edge 2E + 3f + i runs
// m_{i+2} -> m_{i+1}). Each fine edge's wings are then known without searching fine faces.

namespace {

/// Rows of loop_predict_refined for the halves of coarse edges [begin, end) (2 rows each), to a
/// StepWriter or a sink that takes rows as it does.
template <class Step>
void loop_predict_halves(Step& step, const TriangleTopology& coarse, std::uint32_t begin, std::uint32_t end) {
  const double midpoint[] = {0.5, 0.5}, loop_interior[] = {3.0 / 8, 3.0 / 8, 1.0 / 8, 1.0 / 8};
  const std::uint32_t boundary = step.pattern(1.0, midpoint), interior = step.pattern(1.0, loop_interior);
  loop_halves(
      coarse, begin, end,
      [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
        loop_edge_row(step, interior, {a, b, c, d}, loop_interior);
      },
      [&](std::uint32_t a, std::uint32_t b) { step.row(boundary, {a, b}); });
}

/// Rows of loop_predict_refined for the inner edges of coarse faces [begin, end) (3 rows each).
template <class Step>
void loop_predict_inner(Step& step, const TriangleTopology& coarse, std::uint32_t begin, std::uint32_t end) {
  const double loop_interior[] = {3.0 / 8, 3.0 / 8, 1.0 / 8, 1.0 / 8};
  const std::uint32_t interior = step.pattern(1.0, loop_interior);
  loop_inner(coarse, begin, end,
             [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) { step.row(interior, {a, b, c, d}); });
}

/// Rows of loop_update_refined for the odd vertices V + e of coarse edges [begin, end).
void loop_update_odd(StepWriter& step, LoopUpdatePatterns& pattern, const TriangleTopology& coarse, std::uint32_t fine_V,
                     std::uint32_t begin, std::uint32_t end) {
  const auto E = static_cast<std::uint32_t>(coarse.edge_count());
  // Odd vertex m = V + e: the halves 2e, 2e+1, then in each face of e (lower index first) the two
  // inner edges at m, those not parallel to e (i+1 and i+2 if e is its edge i), in ascending
  // order; on the boundary only the two halves.
  const std::uint32_t regular = pattern(6, false), boundary = pattern(2, true);
  for (std::uint32_t e = begin; e < end; ++e) {
    const std::uint32_t h = fine_V + 2 * e;
    std::uint32_t f0 = coarse.edge_faces[2 * e], f1 = coarse.edge_faces[2 * e + 1];
    if (f1 == kNone) {
      step.row(boundary, {h, h + 1});
      continue;
    }
    if (f1 < f0) std::swap(f0, f1);
    const std::uint32_t i0 = edge_in_face(coarse, f0, e), i1 = edge_in_face(coarse, f1, e);
    const std::uint32_t inner0 = fine_V + 2 * E + 3 * f0, inner1 = fine_V + 2 * E + 3 * f1;
    step.row(regular, {h, h + 1, inner0 + (i0 == 0 ? 1 : 0), inner0 + (i0 == 2 ? 1 : 2), inner1 + (i1 == 0 ? 1 : 0),
                       inner1 + (i1 == 2 ? 1 : 2)});
  }
}

/// Rows of loop_update_refined for the coarse vertices (the first V rows).
void loop_update_even(StepWriter& step, LoopUpdatePatterns& pattern, const TriangleTopology& coarse, std::uint32_t fine_V) {
  // Even vertices keep their valence and boundary; their fine edges are the halves at them of
  // their coarse edges (2e at a, 2e+1 at b), in the same order.
  append_vertex_rows(
      step, coarse, coarse.vertex_count, true, [fine_V](std::uint32_t e, std::uint32_t k) { return fine_V + 2 * e + k; },
      [&](std::uint32_t, std::uint32_t n, bool on_boundary) { return pattern(n, on_boundary); });
}

/// Rows of items [first, last) (`rows_per_item` consecutive rows each, at most `arity` sources per
/// row; item 0's first target `first_target`), written by write(step, begin, end) a block of about
/// `block_rows` rows at a time into `buffer` and handed to `apply`.
template <class Write>
void in_blocks(std::uint32_t first_target, std::uint32_t first, std::uint32_t last, std::uint32_t rows_per_item,
               std::uint32_t arity, std::uint32_t block_rows, std::vector<std::uint32_t>& buffer,
               const std::function<void(const LiftingStep&)>& apply, Write&& write) {
  const std::uint32_t items = std::max<std::uint32_t>(1, block_rows / rows_per_item);
  for (std::uint32_t begin = first; begin < last; begin += items) {
    const std::uint32_t end = begin + std::min(items, last - begin);
    StepWriter step(first_target + rows_per_item * begin, std::size_t{arity} * rows_per_item * (end - begin), std::move(buffer));
    write(step, begin, end);
    LiftingStep block = step.finish();
    apply(block);
    buffer = std::move(block.indices);
  }
}

/// What every row of butterfly's refined level (ButterflyRefinedRows) reads of the coarse one,
/// built once and then only read: rows may be written off it on two threads, each with its own
/// ButterflyRefinedRows.
struct ButterflyRefinedLevel {
  explicit ButterflyRefinedLevel(const TriangleTopology& coarse) : t(coarse), vertices(coarse), V(coarse.vertex_count) {
    // The tips across each face's edges, looked up once per face rather than once per row that
    // reads them (four rows each).
    const std::size_t F = coarse.face_count();
    assign_large(across, 6 * F);
    for (std::uint32_t f = 0; f < F; ++f)
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t e = coarse.face_edges[3 * f + k], g = other_face(coarse, e, f);
        std::uint32_t* out = &across[6 * std::size_t{f} + 2 * k];
        for (std::uint32_t s = 0; s < 2; ++s)
          out[s] = g == kNone ? kNone : V + other_edge_at(coarse, g, e, coarse.triangles[3 * f + (k + s) % 3]);
      }
  }

  const TriangleTopology& t;
  ButterflyVertices vertices;
  std::uint32_t V;
  // across[6f + 2k + s]: the midpoint of the other edge, at corner c_{k+s} of face f, of the face
  // across f's edge k (kNone on the boundary): the tip across a wing that is the half of edge k
  // at c_{k+s}.
  std::vector<std::uint32_t> across;
};

/// The rows of predict(coarse.refined(), Scheme::butterfly), read off the coarse level by the 1:4
/// rule (see loop_halves and loop_inner in stencils.h for how refined() numbers and orients the
/// fine edges and faces): for each fine edge its endpoints a0, a1, and on each side (its first
/// face, then its second) the vertex b opposite it and the tips across the two wings, at a0 then
/// at a1, as butterfly_rows gathers them, handed to the same rules. A wing that is an inner edge
/// has a centre or corner face across, whose third vertex is known; a wing that is the half of a
/// coarse edge e' at corner x has across it the corner face at x of the coarse face on the other
/// side of e', whose third vertex is the midpoint of that face's other edge at x. What the rules
/// read of the fine level (valences, rings, boundary neighbours) comes from the coarse level: a
/// coarse vertex keeps its valence and boundary, an odd vertex has valence 6, or 4 on the
/// boundary, and is never extraordinary.
class ButterflyRefinedRows {
 public:
  explicit ButterflyRefinedRows(const ButterflyRefinedLevel& level)
      : t_(level.t), vertices_(level.vertices), V_(level.V), across_(level.across) {}

  /// The rows of the halves of coarse edges [begin, end): (a, m) then (m, b) for each.
  template <class Step>
  void halves(Step& step, std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t regular = butterfly_regular_pattern(step);
    for (std::uint32_t e = begin; e < end; ++e) {
      const std::uint32_t a = t_.edge_vertices[2 * e], b = t_.edge_vertices[2 * e + 1], m = V_ + e;
      const std::uint32_t f0 = t_.edge_faces[2 * e], f1 = t_.edge_faces[2 * e + 1];
      if (f1 == kNone) {
        // Fine boundary edges. The boundary neighbour of the coarse vertex beyond the half is the
        // midpoint of its other coarse boundary edge; that of m is the far endpoint.
        butterfly_boundary_row(step, row_, a, m, V_ + other_boundary_edge(a, e), b);
        butterfly_boundary_row(step, row_, m, b, a, V_ + other_boundary_edge(b, e));
        continue;
      }
      // f0 runs e as a -> b (its edge i0), f1 as b -> a (its edge i1); m_k below is the
      // midpoint of a face's edge k.
      const std::uint32_t i0 = edge_in_face(t_, f0, e), i1 = edge_in_face(t_, f1, e);
      const std::uint32_t* fe0 = &t_.face_edges[3 * f0];
      const std::uint32_t* fe1 = &t_.face_edges[3 * f1];
      const std::uint32_t e0_next = fe0[(i0 + 1) % 3], e0_previous = fe0[(i0 + 2) % 3];
      const std::uint32_t e1_next = fe1[(i1 + 1) % 3], e1_previous = fe1[(i1 + 2) % 3];
      const std::uint32_t* across0 = &across_[6 * std::size_t{f0}];
      const std::uint32_t* across1 = &across_[6 * std::size_t{f1}];
      // (a, m): first face f0's corner face at a (a, m, m_{i0+2}), second f1's corner face at a
      // (a, m_{i1+1}, m). The wings at m are inner edges with the centre faces across. (a is the
      // end of f0's edge i0 + 2 and the start of f1's edge i1 + 1.)
      row(step, regular, e, a, m, {V_ + e0_previous, across0[2 * ((i0 + 2) % 3) + 1], V_ + e0_next},
          {V_ + e1_next, across1[2 * ((i1 + 1) % 3)], V_ + e1_previous});
      // (m, b): first f0's corner face at b (b, m_{i0+1}, m), second f1's (b, m, m_{i1+2}). (b is
      // the start of f0's edge i0 + 1 and the end of f1's edge i1 + 2.)
      row(step, regular, e, m, b, {V_ + e0_next, V_ + e0_previous, across0[2 * ((i0 + 1) % 3)]},
          {V_ + e1_previous, V_ + e1_next, across1[2 * ((i1 + 2) % 3) + 1]});
    }
  }

  /// The rows of the inner edges of coarse faces [begin, end): inner edge i, m_{i+2} -> m_{i+1},
  /// has first the corner face at c_{i+2} (b = c_{i+2}, wings the halves at c_{i+2} of edges i+2
  /// and i+1), second the centre face (b = m_i, the corner faces at c_i and c_{i+1} across).
  template <class Step>
  void inner(Step& step, std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t regular = butterfly_regular_pattern(step);
    for (std::uint32_t f = begin; f < end; ++f) {
      const std::uint32_t* c = &t_.triangles[3 * f];
      const std::uint32_t* fe = &t_.face_edges[3 * f];
      const std::uint32_t* across = &across_[6 * std::size_t{f}];
      for (std::uint32_t i = 0; i < 3; ++i) {
        // c_{i+2} is the start of edge i+2 and the end of edge i+1.
        const std::uint32_t next = (i + 1) % 3, previous = (i + 2) % 3;
        row(step, regular, kNone, V_ + fe[previous], V_ + fe[next], {c[previous], across[2 * previous], across[2 * next + 1]},
            {V_ + fe[i], c[i], c[next]});
      }
    }
  }

 private:
  /// The boundary edge at coarse vertex v other than e.
  std::uint32_t other_boundary_edge(std::uint32_t v, std::uint32_t e) const {
    const VertexEdges& ve = vertices_.edges();
    for (std::uint32_t k = ve.offsets[v]; k < ve.offsets[v + 1]; ++k) {
      const std::uint32_t candidate = ve.edges[k];
      if (candidate != e && t_.is_boundary_edge(candidate)) return candidate;
    }
    // build() refuses a pinched vertex, so a boundary vertex has two boundary edges.
    throw std::logic_error("butterfly rows: boundary vertex " + std::to_string(v) + " has one boundary edge");
  }

  /// Whether fine vertex v is extraordinary (only coarse vertices can be).
  bool irregular(std::uint32_t v) const { return v < V_ && vertices_.irregular(v); }

  /// The row of interior fine edge (a0, a1), a half of coarse edge `e` or an inner edge (e kNone).
  template <class Step>
  [[gnu::always_inline]] void row(Step& step, std::uint32_t regular, std::uint32_t e, std::uint32_t a0,
                                  std::uint32_t a1, const ButterflySide& first, const ButterflySide& second) {
    if (irregular(a0) || irregular(a1)) [[unlikely]]
      extraordinary_row(step, e, irregular(a0) ? a0 : a1);
    else
      butterfly_regular_row(step, regular, row_, a0, a1, first, second);
  }

  /// A half of coarse edge e at its extraordinary endpoint x (the other endpoint, m = V + e, never
  /// is): x's fine ring is the midpoints of its coarse edges in face order from e through e's
  /// first face, as ordered_ring walks the fine corner faces at x.
  template <class Step>
  [[gnu::noinline]] void extraordinary_row(Step& step, std::uint32_t e, std::uint32_t x) {
    const unsigned K = vertices_.valence(x);
    ring_.clear();
    for (std::uint32_t edge = e, f = t_.edge_faces[2 * e]; ring_.size() < K;) {
      ring_.push_back(V_ + edge);
      edge = other_edge_at(t_, f, edge, x);
      f = other_face(t_, edge, f);
    }
    butterfly_extraordinary_terms(row_, x, ring_, 1.0, vertices_.ring_weights(K));
    step.row(row_);
    row_.clear();
  }

  const TriangleTopology& t_;
  const ButterflyVertices& vertices_;
  std::uint32_t V_;
  const std::vector<std::uint32_t>& across_;  // ButterflyRefinedLevel::across
  RowBuilder row_;
  std::vector<std::uint32_t> ring_;
};

/// The rows of predict(coarse.refined(), Scheme::linear), odd = (a + b) / 2, read off the coarse
/// level as ButterflyRefinedRows reads butterfly's.
struct LinearRefinedRows {
  const TriangleTopology& coarse;

  template <class Step>
  void halves(Step& step, std::uint32_t begin, std::uint32_t end) const {
    const std::uint32_t pattern = midpoint_pattern(step);
    for (std::uint32_t e = begin; e < end; ++e) {
      const std::uint32_t m = coarse.vertex_count + e;
      step.row(pattern, {coarse.edge_vertices[2 * e], m});
      step.row(pattern, {m, coarse.edge_vertices[2 * e + 1]});
    }
  }
  template <class Step>
  void inner(Step& step, std::uint32_t begin, std::uint32_t end) const {
    const std::uint32_t pattern = midpoint_pattern(step);
    const std::uint32_t V = coarse.vertex_count;
    for (std::uint32_t f = begin; f < end; ++f)
      for (std::uint32_t i = 0; i < 3; ++i)
        step.row(pattern, {V + coarse.face_edges[3 * f + (i + 2) % 3], V + coarse.face_edges[3 * f + (i + 1) % 3]});
  }
  template <class Step>
  static std::uint32_t midpoint_pattern(Step& step) {
    const double midpoint[] = {0.5, 0.5};
    return step.pattern(1.0, midpoint);
  }
};

}  // namespace

/// What every refined row reads of the coarse level: for butterfly its ButterflyRefinedLevel,
/// built once and then only read (rows may be written off it on two threads, each with a reader
/// of its own).
struct RefinedPredictRows::Shared {
  const TriangleTopology& coarse;
  Scheme scheme;
  std::optional<ButterflyRefinedLevel> butterfly;  ///< for Scheme::butterfly
};

namespace {

/// Calls use(make_rows) with a maker of readers of the refined rows `shared` prepares:
/// make_rows() gives a reader of its own, for one thread, over what all share.
template <class Use>
void with_refined_rows(const RefinedPredictRows::Shared& shared, Use&& use) {
  if (shared.butterfly)
    use([&] { return ButterflyRefinedRows(*shared.butterfly); });
  else
    use([&] { return LinearRefinedRows{shared.coarse}; });
}

/// The patterns a rule registers with the row sinks below (butterfly's regular row, the
/// midpoint), as StepWriter::pattern() would: found by value, else added.
class RowPatterns {
 public:
  std::uint32_t pattern(double scale, std::span<const double> weights) {
    for (std::uint32_t p = 0; p < patterns_.size(); ++p)
      if (patterns_[p].scale == scale && std::equal(weights.begin(), weights.end(), patterns_[p].weights.begin(),
                                                    patterns_[p].weights.end()))
        return p;
    patterns_.push_back({scale, {weights.begin(), weights.end()}});
    return static_cast<std::uint32_t>(patterns_.size() - 1);
  }

 protected:
  struct Pattern {
    double scale;
    std::vector<double> weights;
  };
  std::vector<Pattern> patterns_;
};

/// Takes rows as StepWriter takes them (the rules above write to either) and applies each at once
/// to x (`channels` values per vertex; C of them where C > 0), exactly as lifting.cpp computes a
/// table row: in synthesis (synthesize_run) the target times the row's scale first, then each
/// source times its weight in row order; in analysis, the inverse (analyze_run), the sources
/// times their weights summed from zero in row order, that sum subtracted from the target, the
/// difference divided by the row's scale. The rows' targets are consecutive from the one seek()
/// names.
template <bool Synthesis, int C>
class AppliedRows : public RowPatterns {
 public:
  AppliedRows(double* x, int channels) : x_(x), n_(C > 0 ? C : channels) {}
  void seek(std::uint32_t target) { target_ = x_ + std::size_t{target} * static_cast<std::size_t>(n_); }
  template <std::size_t N>
  void row(std::uint32_t pattern, const std::uint32_t (&sources)[N]) {
    apply(patterns_[pattern].scale, patterns_[pattern].weights.data(), sources, N);
  }
  void row(const RowBuilder& builder, double scale = 1.0) {
    apply(scale, builder.weights().data(), builder.sources().data(), builder.sources().size());
  }

 private:
  [[gnu::always_inline]] void apply(double scale, const double* w, const std::uint32_t* sources, std::size_t arity) {
    const int n = C > 0 ? C : n_;
    double acc[C > 0 ? C : 64];
    for (int c = 0; c < n; ++c) acc[c] = Synthesis ? scale * target_[c] : 0.0;
    for (std::size_t k = 0; k < arity; ++k) {
      const double* source = x_ + std::size_t{sources[k]} * static_cast<std::size_t>(n);
      for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
    }
    for (int c = 0; c < n; ++c) target_[c] = Synthesis ? acc[c] : (target_[c] - acc[c]) / scale;
    target_ += n;
  }

  double* x_;
  double* target_ = nullptr;
  int n_;
};
template <int C>
using SynthesisRows = AppliedRows<true, C>;
template <int C>
using AnalysisRows = AppliedRows<false, C>;

/// Takes rows as StepWriter takes them and keeps them (scale, sources, weights), for a caller that
/// reads a few rows one at a time (LevelRows).
class CapturedRows : public RowPatterns {
 public:
  template <std::size_t N>
  void row(std::uint32_t pattern, const std::uint32_t (&sources)[N]) {
    add(patterns_[pattern].scale, patterns_[pattern].weights.data(), sources, N);
  }
  void row(const RowBuilder& builder, double scale = 1.0) {
    add(scale, builder.weights().data(), builder.sources().data(), builder.sources().size());
  }
  void clear() {
    rows_.clear();
    sources_.clear();
    weights_.clear();
  }
  LevelRows::Row operator[](std::size_t i) const {
    const Kept& r = rows_[i];
    return {r.scale, std::span(sources_).subspan(r.first, r.arity), std::span(weights_).subspan(r.first, r.arity)};
  }

 private:
  void add(double scale, const double* w, const std::uint32_t* sources, std::size_t arity) {
    rows_.push_back({scale, sources_.size(), arity});
    sources_.insert(sources_.end(), sources, sources + arity);
    weights_.insert(weights_.end(), w, w + arity);
  }
  struct Kept {
    double scale;
    std::size_t first, arity;
  };
  std::vector<Kept> rows_;
  std::vector<std::uint32_t> sources_;
  std::vector<double> weights_;
};

/// Takes rows as StepWriter takes them and adds each source's weight to its column sum, row
/// after row and in row order, as add_column_sums() reads a table's.
/// With `only` given, only the sources it marks get their weights.
class ColumnSumRows : public RowPatterns {
 public:
  explicit ColumnSumRows(std::span<double> column_sum, const std::uint8_t* only = nullptr)
      : sum_(column_sum), only_(only) {}
  template <std::size_t N>
  void row(std::uint32_t pattern, const std::uint32_t (&sources)[N]) {
    add(patterns_[pattern].weights.data(), sources, N);
  }
  void row(const RowBuilder& builder, double = 1.0) {
    add(builder.weights().data(), builder.sources().data(), builder.sources().size());
  }

 private:
  void add(const double* w, const std::uint32_t* sources, std::size_t arity) {
    for (std::size_t k = 0; k < arity; ++k)
      if (only_ == nullptr || only_[sources[k]]) sum_[sources[k]] += w[k];
  }
  std::span<double> sum_;
  const std::uint8_t* only_;
};

}  // namespace

LiftingStep loop_predict_refined(const TriangleTopology& coarse, const TriangleTopology& fine) {
  StepWriter step(fine.vertex_count, 4 * fine.edge_count());
  loop_predict_halves(step, coarse, 0, static_cast<std::uint32_t>(coarse.edge_count()));
  loop_predict_inner(step, coarse, 0, static_cast<std::uint32_t>(coarse.face_count()));
  return step.finish();
}

LiftingStep loop_update_refined(const TriangleTopology& coarse, const TriangleTopology& fine) {
  StepWriter step(0, 2 * fine.edge_count());
  LoopUpdatePatterns pattern(step);
  loop_update_even(step, pattern, coarse, fine.vertex_count);
  loop_update_odd(step, pattern, coarse, fine.vertex_count, 0, static_cast<std::uint32_t>(coarse.edge_count()));
  return step.finish();
}

RefinedPredictRows::RefinedPredictRows(const TriangleTopology& coarse, Scheme scheme) {
  if (scheme == Scheme::loop) throw std::invalid_argument("refined predict rows: linear or butterfly only");
  auto shared = std::make_unique<Shared>(Shared{coarse, scheme, std::nullopt});
  if (scheme == Scheme::butterfly) shared->butterfly.emplace(coarse);
  shared_ = std::move(shared);
}

RefinedPredictRows::~RefinedPredictRows() = default;
RefinedPredictRows::RefinedPredictRows(RefinedPredictRows&&) noexcept = default;
RefinedPredictRows& RefinedPredictRows::operator=(RefinedPredictRows&&) noexcept = default;

LiftingStep RefinedPredictRows::step() const {
  const TriangleTopology& coarse = shared_->coarse;
  const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
  StepWriter step(coarse.vertex_count + E, predict_arity(shared_->scheme) * (2 * std::size_t{E} + 3 * std::size_t{F}));
  with_refined_rows(*shared_, [&](auto make_rows) {
    auto rows = make_rows();
    rows.halves(step, 0, E);
    rows.inner(step, 0, F);
  });
  return step.finish();
}

LiftingStep refined_predict(const TriangleTopology& coarse, Scheme scheme) { return RefinedPredictRows(coarse, scheme).step(); }

namespace {

/// The refined rows of `shared` applied to x through Sink<C> (SynthesisRows or AnalysisRows): the
/// halves of the coarse edges, then the inner edges of the coarse faces, a chunk of about
/// `block_rows` rows at a time, each chunk's targets handed to before_odd first; with
/// `concurrent` the second half of the edges and of the faces on a thread of their own.
template <template <int> class Sink>
void apply_refined_rows(const RefinedPredictRows::Shared& shared, std::uint32_t block_rows, double* x, int channels,
                        const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, bool concurrent) {
  const TriangleTopology& coarse = shared.coarse;
  const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
  const std::uint32_t first_odd = coarse.vertex_count + E;
  with_refined_rows(shared, [&](auto make_rows) {
    // The halves of coarse edges [e0, e1), then the inner edges of coarse faces [f0, f1), a
    // chunk of about block_rows rows at a time, each chunk's targets handed to before_odd first.
    auto part = [&](std::uint32_t e0, std::uint32_t e1, std::uint32_t f0, std::uint32_t f1) {
      auto rows = make_rows();
      auto run = [&]<int C>() {
        Sink<C> sink(x, channels);
        auto chunks = [&](std::uint32_t first, std::uint32_t last, std::uint32_t rows_per_item, std::uint32_t first_target,
                          auto&& write) {
          const std::uint32_t items = std::max<std::uint32_t>(1, block_rows / rows_per_item);
          for (std::uint32_t begin = first; begin < last; begin += items) {
            const std::uint32_t end = begin + std::min(items, last - begin);
            if (before_odd) before_odd(first_target + rows_per_item * begin, rows_per_item * (end - begin));
            sink.seek(first_target + rows_per_item * begin);
            write(begin, end);
          }
        };
        chunks(e0, e1, 2, first_odd, [&](std::uint32_t begin, std::uint32_t end) { rows.halves(sink, begin, end); });
        chunks(f0, f1, 3, first_odd + 2 * E, [&](std::uint32_t begin, std::uint32_t end) { rows.inner(sink, begin, end); });
      };
      if (channels == 3)
        run.template operator()<3>();
      else if (channels == 1)
        run.template operator()<1>();
      else
        run.template operator()<0>();
    };
    in_halves(concurrent, E, F, part);
  });
}

}  // namespace

void RefinedPredictRows::synthesize(std::uint32_t block_rows, double* x, int channels,
                                    const std::function<void(std::uint32_t, std::uint32_t)>& before_odd,
                                    bool concurrent) const {
  apply_refined_rows<SynthesisRows>(*shared_, block_rows, x, channels, before_odd, concurrent);
}

void RefinedPredictRows::analyze(std::uint32_t block_rows, double* x, int channels, bool concurrent) const {
  apply_refined_rows<AnalysisRows>(*shared_, block_rows, x, channels, {}, concurrent);
}

void RefinedPredictRows::add_column_sums(std::span<double> column_sum) const {
  const TriangleTopology& coarse = shared_->coarse;
  const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
  if (!shared_->butterfly) {  // linear: two sources a row, nothing to save
    LinearRefinedRows rows{coarse};
    ColumnSumRows sink(column_sum);
    rows.halves(sink, 0, E);
    rows.inner(sink, 0, F);
    return;
  }
  // Butterfly's column sum at a fine vertex whose fine 2-ring holds no extraordinary and no
  // boundary vertex is exactly 3: it is a0 or a1 of its 6 edges' rows (1/2 each), b of the 6 edges
  // facing it (1/8) and a tip of 12 (-1/16), every row the regular one (butterfly_regular_row; a
  // row whose sources repeat merges the same weights), and sums of these dyadic weights are exact
  // in any order. So only the vertices near an irregular coarse vertex (extraordinary or on the
  // boundary; the fine level adds none: its new vertices have valence 6, or 4 on the boundary,
  // next to a boundary coarse vertex) are summed from rows, and from every row that holds them, in
  // row order: the table's bits. By coarse distance d to the nearest irregular coarse vertex
  // (a fine 2-ring reaches one coarse edge): a coarse vertex with d <= kSummed and a midpoint with
  // an endpoint there are summed, from the rows of the coarse edges and faces with a corner at
  // d <= kSummed + 2 (a row's sources lie within one fine 2-ring, one coarse edge, of its edge).
  const ButterflyVertices& vertices = shared_->butterfly->vertices;
  const std::uint32_t V = coarse.vertex_count;
  constexpr std::uint8_t kSummed = 2, kRowsReach = kSummed + 2, kFar = 255;
  std::vector<std::uint8_t> distance(V, kFar);
  for (std::uint32_t v = 0; v < V; ++v)
    if (vertices.irregular(v) || vertices.on_boundary(v)) distance[v] = 0;
  for (std::uint8_t d = 0; d < kRowsReach; ++d)
    for (std::uint32_t e = 0; e < E; ++e) {
      const std::uint32_t a = coarse.edge_vertices[2 * std::size_t{e}], b = coarse.edge_vertices[2 * std::size_t{e} + 1];
      if (distance[a] == d && distance[b] == kFar) distance[b] = static_cast<std::uint8_t>(d + 1);
      if (distance[b] == d && distance[a] == kFar) distance[a] = static_cast<std::uint8_t>(d + 1);
    }
  auto edge_distance = [&](std::uint32_t e) {
    return std::min(distance[coarse.edge_vertices[2 * std::size_t{e}]], distance[coarse.edge_vertices[2 * std::size_t{e} + 1]]);
  };
  std::vector<std::uint8_t> summed(std::size_t{V} + E, 0);
  for (std::uint32_t v = 0; v < V; ++v) summed[v] = distance[v] <= kSummed;
  for (std::uint32_t e = 0; e < E; ++e) summed[V + e] = edge_distance(e) <= kSummed;
  for (std::size_t v = 0; v < summed.size(); ++v)
    if (!summed[v]) column_sum[v] += 3.0;
  ButterflyRefinedRows rows(*shared_->butterfly);
  ColumnSumRows sink(column_sum, summed.data());
  for (std::uint32_t e = 0; e < E; ++e)
    if (edge_distance(e) <= kRowsReach) rows.halves(sink, e, e + 1);
  for (std::uint32_t f = 0; f < F; ++f) {
    const std::uint32_t* c = &coarse.triangles[3 * std::size_t{f}];
    if (std::min({distance[c[0]], distance[c[1]], distance[c[2]]}) <= kRowsReach) rows.inner(sink, f, f + 1);
  }
}

void loop_refined_blocks(const TriangleTopology& coarse, const TriangleTopology& fine, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply) {
  loop_refined_blocks(coarse, fine.vertex_count, block_rows, apply);
}

void loop_refined_blocks(const TriangleTopology& coarse, std::uint32_t fine_vertices, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply) {
  const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
  std::vector<std::uint32_t> buffer;
  // Predict: the halves' rows, then the inner edges' (loop_predict_refined).
  in_blocks(fine_vertices, 0, E, 2, 4, block_rows, buffer, apply, [&](StepWriter& step, std::uint32_t begin, std::uint32_t end) {
    loop_predict_halves(step, coarse, begin, end);
  });
  in_blocks(fine_vertices + 2 * E, 0, F, 3, 4, block_rows, buffer, apply,
            [&](StepWriter& step, std::uint32_t begin, std::uint32_t end) { loop_predict_inner(step, coarse, begin, end); });
  loop_update_blocks(coarse, fine_vertices, block_rows, apply, std::move(buffer));
}

void loop_update_blocks(const TriangleTopology& coarse, std::uint32_t fine_vertices, std::uint32_t block_rows,
                        const std::function<void(const LiftingStep&)>& apply, std::vector<std::uint32_t> buffer,
                        bool concurrent) {
  const auto E = static_cast<std::uint32_t>(coarse.edge_count());
  // The odd vertices' rows of coarse edges [first, last).
  auto odd = [&](std::uint32_t first, std::uint32_t last, std::vector<std::uint32_t>& storage) {
    in_blocks(coarse.vertex_count, first, last, 1, 6, block_rows, storage, apply,
              [&](StepWriter& step, std::uint32_t begin, std::uint32_t end) {
                LoopUpdatePatterns pattern(step);
                loop_update_odd(step, pattern, coarse, fine_vertices, begin, end);
              });
  };
  // The coarse vertices' rows in one block (their counting sort runs over all coarse edges),
  // then the odd vertices'; on two threads, the second half of the odd vertices' beside them.
  std::vector<std::uint32_t> second_buffer;
  run_both(concurrent, [&] { if (concurrent) odd(E / 2, E, second_buffer); }, [&] {
    StepWriter step(0, 2 * std::size_t{E}, std::move(buffer));
    LoopUpdatePatterns pattern(step);
    loop_update_even(step, pattern, coarse, fine_vertices);
    LiftingStep block = step.finish();
    apply(block);
    buffer = std::move(block.indices);
    odd(0, concurrent ? E / 2 : E, buffer);
  });
}

void add_column_sums(const LiftingStep& predict, std::span<double> column_sum) {
  const std::uint32_t* source = predict.indices.data();
  for (const LiftingStep::Run& run : predict.runs) {
    const LiftingStep::Pattern& p = predict.patterns[run.pattern];
    for (std::uint32_t r = 0; r < run.rows; ++r)
      for (std::uint32_t k = 0; k < p.arity; ++k) column_sum[*source++] += predict.pattern_weights[p.first_weight + k];
  }
}

LiftingStep mean_preserving_update(const TriangleTopology& t, const LiftingStep& predict) {
  // c_l = sum over odd k of p(k, l): how much of the fine signal even vertex l predicts.
  std::vector<double> column_sum(t.vertex_count, 0.0);
  add_column_sums(predict, column_sum);
  StepWriter step(0, 2 * t.edge_count());
  std::vector<double> weights;
  append_vertex_rows(
      step, t, t.vertex_count, false, [V = t.vertex_count](std::uint32_t e, std::uint32_t) { return V + e; },
      [&](std::uint32_t v, std::uint32_t n, bool) {
        weights.assign(n, -update_weight(column_sum[v]));
        return step.pattern(1.0, weights);
      });
  return step.finish();
}

/// LevelRows' state: at the base its tables and where each row sits in them; above it what the
/// rules read (for linear and butterfly the level below, as RefinedPredictRows reads it) and the
/// rows kept by the last call.
struct LevelRows::Impl {
  Impl(const SemiRegularHierarchy& h, WaveletOptions o, int l, const LevelRows* b, std::span<const double> w)
      : options(o), below(b), update_weights(w), V(h.vertex_count(l)) {
    if (l == 0) {
      base = &h.topology(0);
      base_edges.emplace(*base);
    } else if (b == nullptr) {
      throw std::invalid_argument("LevelRows: a level above the base needs the level below");
    } else {
      coarse = &h.topology(l - 1);
    }
  }

  WaveletOptions options;
  const TriangleTopology* base = nullptr;  // at the base: its topology
  const LevelRows* below;
  const TriangleTopology* coarse = nullptr;   // above the base: the level below
  std::optional<VertexEdges> base_edges;      // at the base
  mutable std::vector<std::uint32_t> below_edges;  // incident_edges()' of the level below
  std::span<const double> update_weights;
  std::uint32_t V;
  std::vector<Step> steps;
  // The base: its tables, and per step each row's pattern and first index.
  std::optional<WaveletTransform> tables;
  std::vector<std::vector<std::uint32_t>> row_pattern;
  std::vector<std::vector<std::size_t>> row_index;
  // Linear and butterfly above the base.
  std::optional<RefinedPredictRows::Shared> refined;
  std::optional<ButterflyRefinedRows> butterfly;
  std::optional<LinearRefinedRows> linear;
  CapturedRows captured;
  // The row of the last call where it is written here.
  std::vector<std::uint32_t> sources;
  std::vector<double> weights;

  // Predict row r of a refined level: the rows of its item, the two halves of a coarse edge or the
  // three inner edges of a coarse face, written by halves(captured, e, e + 1) or
  // inner(captured, f, f + 1), and r's among them.
  template <class Halves, class Inner>
  Row refined_row(std::uint32_t r, Halves&& halves, Inner&& inner) {
    captured.clear();
    const auto E = static_cast<std::uint32_t>(coarse->edge_count());
    if (r < 2 * E) {
      halves(r / 2);
      return captured[r % 2];
    }
    inner((r - 2 * E) / 3);
    return captured[(r - 2 * E) % 3];
  }
  // Whether the level's edge e is on the boundary: above the base, a half of a boundary edge
  // of the level below (inner edges never are).
  bool is_boundary_edge(std::uint32_t e) const {
    if (base != nullptr) return base->is_boundary_edge(e);
    return e < 2 * coarse->edge_count() && coarse->is_boundary_edge(e / 2);
  }
  // v's incident edges in increasing order (all, or only its boundary edges if `boundary_only`
  // and it has some), as sources V + e: the sources of loop_update() and mean_preserving_update().
  // Returns whether v is on a boundary.
  bool vertex_sources(std::uint32_t v, bool boundary_only) {
    const bool boundary = below_edges_of(v, incident_scratch);
    sources.clear();
    for (const std::uint32_t e : incident_scratch)
      if (!(boundary_only && boundary) || is_boundary_edge(e)) sources.push_back(V + e);
    return boundary;
  }
  bool below_edges_of(std::uint32_t v, std::vector<std::uint32_t>& out) const;
  std::vector<std::uint32_t> incident_scratch;
  Row written(double scale) { return {scale, sources, weights}; }
};

bool LevelRows::Impl::below_edges_of(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (base_edges) {
    out.assign(base_edges->edges.begin() + base_edges->offsets[v], base_edges->edges.begin() + base_edges->offsets[v + 1]);
    return base_edges->boundary[v] != 0;
  }
  const std::uint32_t Vc = coarse->vertex_count;
  if (v < Vc) {
    const bool boundary = below->incident_edges(v, below_edges);
    for (const std::uint32_t e : below_edges) out.push_back(2 * e + (coarse->edge_vertices[2 * std::size_t{e}] == v ? 0 : 1));
    return boundary;
  }
  // The midpoint of coarse edge e: its halves, then in each face of e (lower index first) the
  // inner edges at it: of face f with e as its edge i, inner edges i + 1 and i + 2 (inner edge k
  // joins the midpoints of edges k + 2 and k + 1), in increasing order.
  const std::uint32_t e = v - Vc, Ec = static_cast<std::uint32_t>(coarse->edge_count());
  out.push_back(2 * e);
  out.push_back(2 * e + 1);
  std::uint32_t f0 = coarse->edge_faces[2 * std::size_t{e}], f1 = coarse->edge_faces[2 * std::size_t{e} + 1];
  if (f1 != kNone && f1 < f0) std::swap(f0, f1);
  for (const std::uint32_t f : {f0, f1}) {
    if (f == kNone) continue;
    const std::uint32_t i = edge_in_face(*coarse, f, e), inner = 2 * Ec + 3 * f;
    out.push_back(inner + (i == 0 ? 1 : 0));
    out.push_back(inner + (i == 2 ? 1 : 2));
  }
  return f1 == kNone;
}

bool LevelRows::incident_edges(std::uint32_t v, std::vector<std::uint32_t>& edges) const {
  return impl_->below_edges_of(v, edges);
}

void LevelRows::edge_ends(std::uint32_t e, std::uint32_t& a, std::uint32_t& b) const {
  const Impl& m = *impl_;
  if (m.base != nullptr) {
    a = m.base->edge_vertices[2 * std::size_t{e}];
    b = m.base->edge_vertices[2 * std::size_t{e} + 1];
  } else {
    m.coarse->refined_edge(e, a, b);
  }
}

LevelRows::LevelRows(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, const LevelRows* below,
                     std::span<const double> update_weights)
    : impl_(std::make_unique<Impl>(hierarchy, options, level, below, update_weights)) {
  Impl& m = *impl_;
  const std::uint32_t E = hierarchy.vertex_count(level + 1) - m.V;
  if (level == 0) {
    m.tables.emplace(hierarchy, options, 0, 1);
    for (const LiftingStep& step : m.tables->steps(0)) {
      m.steps.push_back({step.first_target, step.row_count});
      std::vector<std::uint32_t>& pattern = m.row_pattern.emplace_back();
      std::vector<std::size_t>& index = m.row_index.emplace_back();
      std::size_t at = 0;
      for (const LiftingStep::Run& run : step.runs)
        for (std::uint32_t r = 0; r < run.rows; ++r, at += step.patterns[run.pattern].arity) {
          pattern.push_back(run.pattern);
          index.push_back(at);
        }
    }
    return;
  }
  const Step predict{m.V, E}, update{0, m.V};
  if (options.scheme == Scheme::loop) {
    m.steps = {predict, update};
    return;
  }
  m.refined.emplace(RefinedPredictRows::Shared{hierarchy.topology(level - 1), options.scheme, std::nullopt});
  if (options.scheme == Scheme::butterfly) {
    m.refined->butterfly.emplace(m.refined->coarse);
    m.butterfly.emplace(*m.refined->butterfly);
  } else {
    m.linear.emplace(LinearRefinedRows{m.refined->coarse});
  }
  if (options.mean_preserving_update) {
    if (update_weights.size() != m.V) throw std::invalid_argument("LevelRows: the update's weights are not the level's vertices");
    m.steps = {update, predict};
  } else {
    m.steps = {predict};
  }
}

LevelRows::~LevelRows() = default;

const std::vector<LevelRows::Step>& LevelRows::steps() const { return impl_->steps; }

LevelRows::Row LevelRows::row(std::size_t step, std::uint32_t target) {
  Impl& m = *impl_;
  const std::uint32_t r = target - m.steps[step].first_target;
  if (m.tables) {
    const LiftingStep& s = m.tables->steps(0)[step];
    const LiftingStep::Pattern& p = s.patterns[m.row_pattern[step][r]];
    return {p.scale, std::span(s.indices).subspan(m.row_index[step][r], p.arity),
            std::span(s.pattern_weights).subspan(p.first_weight, p.arity)};
  }
  const bool is_predict = m.steps[step].first_target == m.V;
  if (m.options.scheme == Scheme::loop) {
    if (is_predict)  // loop_predict_refined's row, read off the level below
      return m.refined_row(
          r, [&](std::uint32_t e) { loop_predict_halves(m.captured, *m.coarse, e, e + 1); },
          [&](std::uint32_t f) { loop_predict_inner(m.captured, *m.coarse, f, f + 1); });
    // loop_update(t): the odd vertices on the target's edges (on a boundary its boundary edges'),
    // by loop_vertex_rule().
    const bool boundary = m.vertex_sources(target, true);
    const auto n = static_cast<std::uint32_t>(m.sources.size());
    const LoopVertexRule rule = loop_vertex_rule(n, boundary);
    m.weights.assign(n, rule.weight);
    return m.written(rule.scale);
  }
  if (is_predict) {
    auto halves = [&](std::uint32_t e) { m.butterfly ? m.butterfly->halves(m.captured, e, e + 1) : m.linear->halves(m.captured, e, e + 1); };
    auto inner = [&](std::uint32_t f) { m.butterfly ? m.butterfly->inner(m.captured, f, f + 1) : m.linear->inner(m.captured, f, f + 1); };
    return m.refined_row(r, halves, inner);
  }
  // mean_preserving_update(t, predict): the odd vertices on all the target's edges, each weighted
  // by its -lambda.
  m.vertex_sources(target, false);
  m.weights.assign(m.sources.size(), m.update_weights[target]);
  return m.written(1.0);
}

}  // namespace meshlift::stencils
