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
#include <numbers>
#include <stdexcept>

#include "meshlift/lifting.h"
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

namespace {
/// How many source entries ahead synthesis prefetches; the index arrays carry this much padding.
constexpr std::uint32_t kPrefetchDistance = 48;
}  // namespace

WaveletTransform::WaveletTransform(const SemiRegularHierarchy& hierarchy, WaveletOptions options)
    : options_(options) {
  for (int j = 0; j <= hierarchy.levels(); ++j) vertex_counts_.push_back(hierarchy.vertex_count(j));
  steps_.resize(hierarchy.levels());
  for (int j = 0; j < hierarchy.levels(); ++j) {
    const TriangleTopology& t = hierarchy.topology(j);
    const VertexEdges vertex_edges(t);
    LiftingStep predict = stencils::predict(t, vertex_edges, options.scheme);
    auto& steps = steps_[j];
    if (options.scheme == Scheme::loop) {
      steps.push_back(std::move(predict));
      steps.push_back(stencils::loop_update(t, vertex_edges));
    } else if (options.mean_preserving_update) {
      steps.push_back(stencils::mean_preserving_update(t, vertex_edges, predict));
      steps.push_back(std::move(predict));
    } else {
      steps.push_back(std::move(predict));
    }
    for (LiftingStep& step : steps) {
      step.indices.resize(step.indices.size() + kPrefetchDistance, 0);
      step.indices.shrink_to_fit();
      step.row_pattern.shrink_to_fit();
    }
  }
}

void LiftingStep::append_row(double scale, std::span<const std::uint32_t> sources, std::span<const double> weights) {
  const auto arity = static_cast<std::uint32_t>(sources.size());
  auto matches = [&](std::uint32_t p) {
    const Pattern& candidate = patterns[p];
    return candidate.arity == arity && candidate.scale == scale &&
           std::equal(weights.begin(), weights.end(), pattern_weights.begin() + candidate.first_weight);
  };
  // Consecutive rows mostly repeat the previous row's pattern: try it first.
  std::uint32_t found = kNone;
  if (!row_pattern.empty() && matches(row_pattern.back())) found = row_pattern.back();
  for (std::uint32_t p = 0; p < patterns.size() && found == kNone; ++p)
    if (matches(p)) found = p;
  if (found == kNone) {
    found = static_cast<std::uint32_t>(patterns.size());
    patterns.push_back({arity, static_cast<std::uint32_t>(pattern_weights.size()), scale});
    pattern_weights.insert(pattern_weights.end(), weights.begin(), weights.end());
  }
  row_pattern.push_back(found);
  indices.insert(indices.end(), sources.begin(), sources.end());
}

std::size_t LiftingStep::memory_bytes() const {
  return (row_pattern.capacity() + indices.capacity()) * sizeof(std::uint32_t) + patterns.capacity() * sizeof(Pattern) +
         pattern_weights.capacity() * sizeof(double);
}

namespace {

// One row in the synthesis direction: x[t] = scale x[t] + sum_k w_k x[i_k], with C channels and
// A sources known at compile time where it matters (A = 0: read from the pattern). Fixed
// summation order (scale term first, then the sources in table order) so that every build of
// the decoder computes the same bits.
template <int C, int A>
inline const std::uint32_t* synthesize_row(double* __restrict x, double* __restrict target, const std::uint32_t* idx,
                                           const double* w, double scale, std::uint32_t arity, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t count = A > 0 ? static_cast<std::uint32_t>(A) : arity;
  double acc[C > 0 ? C : 64];
  for (int c = 0; c < n; ++c) acc[c] = scale * target[c];
  for (std::uint32_t k = 0; k < count; ++k) {
    // Sources are scattered over a level larger than the caches: fetch those of a row about
    // eight rows ahead (the index array is padded so this never reads past its end).
    __builtin_prefetch(x + static_cast<std::size_t>(idx[k + kPrefetchDistance]) * n);
    const double* source = x + static_cast<std::size_t>(idx[k]) * n;
    for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
  }
  for (int c = 0; c < n; ++c) target[c] = acc[c];
  return idx + count;
}

template <int C>
void step_synthesis(const LiftingStep& s, double* x, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t* idx = s.indices.data();
  const LiftingStep::Pattern* patterns = s.patterns.data();
  const double* weights = s.pattern_weights.data();
  double* target = x + static_cast<std::size_t>(s.first_target) * n;
  for (const std::uint32_t pattern : s.row_pattern) {
    const LiftingStep::Pattern& p = patterns[pattern];
    const double* w = weights + p.first_weight;
    // The regular rows: 2 (linear, boundary), 4 (Loop interior edge, 4-point), 6 and 8 (Loop even
    // and butterfly); the rest (extraordinary vertices) take the generic loop.
    switch (p.arity) {
      case 2:
        idx = synthesize_row<C, 2>(x, target, idx, w, p.scale, 2, n);
        break;
      case 4:
        idx = synthesize_row<C, 4>(x, target, idx, w, p.scale, 4, n);
        break;
      case 6:
        idx = synthesize_row<C, 6>(x, target, idx, w, p.scale, 6, n);
        break;
      case 8:
        idx = synthesize_row<C, 8>(x, target, idx, w, p.scale, 8, n);
        break;
      default:
        idx = synthesize_row<C, 0>(x, target, idx, w, p.scale, p.arity, n);
    }
    target += n;
  }
}

// The inverse: x[t] = (x[t] - sum_k w_k x[i_k]) / scale.
template <int C>
void step_analysis(const LiftingStep& s, double* x, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t* idx = s.indices.data();
  double* target = x + static_cast<std::size_t>(s.first_target) * n;
  for (const std::uint32_t pattern : s.row_pattern) {
    const LiftingStep::Pattern& p = s.patterns[pattern];
    const double* w = s.pattern_weights.data() + p.first_weight;
    double acc[C > 0 ? C : 64] = {};
    for (std::uint32_t k = 0; k < p.arity; ++k) {
      __builtin_prefetch(x + static_cast<std::size_t>(idx[k + kPrefetchDistance]) * n);
      const double* source = x + static_cast<std::size_t>(idx[k]) * n;
      for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
    }
    idx += p.arity;
    for (int c = 0; c < n; ++c) target[c] = (target[c] - acc[c]) / p.scale;
    target += n;
  }
}

void check_channels(int channels) {
  if (channels < 1 || channels > 64) throw std::invalid_argument("channels must be between 1 and 64");
}

}  // namespace

void WaveletTransform::analyze(std::span<double> values, int channels) const {
  check_channels(channels);
  if (values.size() < static_cast<std::size_t>(vertex_counts_.back()) * channels)
    throw std::invalid_argument("analyze: values hold fewer vertices than the finest level");
  for (int j = levels() - 1; j >= 0; --j) {
    const auto& steps = steps_[j];
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) {
      if (channels == 3)
        step_analysis<3>(*it, values.data(), 3);
      else
        step_analysis<0>(*it, values.data(), channels);
    }
  }
}

void WaveletTransform::synthesize(std::span<double> values, int channels, int to_level, int from_level) const {
  check_channels(channels);
  if (to_level < 0) to_level = levels();
  if (to_level > levels()) throw std::invalid_argument("synthesize: to_level exceeds the hierarchy's levels");
  if (from_level < 0 || from_level > to_level) throw std::invalid_argument("synthesize: from_level must be in 0..to_level");
  if (values.size() < static_cast<std::size_t>(vertex_counts_[to_level]) * channels)
    throw std::invalid_argument("synthesize: values hold fewer vertices than the requested level");
  for (int j = from_level; j < to_level; ++j)
    for (const LiftingStep& step : steps_[j]) {
      if (channels == 3)
        step_synthesis<3>(step, values.data(), 3);
      else
        step_synthesis<0>(step, values.data(), channels);
    }
}

std::size_t WaveletTransform::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& level : steps_)
    for (const auto& s : level) bytes += s.memory_bytes();
  return bytes;
}

}  // namespace meshlift
