// The base vertices' coefficients above the base plane (FORMAT.md §5.1, format version 4):
// predicted from their neighbours in the base mesh and coded as integers, before the bit planes.
//
// Why: SPIHT codes a base coordinate one bit plane at a time from the top, as if nothing were
// known of it; but a base vertex lies about an edge length from where its neighbours predict it
// (the mean of the parallelograms across its faces whose corners are decoded before it, as
// Cohen-Or et al. and Draco's multi-parallelogram predict), and its coordinate is about the
// model's size from the centre. Coding the top planes of the base as the residual of that
// prediction saves log2(size / edge) bits per coordinate (~3.4 bits on
// armadillo's 813-vertex base: 2,060 of the 2,190 bytes the stream held down to plane 9 were the
// base's; docs/RESULTS.md). The planes below the base plane stay in SPIHT's embedded order, so
// the stream is embedded from the base plane on; above it, a prefix holds the base vertices
// decoded so far (in label order) and the predictions of the rest (with zero residuals).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/range_coder.h"
#include "meshlift/topology.h"
#include "zerotree_coder.h"

namespace meshlift::base_values {

/// Largest number of planes the base part may cover (top_plane + 1 - base_plane): the high parts
/// are then below 2^29 in magnitude and the residuals of the prediction below 2^31, which the
/// unsigned integer coder holds.
inline constexpr int kMaxPlanes = 29;

/// The plane the encoder starts SPIHT at for the base vertices: the base part codes the planes
/// [base_plane, top_plane] of every base coefficient. Chosen where the prediction has taken most
/// of what it can: the step 2^base_plane between a half and the whole of the residuals' root mean
/// square magnitude, within [max(0, top_plane + 1 - kMaxPlanes), top_plane + 1]. Finer, each
/// plane costs about a bit per coordinate either way, but the base part (which a prefix needs
/// whole) grows; coarser, the prediction's gain is cut. Measured (docs/RESULTS.md): a quarter or
/// an eighth of the RMS give the same BD-rate over 55-75 dB, the whole RMS 0.3 points less, and
/// the coarser the step the better the prefixes below 1 bit per input vertex.
int choose_base_plane(const TriangleTopology& base, const zerotree::Quantized& q, int top_plane);

/// The residuals the base part codes for the high parts `high` of the base vertices
/// (base.vertex_count * components values, vertex-major): each value minus its prediction from the
/// vertices labelled before it (FORMAT.md §5.1). Exposed for tests.
std::vector<std::int64_t> residuals(const TriangleTopology& base, std::span<const std::int64_t> high, int components);

/// Codes the high parts sign * (magnitude >> base_plane) of the base vertices' coefficients in q
/// (the first base.vertex_count vertices, vertex-major, q.components each), vertex by vertex in
/// label order. `base` is the base mesh in stream order (§4). Nothing is coded if
/// base_plane > top_plane.
void encode(const TriangleTopology& base, const zerotree::Quantized& q, int base_plane, int top_plane,
            RangeEncoder& encoder);

/// Decodes them into `high` (base.vertex_count * components signed values, vertex-major; resized).
/// Returns how many vertices were decoded whole: base_vertices, or fewer if the stream ended:
/// then every later vertex takes its prediction from those before it with a zero residual,
/// clamped to |high| < 2^(top_plane + 1 - base_plane) (FORMAT.md §5.1). `corrupt` is set for a
/// value out of that range or an invalid integer code (the values from that vertex on are 0).
std::uint32_t decode(const TriangleTopology& base, int components, int base_plane, int top_plane, RangeDecoder& decoder,
                     std::vector<std::int64_t>& high, bool& corrupt);

}  // namespace meshlift::base_values
