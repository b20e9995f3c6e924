// Lifting wavelet transforms: analysis and synthesis over the same tables (seed 003 §5.4.2).
//
// Per level j -> j+1 the synthesis steps are, in order:
//   linear / butterfly:           [predict]
//   with mean-preserving update:  [inverse update, predict]   (analysis: predict, then update)
//   loop:                         [predict, loop update]      (analysis: inverse update, then predict)
// For Loop the update step reads the final odd values, so synthesis with zero details is Loop
// subdivision exactly (CODEC-NOTES §3).
//
// Mean-preserving update (seed 003 eq. 5.8/5.9) for one vanishing moment: with
// (U d)(l) = lambda_l sum_{k ~ l} d(k), condition (5.8) U^T (1 + P^T 1) = 1 reads, for the odd
// vertex k on edge (a, b): lambda_a (1 + c_a) + lambda_b (1 + c_b) = 1, where c_l = (P^T 1)(l) is
// the column sum of the predictor. lambda_l = 1 / (2 (1 + c_l)) solves it at every edge; in the
// regular case c = 3 and lambda = 1/8, the weight of Schroeder and Sweldens' lifted linear
// wavelet (the seed's 1/24 counts an even vertex's six odd neighbours, U 1, where U^T 1 belongs).
// It preserves sum(fine) = sum_l (1 + c_l) coarse(l) exactly; tests/codec/test_lifting.cpp checks it.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "meshlift/lifting.h"

#include "concurrent.h"
#include "large_array.h"
#include "stencils.h"

namespace meshlift {

const char* to_string(Scheme scheme) {
  switch (scheme) {
    case Scheme::linear:
      return "linear";
    case Scheme::butterfly:
      return "butterfly";
    case Scheme::loop:
      return "loop";
  }
  return "?";
}

double loop_beta(unsigned n) {
  const double c = 3.0 / 8 + 0.25 * std::cos(2.0 * std::numbers::pi / n);
  return (5.0 / 8 - c * c) / n;
}

Scheme parse_scheme(const std::string& name) {
  for (Scheme s : {Scheme::linear, Scheme::butterfly, Scheme::loop})
    if (name == to_string(s)) return s;
  throw std::invalid_argument("unknown wavelet scheme '" + name + "' (expected linear, butterfly or loop)");
}

WaveletTransform::WaveletTransform(const SemiRegularHierarchy& hierarchy, WaveletOptions options)
    : WaveletTransform(hierarchy, options, 0, hierarchy.levels()) {}

WaveletTransform::WaveletTransform(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int first_level,
                                   int end_level)
    : options_(options), first_level_(first_level), end_level_(end_level) {
  if (first_level < 0 || first_level > end_level || end_level > hierarchy.levels())
    throw std::invalid_argument("WaveletTransform: levels " + std::to_string(first_level) + " .. " +
                                std::to_string(end_level) + " are not within 0 .. " + std::to_string(hierarchy.levels()));
  for (int j = 0; j <= hierarchy.levels(); ++j) vertex_counts_.push_back(hierarchy.vertex_count(j));
  steps_.resize(hierarchy.levels());
  for (int j = first_level; j < end_level; ++j) {
    const TriangleTopology& t = hierarchy.topology(j);
    auto& steps = steps_[j];
    if (options.scheme == Scheme::loop) {
      // Levels above the base are refinements of the level below: their rows follow from it.
      const TriangleTopology* coarse = j > 0 ? &hierarchy.topology(j - 1) : nullptr;
      steps.push_back(coarse ? stencils::loop_predict_refined(*coarse, t) : stencils::predict(t, options.scheme));
      steps.push_back(coarse ? stencils::loop_update_refined(*coarse, t) : stencils::loop_update(t));
      continue;
    }
    // Above the base, read off the level below too (a quarter of the random reads).
    LiftingStep predict = j > 0 ? stencils::refined_predict(hierarchy.topology(j - 1), options.scheme)
                                : stencils::predict(t, options.scheme);
    if (options.mean_preserving_update) {
      steps.push_back(stencils::mean_preserving_update(t, predict));
      steps.push_back(std::move(predict));
    } else {
      steps.push_back(std::move(predict));
    }
  }
}

std::size_t LiftingStep::memory_bytes() const {
  return indices.capacity() * sizeof(std::uint32_t) + runs.capacity() * sizeof(Run) + patterns.capacity() * sizeof(Pattern) +
         pattern_weights.capacity() * sizeof(double);
}

namespace {

/// How many source entries ahead the loops prefetch (at most LiftingStep::kPadding): about
/// eight rows, as sources are scattered over a level larger than the caches.
constexpr std::uint32_t kPrefetchDistance = LiftingStep::kPadding;

// `rows` rows of one pattern in the synthesis direction: x[t] = scale x[t] + sum_k w_k x[i_k],
// with C channels and A sources known at compile time where it matters (0: read at run time).
// Fixed summation order (scale term first, then the sources in table order) so that every build
// of the decoder computes the same bits.
template <int C, int A>
const std::uint32_t* synthesize_run(double* __restrict x, double* __restrict target, const std::uint32_t* idx,
                                    const LiftingStep::Pattern& p, const double* w, std::uint32_t rows, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t arity = A > 0 ? static_cast<std::uint32_t>(A) : p.arity;
  const double scale = p.scale;
  for (std::uint32_t r = 0; r < rows; ++r, target += n, idx += arity) {
    double acc[C > 0 ? C : 64];
    for (int c = 0; c < n; ++c) acc[c] = scale * target[c];
    for (std::uint32_t k = 0; k < arity; ++k) {
      __builtin_prefetch(x + static_cast<std::size_t>(idx[k + kPrefetchDistance]) * n);
      const double* source = x + static_cast<std::size_t>(idx[k]) * n;
      for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
    }
    for (int c = 0; c < n; ++c) target[c] = acc[c];
  }
  return idx;
}

// The inverse: x[t] = (x[t] - sum_k w_k x[i_k]) / scale, the sum from zero in table order.
template <int C, int A>
const std::uint32_t* analyze_run(double* __restrict x, double* __restrict target, const std::uint32_t* idx,
                                 const LiftingStep::Pattern& p, const double* w, std::uint32_t rows, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t arity = A > 0 ? static_cast<std::uint32_t>(A) : p.arity;
  const double scale = p.scale;
  for (std::uint32_t r = 0; r < rows; ++r, target += n, idx += arity) {
    double acc[C > 0 ? C : 64] = {};
    for (std::uint32_t k = 0; k < arity; ++k) {
      __builtin_prefetch(x + static_cast<std::size_t>(idx[k + kPrefetchDistance]) * n);
      const double* source = x + static_cast<std::size_t>(idx[k]) * n;
      for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
    }
    for (int c = 0; c < n; ++c) target[c] = (target[c] - acc[c]) / scale;
  }
  return idx;
}

// One step, run by run, its rows [begin, end) (no row reads another row's target, so any split
// of the rows computes the same bits). The regular rows take a specialized loop: 2 sources
// (linear, boundary), 4 (Loop interior edge, 4-point), 6 and 8 (Loop even vertex, butterfly);
// the rest (extraordinary vertices) the generic one.
template <bool Synthesis, int C>
void apply_step(const LiftingStep& s, double* x, int channels, std::uint32_t begin, std::uint32_t end) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t* idx = s.indices.data();
  std::uint32_t row = 0;  // the run's first row
  for (const LiftingStep::Run& run : s.runs) {
    const LiftingStep::Pattern& p = s.patterns[run.pattern];
    const std::uint32_t run_end = row + run.rows, first = std::max(row, begin), last = std::min(run_end, end);
    if (first < last) {
      const double* w = s.pattern_weights.data() + p.first_weight;
      const std::uint32_t* from = idx + std::size_t{first - row} * p.arity;
      double* target = x + (std::size_t{s.first_target} + first) * static_cast<std::size_t>(n);
      auto apply = [&]<int A>() {
        Synthesis ? synthesize_run<C, A>(x, target, from, p, w, last - first, n)
                  : analyze_run<C, A>(x, target, from, p, w, last - first, n);
      };
      switch (p.arity) {
        case 2:
          apply.template operator()<2>();
          break;
        case 4:
          apply.template operator()<4>();
          break;
        case 6:
          apply.template operator()<6>();
          break;
        case 8:
          apply.template operator()<8>();
          break;
        default:
          apply.template operator()<0>();
      }
    }
    if (run_end >= end) break;
    idx += std::size_t{run.rows} * p.arity;
    row = run_end;
  }
}

template <bool Synthesis>
void apply_step(const LiftingStep& s, double* x, int channels, std::uint32_t begin, std::uint32_t end) {
  // Positions (3) and single channels (1) get unrolled loops.
  if (channels == 3)
    apply_step<Synthesis, 3>(s, x, 3, begin, end);
  else if (channels == 1)
    apply_step<Synthesis, 1>(s, x, 1, begin, end);
  else
    apply_step<Synthesis, 0>(s, x, channels, begin, end);
}

/// The whole step; on two threads (each half of the rows) when asked and the step is large.
template <bool Synthesis>
void apply_step(const LiftingStep& s, double* x, int channels, bool concurrent = false) {
  constexpr std::uint32_t kConcurrentRows = 1u << 14;
  const std::uint32_t rows = s.row_count, half = rows / 2;
  if (!concurrent || rows < kConcurrentRows) {
    apply_step<Synthesis>(s, x, channels, 0, rows);
    return;
  }
  run_both(true, [&] { apply_step<Synthesis>(s, x, channels, half, rows); },
           [&] { apply_step<Synthesis>(s, x, channels, 0, half); });
}

// Loop's predict step of a refined level applied as its rows are read off the coarse faces
// (stencils::loop_halves, loop_inner), for the halves of coarse edges [e0, e1) and then the inner
// edges of coarse faces [f0, f1), in chunks, each chunk's targets handed to before_odd first: each
// row computed as synthesize_run computes its table row (the target times the scale 1 first, then
// the sources in row order with the row's weights), a pillow's merged row as its table holds it
// (c once, with 1/8 + 1/8).
// With Synthesis false its analysis, each row as analyze_run computes it: the sources summed
// from zero in row order, subtracted from the target (the scale is 1); before_odd is then unused.
template <bool Synthesis, int C>
void loop_predict_direct(const TriangleTopology& coarse, std::uint32_t first_odd, double* __restrict x, int channels,
                         const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, std::uint32_t e0,
                         std::uint32_t e1, std::uint32_t f0, std::uint32_t f1) {
  const int n = C > 0 ? C : channels;
  const double outer = 3.0 / 8, wing = 1.0 / 8, merged = 1.0 / 8 + 1.0 / 8, half = 0.5;
  double* target = nullptr;
  // The row's first term (the target times its scale 1, or analyze_run's zero) and its end.
  auto start = [&](int k) { return Synthesis ? 1.0 * target[k] : 0.0; };
  auto finish = [&](int k, double acc) { target[k] = Synthesis ? acc : (target[k] - acc) / 1.0; };
  auto interior = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    const double *pa = x + std::size_t{a} * n, *pb = x + std::size_t{b} * n, *pc = x + std::size_t{c} * n;
    if (c != d) [[likely]] {
      const double* pd = x + std::size_t{d} * n;
      for (int k = 0; k < n; ++k) {
        double acc = start(k);
        acc += outer * pa[k];
        acc += outer * pb[k];
        acc += wing * pc[k];
        acc += wing * pd[k];
        finish(k, acc);
      }
    } else {
      for (int k = 0; k < n; ++k) {
        double acc = start(k);
        acc += outer * pa[k];
        acc += outer * pb[k];
        acc += merged * pc[k];
        finish(k, acc);
      }
    }
    target += n;
  };
  auto boundary = [&](std::uint32_t a, std::uint32_t b) {
    const double *pa = x + std::size_t{a} * n, *pb = x + std::size_t{b} * n;
    for (int k = 0; k < n; ++k) {
      double acc = start(k);
      acc += half * pa[k];
      acc += half * pb[k];
      finish(k, acc);
    }
    target += n;
  };
  constexpr std::uint32_t kChunk = 8192;
  const auto E = static_cast<std::uint32_t>(coarse.edge_count());
  for (std::uint32_t begin = e0; begin < e1; begin += kChunk) {
    const std::uint32_t end = begin + std::min(kChunk, e1 - begin);
    if (Synthesis && before_odd) before_odd(first_odd + 2 * begin, 2 * (end - begin));
    target = x + (std::size_t{first_odd} + 2 * std::size_t{begin}) * n;
    stencils::loop_halves(coarse, begin, end, interior, boundary);
  }
  for (std::uint32_t begin = f0; begin < f1; begin += kChunk) {
    const std::uint32_t end = begin + std::min(kChunk, f1 - begin);
    if (Synthesis && before_odd) before_odd(first_odd + 2 * E + 3 * begin, 3 * (end - begin));
    target = x + (std::size_t{first_odd} + 2 * std::size_t{E} + 3 * std::size_t{begin}) * n;
    stencils::loop_inner(coarse, begin, end, interior);
  }
}

void check_channels(int channels) {
  if (channels < 1 || channels > 64) throw std::invalid_argument("channels must be between 1 and 64");
}

/// loop_predict_direct with its channel count known at compile time for positions (3) and single channels (1).
template <bool Synthesis>
void loop_predict(const TriangleTopology& coarse, std::uint32_t first_odd, double* x, int channels,
                  const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, std::uint32_t e0, std::uint32_t e1,
                  std::uint32_t f0, std::uint32_t f1) {
  if (channels == 3)
    loop_predict_direct<Synthesis, 3>(coarse, first_odd, x, 3, before_odd, e0, e1, f0, f1);
  else if (channels == 1)
    loop_predict_direct<Synthesis, 1>(coarse, first_odd, x, 1, before_odd, e0, e1, f0, f1);
  else
    loop_predict_direct<Synthesis, 0>(coarse, first_odd, x, channels, before_odd, e0, e1, f0, f1);
}

/// Loop's update step above the base is made and applied in blocks of 16 Ki rows (256 KiB of
/// sources, in L2 from writing to use).
constexpr std::uint32_t kLoopUpdateBlockRows = 16384;

}  // namespace

void WaveletTransform::require_tables(int first_level, int end_level) const {
  if (first_level < end_level && (first_level < first_level_ || end_level > end_level_))
    throw std::logic_error("WaveletTransform: levels " + std::to_string(first_level) + " .. " + std::to_string(end_level) +
                           " asked for, tables built for " + std::to_string(first_level_) + " .. " +
                           std::to_string(end_level_) + " only");
}

void WaveletTransform::analyze(std::span<double> values, int channels) const {
  check_channels(channels);
  require_tables(0, levels());
  if (values.size() < static_cast<std::size_t>(vertex_counts_.back()) * channels)
    throw std::invalid_argument("analyze: values hold fewer vertices than the finest level");
  for (int j = levels() - 1; j >= 0; --j) {
    const auto& steps = steps_[j];
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) apply_step<false>(*it, values.data(), channels);
  }
}

void WaveletTransform::synthesize(std::span<double> values, int channels, int to_level, int from_level, bool concurrent) const {
  check_channels(channels);
  if (to_level < 0) to_level = levels();
  if (to_level > levels()) throw std::invalid_argument("synthesize: to_level exceeds the hierarchy's levels");
  if (from_level < 0 || from_level > to_level) throw std::invalid_argument("synthesize: from_level must be in 0..to_level");
  if (values.size() < static_cast<std::size_t>(vertex_counts_[to_level]) * channels)
    throw std::invalid_argument("synthesize: values hold fewer vertices than the requested level");
  require_tables(from_level, to_level);
  for (int j = from_level; j < to_level; ++j)
    for (const LiftingStep& step : steps_[j]) apply_step<true>(step, values.data(), channels, concurrent);
}

namespace {

/// Calls f(e, a, b) for every edge e = (a, b) of level `level`, in increasing order: the base's
/// from its own topology, above it read off the level below (TriangleTopology::refined_edge),
/// whose topology the decoder keeps (a quarter of the size).
template <class F>
void for_each_level_edge(const SemiRegularHierarchy& hierarchy, int level, F&& f) {
  const auto edges = static_cast<std::uint32_t>(hierarchy.vertex_count(level + 1) - hierarchy.vertex_count(level));
  if (level == 0) {
    const std::uint32_t* ends = hierarchy.topology(0).edge_vertices.data();
    for (std::uint32_t e = 0; e < edges; ++e) f(e, ends[2 * std::size_t{e}], ends[2 * std::size_t{e} + 1]);
    return;
  }
  const TriangleTopology& coarse = hierarchy.topology(level - 1);
  for (std::uint32_t e = 0; e < edges; ++e) {
    std::uint32_t a, b;
    coarse.refined_edge(e, a, b);
    f(e, a, b);
  }
}

/// The synthesis step of the mean-preserving update (stencils::mean_preserving_update) without
/// its table, over level `level` of `hierarchy`: each even vertex v (below vertex_count(level))
/// gets x[v] += weight[v] x[V + e] for its edges e in increasing order, weight[v] = -lambda_v
/// (update_weights(); seed 003 eq. 5.9, docs/WAVELETS.md). Those are the operations of v's row in
/// their order (the scale 1 term, then the sources in table order), so the bits are the table's.
/// The edges come from the base's own topology, above it from the level below
/// (TriangleTopology::refined_edge), whose topology the decoder keeps (a quarter of the size).
/// x holds `channels` values per vertex.
void inverse_update_level(const SemiRegularHierarchy& hierarchy, int level, std::span<const double> weight, double* x,
                          int channels) {
  const auto n = static_cast<std::size_t>(channels);
  const std::uint32_t first_odd = hierarchy.vertex_count(level);
  for_each_level_edge(hierarchy, level, [&](std::uint32_t e, std::uint32_t a, std::uint32_t b) {
    const double* detail = x + (std::size_t{first_odd} + e) * n;
    for (const std::uint32_t v : {a, b}) {
      const double w = weight[v];
      double* even = x + std::size_t{v} * n;
      for (std::size_t c = 0; c < n; ++c) even[c] += w * detail[c];
    }
  });
}

/// The predict step of linear or butterfly for level `level`, 8 Ki rows at a time (256 KiB of
/// butterfly's sources): at the base its rows' blocks from its topology, each applied as it
/// comes, before_odd given each block's targets first; above it each row applied as it is read
/// off the level below (`rows`, stencils::RefinedPredictRows; the level's own topology is not
/// needed), before_odd given each chunk's. The same bits either way.
constexpr std::uint32_t kPredictBlockRows = 8192;
void predict_synthesis(const SemiRegularHierarchy& hierarchy, Scheme scheme, int level,
                       const stencils::RefinedPredictRows* rows, double* x, int channels,
                       const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, bool concurrent) {
  if (level > 0) {
    rows->synthesize(kPredictBlockRows, x, channels, before_odd, concurrent);
    return;
  }
  stencils::predict_blocks(hierarchy.topology(0), scheme, kPredictBlockRows, [&](const LiftingStep& block) {
    if (before_odd) before_odd(block.first_target, block.row_count);
    apply_step<true>(block, x, channels);
  });
}

/// The refined rows of level `level` (read off the level below), or none at the base.
std::optional<stencils::RefinedPredictRows> refined_rows(const SemiRegularHierarchy& hierarchy, Scheme scheme, int level) {
  std::optional<stencils::RefinedPredictRows> rows;
  if (level > 0) rows.emplace(hierarchy.topology(level - 1), scheme);
  return rows;
}

/// update_weights() of a level whose refined rows (refined_rows()) are made already.
std::vector<double> level_update_weights(const SemiRegularHierarchy& hierarchy, Scheme scheme, int level,
                                         const stencils::RefinedPredictRows* rows) {
  // The predict rows' column sums in table order (stencils::add_column_sums: at the base over its
  // blocks, above it as the rows are read off the level below), then each vertex's weight in
  // place of its sum.
  std::vector<double> weight(hierarchy.vertex_count(level), 0.0);
  if (level == 0)
    stencils::predict_blocks(hierarchy.topology(0), scheme, kPredictBlockRows,
                             [&](const LiftingStep& block) { stencils::add_column_sums(block, weight); });
  else
    rows->add_column_sums(weight);
  for (double& w : weight) w = -stencils::update_weight(w);
  return weight;
}

}  // namespace

void synthesize_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                      int channels) {
  synthesize_level(hierarchy, options, level, values, channels, {});
}

std::vector<double> update_weights(const SemiRegularHierarchy& hierarchy, Scheme scheme, int level) {
  if (scheme == Scheme::loop) throw std::invalid_argument("update_weights: Loop has its own update");
  if (level < 0 || level >= hierarchy.levels())
    throw std::invalid_argument("update_weights: no level " + std::to_string(level) + " below the finest");
  const std::optional<stencils::RefinedPredictRows> rows = refined_rows(hierarchy, scheme, level);
  return level_update_weights(hierarchy, scheme, level, rows ? &*rows : nullptr);
}

void synthesize_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                      int channels, const std::function<void(std::uint32_t, std::uint32_t)>& before_odd, bool concurrent,
                      std::span<const double> weights) {
  check_channels(channels);
  if (level < 0 || level >= hierarchy.levels())
    throw std::invalid_argument("synthesize_level: no level " + std::to_string(level) + " below the finest");
  if (values.size() < static_cast<std::size_t>(hierarchy.vertex_count(level + 1)) * channels)
    throw std::invalid_argument("synthesize_level: values hold fewer vertices than the level makes");
  const std::uint32_t first_odd = hierarchy.vertex_count(level);
  if (options.scheme != Scheme::loop) {
    // One predict step (predict_synthesis), each chunk's odd vertices made ready just before it.
    if (!options.mean_preserving_update) {
      const std::optional<stencils::RefinedPredictRows> rows = refined_rows(hierarchy, options.scheme, level);
      predict_synthesis(hierarchy, options.scheme, level, rows ? &*rows : nullptr, values.data(), channels, before_odd,
                        concurrent);
      return;
    }
    // With the mean-preserving update, its step first, without the tables of either step: its
    // weights (handed over, or update_weights(): a first pass over the predict rows), every odd
    // vertex made ready (the update reads them all), the update, then the predict rows as above,
    // read through the same refined rows as the weights' pass (made once, in that pass). The
    // first two side by side: the weights' pass reads only the topology and writes only `rows`
    // and `computed`; before_odd writes only odd vertices; run_both joins both before the update
    // reads them.
    if (!weights.empty() && weights.size() != first_odd)
      throw std::invalid_argument("synthesize_level: the update's weights are not the level's vertices");
    std::optional<stencils::RefinedPredictRows> rows;
    std::vector<double> computed;
    run_both(
        concurrent && weights.empty(),
        [&] { if (before_odd) before_odd(first_odd, hierarchy.vertex_count(level + 1) - first_odd); },
        [&] {
          rows = refined_rows(hierarchy, options.scheme, level);
          if (weights.empty()) computed = level_update_weights(hierarchy, options.scheme, level, rows ? &*rows : nullptr);
        });
    inverse_update_level(hierarchy, level, weights.empty() ? std::span<const double>(computed) : weights, values.data(),
                         channels);
    predict_synthesis(hierarchy, options.scheme, level, rows ? &*rows : nullptr, values.data(), channels, {}, concurrent);
    return;
  }
  if (level == 0) {
    // Loop's base level: its tables (its update step reads the odd vertices).
    if (before_odd) before_odd(first_odd, hierarchy.vertex_count(level + 1) - first_odd);
    WaveletTransform(hierarchy, options, level, level + 1).synthesize(values, channels, level + 1, level);
    return;
  }
  // The predict step straight off the coarse faces, 8 Ki coarse edges or faces at a time; then
  // the update step a block at a time.
  // With `concurrent`, the second half of the edges and of the faces on a thread of their own.
  const TriangleTopology& coarse = hierarchy.topology(level - 1);
  const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
  in_halves(concurrent, E, F, [&](std::uint32_t e0, std::uint32_t e1, std::uint32_t f0, std::uint32_t f1) {
    loop_predict<true>(coarse, first_odd, values.data(), channels, before_odd, e0, e1, f0, f1);
  });
  stencils::loop_update_blocks(
      coarse, first_odd, kLoopUpdateBlockRows,
      [&](const LiftingStep& block) { apply_step<true>(block, values.data(), channels); }, {}, concurrent);
}

void analyze_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                   int channels, bool concurrent, std::span<const double> weights) {
  check_channels(channels);
  if (level < 0 || level >= hierarchy.levels())
    throw std::invalid_argument("analyze_level: no level " + std::to_string(level) + " below the finest");
  if (values.size() < static_cast<std::size_t>(hierarchy.vertex_count(level + 1)) * channels)
    throw std::invalid_argument("analyze_level: values hold fewer vertices than the level makes");
  double* const x = values.data();
  if (level == 0) {
    // The base's tables (small), their steps in reverse.
    const WaveletTransform tables(hierarchy, options, 0, 1);
    const auto& steps = tables.steps(0);
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) apply_step<false>(*it, x, channels, concurrent);
    return;
  }
  const std::uint32_t first_odd = hierarchy.vertex_count(level);
  if (options.scheme == Scheme::loop) {
    // Synthesis is [predict, update]: first the update's rows a block at a time, then the predict
    // rows straight off the coarse faces.
    const TriangleTopology& coarse = hierarchy.topology(level - 1);
    const auto E = static_cast<std::uint32_t>(coarse.edge_count()), F = static_cast<std::uint32_t>(coarse.face_count());
    stencils::loop_update_blocks(
        coarse, first_odd, kLoopUpdateBlockRows, [&](const LiftingStep& block) { apply_step<false>(block, x, channels); },
        {}, concurrent);
    in_halves(concurrent, E, F, [&](std::uint32_t e0, std::uint32_t e1, std::uint32_t f0, std::uint32_t f1) {
      loop_predict<false>(coarse, first_odd, x, channels, {}, e0, e1, f0, f1);
    });
    return;
  }
  // Synthesis is [update, predict] with the mean-preserving update, else [predict]: the predict
  // rows as they are read off the level below, then the update.
  const std::optional<stencils::RefinedPredictRows> rows = refined_rows(hierarchy, options.scheme, level);
  rows->analyze(kPredictBlockRows, x, channels, concurrent);
  if (!options.mean_preserving_update) return;
  if (!weights.empty() && weights.size() != first_odd)
    throw std::invalid_argument("analyze_level: the update's weights are not the level's vertices");
  std::vector<double> computed;
  if (weights.empty()) computed = level_update_weights(hierarchy, options.scheme, level, &*rows);
  const std::span<const double> weight = weights.empty() ? std::span<const double>(computed) : weights;
  // Each even vertex's row as analyze_run computes it: its sources (the details on its edges,
  // in increasing edge order) times its weight summed from zero, then subtracted. The sums are
  // scattered over the edges in increasing order into a buffer, each vertex's in its row's order.
  const auto n = static_cast<std::size_t>(channels);
  std::vector<double> sum;
  assign_large(sum, std::size_t{first_odd} * n, 0.0);
  for_each_level_edge(hierarchy, level, [&](std::uint32_t e, std::uint32_t a, std::uint32_t b) {
    const double* detail = x + (std::size_t{first_odd} + e) * n;
    for (const std::uint32_t v : {a, b}) {
      const double w = weight[v];
      double* s = sum.data() + std::size_t{v} * n;
      for (std::size_t c = 0; c < n; ++c) s[c] += w * detail[c];
    }
  });
  for (std::size_t i = 0; i < std::size_t{first_odd} * n; ++i) x[i] = (x[i] - sum[i]) / 1.0;
}

std::size_t WaveletTransform::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& level : steps_)
    for (const auto& s : level) bytes += s.memory_bytes();
  return bytes;
}

}  // namespace meshlift
