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

Scheme parse_scheme(const std::string& name) {
  for (Scheme s : {Scheme::linear, Scheme::butterfly, Scheme::loop})
    if (name == to_string(s)) return s;
  throw std::invalid_argument("unknown wavelet scheme '" + name + "' (expected linear, butterfly or loop)");
}

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
  }
}

namespace {

// One step in the synthesis direction: x[t] = scale[t] x[t] + sum_k w_k x[i_k]. Fixed summation
// order (scale term first, then the row in table order) so encoder and decoder agree bit for bit.
template <int C>
void step_synthesis(const LiftingStep& s, double* x, int channels) {
  const int n = C > 0 ? C : channels;
  const std::uint32_t* off = s.offsets.data();
  const std::uint32_t* idx = s.indices.data();
  const double* w = s.weights.data();
  const bool scaled = !s.scales.empty();
  const std::size_t rows = s.rows();
  for (std::size_t r = 0; r < rows; ++r) {
    double* target = x + (s.first_target + r) * n;
    double acc[C > 0 ? C : 64];
    const double scale = scaled ? s.scales[r] : 1.0;
    for (int c = 0; c < n; ++c) acc[c] = scale * target[c];
    for (std::uint32_t k = off[r]; k < off[r + 1]; ++k) {
      const double* source = x + static_cast<std::size_t>(idx[k]) * n;
      for (int c = 0; c < n; ++c) acc[c] += w[k] * source[c];
    }
    for (int c = 0; c < n; ++c) target[c] = acc[c];
  }
}

// The inverse: x[t] = (x[t] - sum_k w_k x[i_k]) / scale[t].
template <int C>
void step_analysis(const LiftingStep& s, double* x, int channels) {
  const int n = C > 0 ? C : channels;
  const bool scaled = !s.scales.empty();
  for (std::size_t r = 0; r < s.rows(); ++r) {
    double* target = x + (s.first_target + r) * n;
    double acc[C > 0 ? C : 64] = {};
    for (std::uint32_t k = s.offsets[r]; k < s.offsets[r + 1]; ++k) {
      const double* source = x + static_cast<std::size_t>(s.indices[k]) * n;
      for (int c = 0; c < n; ++c) acc[c] += s.weights[k] * source[c];
    }
    const double scale = scaled ? s.scales[r] : 1.0;
    for (int c = 0; c < n; ++c) target[c] = (target[c] - acc[c]) / scale;
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

void WaveletTransform::synthesize(std::span<double> values, int channels, int to_level) const {
  check_channels(channels);
  if (to_level < 0) to_level = levels();
  if (to_level > levels()) throw std::invalid_argument("synthesize: to_level exceeds the hierarchy's levels");
  if (values.size() < static_cast<std::size_t>(vertex_counts_[to_level]) * channels)
    throw std::invalid_argument("synthesize: values hold fewer vertices than the requested level");
  for (int j = 0; j < to_level; ++j)
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
    for (const auto& s : level)
      bytes += s.offsets.capacity() * 4 + s.indices.capacity() * 4 + (s.weights.capacity() + s.scales.capacity()) * 8;
  return bytes;
}

}  // namespace meshlift
