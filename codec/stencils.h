// Builds the lifting steps of one level (level j -> j+1) as index+weight tables, one rule per
// scheme, each formula beside the code that applies it. Internal to codec/.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "meshlift/lifting.h"
#include "meshlift/topology.h"

namespace meshlift::stencils {

/// Predict step: one row per odd vertex V_j + e (edge e of level j), sources are even vertices.
/// Synthesis adds the prediction to the stored detail: odd = detail + P(even).
LiftingStep predict(const TriangleTopology& topology, Scheme scheme);

/// The rows of predict(topology, scheme) for linear or butterfly, the same rows in the same
/// order, as consecutive blocks of `block_rows` rows (one step per block, its targets
/// consecutive), handed to `apply` one at a time in one reused buffer: applying each block as it
/// comes is the synthesis of the whole step (its rows are independent), without its table in
/// memory. \throw std::invalid_argument for Scheme::loop (loop_refined_blocks).
void predict_blocks(const TriangleTopology& topology, Scheme scheme, std::uint32_t block_rows,
                    const std::function<void(const LiftingStep&)>& apply);

/// The rows of predict(coarse.refined(), scheme) for linear or butterfly, the same rows in the
/// same order, read off the coarse level by the refinement rule (the fine level's topology is not
/// needed). What every row reads of the coarse level (butterfly: the valences, the tips across
/// each face's edges) is built once, here, for any number of the uses below (the update's column
/// sums and the predict step of one synthesis). \throw std::invalid_argument for Scheme::loop
/// (Loop's rows: loop_halves, loop_inner).
class RefinedPredictRows {
 public:
  RefinedPredictRows(const TriangleTopology& coarse, Scheme scheme);
  ~RefinedPredictRows();
  RefinedPredictRows(RefinedPredictRows&&) noexcept;
  RefinedPredictRows& operator=(RefinedPredictRows&&) noexcept;

  /// Their synthesis applied to x, `channels` values per vertex, as each row is read, with no
  /// table: each row computed as the synthesis computes its table row (lifting.cpp's
  /// synthesize_run: the target times the scale, then the sources in row order), so the same
  /// bits. The halves of the coarse edges, then the inner edges of the coarse faces, a chunk of
  /// about `block_rows` rows at a time; before_odd (if set) gets each chunk's targets (first,
  /// count) before its rows. With `concurrent`, the second half of the edges and of the faces on a
  /// thread of its own (before_odd then called from two threads at once, with disjoint targets).
  void synthesize(std::uint32_t block_rows, double* x, int channels,
                  const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, bool concurrent) const;
  /// Their analysis (the inverse, each row as lifting.cpp's analyze_run computes a table row: the
  /// sources in row order summed from zero, subtracted from the target, divided by the scale),
  /// with no table, the same chunks and halves as synthesize(): the same bits as the table's.
  void analyze(std::uint32_t block_rows, double* x, int channels, bool concurrent) const;
  /// Adds the weights of every row to `column_sum` (indexed by source vertex), as
  /// add_column_sums() adds a table's, with no table: the same bits. Butterfly's rows are read
  /// only near the extraordinary and boundary vertices: elsewhere a vertex's sum is exactly 3.
  /// \pre column_sum holds zeros for the rows' sources, the coarse level's vertices and edge
  /// midpoints (the sums of dyadic weights are exact in any order only from zero).
  void add_column_sums(std::span<double> column_sum) const;
  /// The rows as one step (a table).
  LiftingStep step() const;

  struct Shared;

 private:
  std::unique_ptr<const Shared> shared_;
};
/// The same rows as one step: RefinedPredictRows(coarse, scheme).step().
LiftingStep refined_predict(const TriangleTopology& coarse, Scheme scheme);

/// The rows of the lifting steps of level `level` -> `level` + 1 (WaveletTransform's steps(level),
/// in synthesis order) read one at a time by target, without the steps' tables (18 to 36 bytes
/// per vertex of level + 1): for a caller that visits a few rows of each level, as the encoder's
/// level weights follow an impulse's support. Each row is its table row: the same scale, the
/// same sources in the same order, the same weights. At the base they are read off its tables
/// (small); above it Loop's predict rows off the level below (loop_halves, loop_inner: the rows
/// of loop_predict_refined), its update rows off the incident edges (the rule of loop_update()),
/// linear's and butterfly's predict rows off the level below (RefinedPredictRows' rules), and
/// the mean-preserving update's off the incident edges with the weights given. Above the base
/// the level's own topology is not read (a hierarchy may leave out that of the level below its
/// finest, as the encoder's and the decoder's do).
class LevelRows {
 public:
  /// `below` is level - 1's (nullptr at the base) and must outlive this: above the base a
  /// vertex's incident edges are read off it (incident_edges()), so that no level but the base
  /// lists them (VertexEdges, ~30 bytes per vertex). `update_weights` is
  /// update_weights(hierarchy, options.scheme, level) where linear or butterfly have the
  /// mean-preserving update above the base (else not read).
  LevelRows(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, const LevelRows* below,
            std::span<const double> update_weights = {});
  ~LevelRows();
  LevelRows(const LevelRows&) = delete;
  LevelRows& operator=(const LevelRows&) = delete;

  /// A step's rows are those of targets first_target .. first_target + rows - 1.
  struct Step {
    std::uint32_t first_target = 0;
    std::uint32_t rows = 0;
  };
  const std::vector<Step>& steps() const;
  /// In synthesis x[t] = scale * x[t] + sum_k weights[k] * x[sources[k]].
  struct Row {
    double scale = 1.0;
    std::span<const std::uint32_t> sources;
    std::span<const double> weights;
  };
  /// Step `step`'s row of `target`; valid until the next call.
  Row row(std::size_t step, std::uint32_t target);
  /// The endpoints of the level's edge e (above the base read off the level below, as
  /// TriangleTopology::refined_edge gives them).
  void edge_ends(std::uint32_t e, std::uint32_t& a, std::uint32_t& b) const;
  /// The edges of the level at vertex v in increasing order, as VertexEdges lists them, into
  /// `edges` (replaced); returns whether v is on a boundary. Above the base by the 1:4 rule of
  /// TriangleTopology::refined(): a vertex of the level below has the halves at it of its edges
  /// there (2e at the first endpoint, 2e + 1 at the second); the midpoint of edge e of the level
  /// below has the halves 2e, 2e + 1, then in each face of e (the lower index first) the two
  /// inner edges at it; it is on a boundary if e is.
  bool incident_edges(std::uint32_t v, std::vector<std::uint32_t>& edges) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Loop's vertex rule written over the odd vertices (CODEC-NOTES §3): one row per even vertex,
/// synthesis even' = s_n even + w_n sum(adjacent odd); boundary even' = even/2 + (odd_l + odd_r)/4.
LiftingStep loop_update(const TriangleTopology& topology);

/// predict(fine, Scheme::loop) and loop_update(fine) for a level that is the 1:4 refinement of
/// `coarse` (fine == coarse.refined(), as in a SemiRegularHierarchy): the same rows, read off the
/// coarse level's faces by the refinement rule instead of searched for in the fine level, in
/// about a quarter of the random memory accesses.
LiftingStep loop_predict_refined(const TriangleTopology& coarse, const TriangleTopology& fine);
LiftingStep loop_update_refined(const TriangleTopology& coarse, const TriangleTopology& fine);

/// The rows of loop_predict_refined and then of loop_update_refined, the same rows in the same
/// order, as consecutive blocks of about `block_rows` rows each (one step per block, its targets
/// consecutive), handed to `apply` one at a time in one reused buffer: applying each block as it
/// comes is the synthesis of the whole steps (a step's rows are independent: targets and sources
/// are disjoint), without their tables in memory, and with each block's rows still in cache.
void loop_refined_blocks(const TriangleTopology& coarse, const TriangleTopology& fine, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply);
/// The same knowing only the fine level's vertex count (all the rows read of it), for a
/// hierarchy that does not hold the fine level's topology.
void loop_refined_blocks(const TriangleTopology& coarse, std::uint32_t fine_vertices, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply);

/// The update half of loop_refined_blocks (its blocks after the predict step's), in `buffer`'s
/// storage: for a caller that applies the predict step its own way. With `concurrent`, the second
/// half of the odd vertices' rows on a thread of its own: `apply` is then called from two threads
/// at once, with disjoint blocks (the step's rows are independent).
void loop_update_blocks(const TriangleTopology& coarse, std::uint32_t fine_vertices, std::uint32_t block_rows,
                        const std::function<void(const LiftingStep&)>& apply, std::vector<std::uint32_t> buffer = {},
                        bool concurrent = false);

/// Where edge e sits in face f: face edge i runs corner i -> i+1.
inline std::uint32_t edge_in_face(const TriangleTopology& t, std::uint32_t f, std::uint32_t e) {
  const std::uint32_t* fe = &t.face_edges[3 * f];
  return fe[0] == e ? 0 : fe[1] == e ? 1 : 2;
}

/// Loop's predict rows of a refined level read off the coarse level (the rows of
/// loop_predict_refined, in order), for a caller that applies them as they come: for the two
/// halves of each coarse edge in [begin, end), interior(a, b, c, d) for odd = 3/8 (a + b) +
/// 1/8 (c + d) (c == d across a two-face pillow), or boundary(a, b) for odd = (a + b) / 2.
/// Coarse edge e = (a, b) with odd vertex m = V + e becomes halves (a, m) and (m, b). Face f0 =
/// edge_faces[2e] runs a -> b with e its edge i0: its corner face at a opposes the half at a
/// with m_{i0+2}, its corner face at b opposes the half at b with m_{i0+1}. Face f1 runs b -> a
/// with e its edge i1: at b it opposes m_{i1+2}, at a m_{i1+1}.
template <class Interior, class Boundary>
void loop_halves(const TriangleTopology& coarse, std::uint32_t begin, std::uint32_t end, Interior&& interior,
                 Boundary&& boundary) {
  const std::uint32_t V = coarse.vertex_count;
  for (std::uint32_t e = begin; e < end; ++e) {
    const std::uint32_t a = coarse.edge_vertices[2 * e], b = coarse.edge_vertices[2 * e + 1], m = V + e;
    const std::uint32_t f0 = coarse.edge_faces[2 * e], f1 = coarse.edge_faces[2 * e + 1];
    if (f1 == kNone) {
      boundary(a, m);
      boundary(m, b);
      continue;
    }
    const std::uint32_t i0 = edge_in_face(coarse, f0, e), i1 = edge_in_face(coarse, f1, e);
    const std::uint32_t* m0 = &coarse.face_edges[3 * f0];
    const std::uint32_t* m1 = &coarse.face_edges[3 * f1];
    interior(a, m, V + m0[(i0 + 2) % 3], V + m1[(i1 + 1) % 3]);
    interior(m, b, V + m0[(i0 + 1) % 3], V + m1[(i1 + 2) % 3]);
  }
}

/// The same for the three inner edges of each coarse face in [begin, end): inner edge i of face
/// f, m_{i+2} -> m_{i+1}, has as first face the corner face at c_{i+2}, as second the centre
/// face, opposite m_i.
template <class Interior>
void loop_inner(const TriangleTopology& coarse, std::uint32_t begin, std::uint32_t end, Interior&& interior) {
  const std::uint32_t V = coarse.vertex_count;
  for (std::uint32_t f = begin; f < end; ++f) {
    const std::uint32_t* c = &coarse.triangles[3 * f];
    const std::uint32_t m[3] = {V + coarse.face_edges[3 * f], V + coarse.face_edges[3 * f + 1], V + coarse.face_edges[3 * f + 2]};
    for (int i = 0; i < 3; ++i) interior(m[(i + 2) % 3], m[(i + 1) % 3], c[(i + 2) % 3], m[i]);
  }
}

/// Mean-preserving update for interpolating schemes (seed 003 eq. 5.9), as its synthesis
/// (inverse) step: even = even~ - lambda_l * sum(adjacent details), lambda_l = 1 / (2 (1 + c_l)),
/// c_l the column sum of `predict` at l (see lifting.cpp for the derivation from eq. 5.8). The
/// row of even vertex l takes its edges in increasing order.
LiftingStep mean_preserving_update(const TriangleTopology& topology, const LiftingStep& predict);

/// Adds each source's weights in the rows of `predict` to `column_sum` (indexed by source
/// vertex), row after row in table order: over the blocks of predict_blocks() in the order they
/// come, the same sums, bit for bit, as over the whole step. \pre column_sum covers every source vertex.
void add_column_sums(const LiftingStep& predict, std::span<double> column_sum);

/// lambda_l of the mean-preserving update from the column sum c_l: 1 / (2 (1 + c_l)) (seed 003
/// eq. 5.8-5.9; derived in docs/WAVELETS.md), or 0 where 1 + c_l <= 1e-3: a vertex the prediction
/// hardly reads, where the formula would blow up.
inline double update_weight(double column_sum) {
  const double mass = 1.0 + column_sum;
  return mass > 1e-3 ? 1.0 / (2.0 * mass) : 0.0;
}

}  // namespace meshlift::stencils
