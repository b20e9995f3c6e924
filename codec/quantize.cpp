#include "quantize.h"

#include <cmath>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MESHLIFT_QUANTIZE_AVX 1
#endif

namespace meshlift {
namespace {

/// Coefficient i alone: the formulas of quantize() as written there.
using Coefficient = zerotree::Quantized::Coefficient;

bool quantize_one(double x, double step, double weight, Coefficient& out, double* reconstruction) {
  const double scaled = std::abs(x) * weight / step;
  // floor(min(scaled, 2^31 - 1)) by a conversion, which is defined there; a NaN gives 0.
  const std::uint32_t magnitude =
      scaled < 2147483647.0 ? static_cast<std::uint32_t>(scaled) : scaled >= 2147483647.0 ? 2147483647u : 0u;
  const bool negative = x < 0 && magnitude > 0;
  out = Coefficient{magnitude, negative, 0, 0};
  if (reconstruction != nullptr)
    *reconstruction = zerotree::dequantize(zerotree::Decoded::midpoint(magnitude, 0, negative), step, weight);
  return scaled >= 2147483648.0;
}

#if defined(MESHLIFT_QUANTIZE_AVX)
// Four coefficients at a time: the steps of lanes i .. i + 3 from a pattern of 4 * components
// steps (a multiple of both 4 and the component count, so it repeats with the lanes); |x| as x
// without its sign bit, min() as the two comparisons of quantize_one (a NaN in neither), the
// floor as a truncating conversion of a value in [0, 2^31 - 1], the midpoint's sign as its sign
// bit, its 0 for a zero magnitude by a mask. Returns the coefficients done (a multiple of 4).
__attribute__((target("avx"))) std::size_t quantize_avx(const double* x, std::size_t n, int components, const double* steps,
                                                        double weight, Coefficient* out, double* reconstruction,
                                                        bool& too_fine) {
  const std::size_t period = 4 * static_cast<std::size_t>(components);
  alignas(32) double pattern[4 * zerotree::kMaxComponents];  // period <= 4 * kMaxComponents (quantize.h)
  for (std::size_t t = 0; t < period; ++t) pattern[t] = steps[t % static_cast<std::size_t>(components)];
  const __m256d sign = _mm256_set1_pd(-0.0), w = _mm256_set1_pd(weight), cap = _mm256_set1_pd(2147483647.0);
  const __m256d limit = _mm256_set1_pd(2147483648.0), half = _mm256_set1_pd(0.5), zero = _mm256_setzero_pd();
  __m256d fine = zero;
  const std::size_t done = n & ~std::size_t{3};
  for (std::size_t i = 0, p = 0; i < done; i += 4, p = p + 4 == period ? 0 : p + 4) {
    const __m256d v = _mm256_loadu_pd(x + i), step = _mm256_load_pd(pattern + p);
    const __m256d scaled = _mm256_div_pd(_mm256_mul_pd(_mm256_andnot_pd(sign, v), w), step);
    fine = _mm256_or_pd(fine, _mm256_cmp_pd(scaled, limit, _CMP_GE_OQ));
    const __m256d clamped = _mm256_or_pd(_mm256_and_pd(_mm256_cmp_pd(scaled, cap, _CMP_LT_OQ), scaled),
                                         _mm256_and_pd(_mm256_cmp_pd(scaled, cap, _CMP_GE_OQ), cap));
    const __m128i m = _mm256_cvttpd_epi32(clamped);
    const __m256d known = _mm256_cvtepi32_pd(m);
    const __m256d nonzero = _mm256_cmp_pd(known, zero, _CMP_NEQ_OQ);
    const __m256d is_negative = _mm256_and_pd(_mm256_cmp_pd(v, zero, _CMP_LT_OQ), nonzero);
    const int bits = _mm256_movemask_pd(is_negative);
    alignas(16) std::uint32_t lanes[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes), m);
    for (int k = 0; k < 4; ++k)
      out[i + static_cast<std::size_t>(k)] = Coefficient{lanes[k], ((bits >> k) & 1) != 0, 0, 0};
    if (reconstruction != nullptr) {
      // midpoint: known + 0.5, negated if negative, 0 if known is; dequantize: mid * step / w.
      const __m256d mid = _mm256_and_pd(_mm256_xor_pd(_mm256_add_pd(known, half), _mm256_and_pd(is_negative, sign)), nonzero);
      _mm256_storeu_pd(reconstruction + i, _mm256_div_pd(_mm256_mul_pd(mid, step), w));
    }
  }
  too_fine |= _mm256_movemask_pd(fine) != 0;
  return done;
}
#endif

}  // namespace

bool quantize(const double* x, std::size_t n, int components, const double* steps, double weight, Coefficient* out,
              double* reconstruction) {
  bool too_fine = false;
  std::size_t i = 0;
#if defined(MESHLIFT_QUANTIZE_AVX)
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) i = quantize_avx(x, n, components, steps, weight, out, reconstruction, too_fine);
#endif
  const auto k = static_cast<std::size_t>(components);
  for (; i < n; ++i)
    too_fine |= quantize_one(x[i], steps[i % k], weight, out[i], reconstruction != nullptr ? reconstruction + i : nullptr);
  return too_fine;
}

}  // namespace meshlift
