// The encoder's dead-zone quantizer (FORMAT.md §5) over a flat range of coefficients, and the
// decoder's full-rate reconstruction of what it keeps, for the encoder's closed loop. Internal to
// codec/.
#pragma once

#include <cstddef>
#include <cstdint>

#include "zerotree_coder.h"

namespace meshlift {

/// Quantizes the n coefficients x[0, n) of whole vertices (coefficient i is of component
/// i % components, whose step is steps[i % components]) of one level, whose weight is w_j, into
/// out[0, n) (their widths 0):
///   magnitude = floor(min(|x| w_j / step_c, 2^31 - 1)), negative = x < 0 and magnitude > 0;
/// and, if `reconstruction` is not null, writes there what the decoder reconstructs from them at
/// full rate, zerotree::dequantize(Decoded::midpoint(magnitude, 0, negative), step_c, w_j)
/// (`reconstruction` may be x: each value is written after its coefficient is read). Returns
/// whether some |x| w_j / step_c reached 2^31 (the precision is too fine for 32-bit magnitudes).
/// Four coefficients per instruction where AVX is offered, with the same IEEE operations in the
/// same order as the scalar formulas (no FMA), so the same bits; a NaN quantizes to 0 either way.
/// \pre 1 <= components <= zerotree::kMaxComponents.
bool quantize(const double* x, std::size_t n, int components, const double* steps, double weight,
              zerotree::Quantized::Coefficient* out, double* reconstruction);

}  // namespace meshlift
