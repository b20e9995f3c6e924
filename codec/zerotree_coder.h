// Embedded bit-plane coding of the wavelet coefficients by set partitioning in hierarchical
// trees (SPIHT, Said & Pearlman 1996) over the semi-regular coefficient tree, as Progressive
// Geometry Compression (Khodakovsky, Schroeder, Sweldens 2000) does, with every decision coded by
// the adaptive binary range coder under a context (level, component, sibling significance).
// A vertex carries K components: its three geometry coefficients (x, y, z, or normal and two
// tangents in local frames) and then those of any extra channels (FORMAT.md §5).
// Encoder and decoder run the same traversal (zerotree_coder.cpp), so they cannot drift apart.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/range_coder.h"
#include "meshlift/semi_regular.h"

namespace meshlift::zerotree {

/// Components coded per vertex: 3 for the geometry, up to kMaxChannelComponents more.
inline constexpr int kGeometryComponents = 3;
inline constexpr int kMaxChannelComponents = 4;
inline constexpr int kMaxComponents = kGeometryComponents + kMaxChannelComponents;

/// The coding forest over all vertices: roots are the base vertices; a base vertex's children
/// are the level-1 odd vertices on the base edges it starts (edge_vertices[2e] == v); every other
/// vertex's children are its coefficient-tree children (CODEC-NOTES §1).
struct Forest {
  std::uint32_t roots = 0;
  std::vector<std::uint32_t> child_offsets;  ///< vertex_count + 1
  std::vector<std::uint32_t> children;
  std::vector<std::uint8_t> level;  ///< level of each vertex (for contexts)

  explicit Forest(const SemiRegularHierarchy& hierarchy);
  std::uint32_t vertex_count() const { return static_cast<std::uint32_t>(level.size()); }
};

/// Integer magnitudes floor(|c| / step) and signs of the normalized coefficients, `components`
/// per vertex (vertex-major).
struct Quantized {
  int components = kGeometryComponents;
  std::vector<std::uint32_t> magnitude;
  std::vector<std::uint8_t> negative;
};

/// Highest plane n with some magnitude >= 2^n (-1 if all are zero).
int top_plane(const Quantized& q);

void encode(const Forest& forest, const Quantized& q, int top_plane, RangeEncoder& encoder);

/// What the decoder knows of each coefficient: magnitude bits known down to `low_plane`
/// (|c| in [known, known + 2^low_plane) steps), or insignificant (known == 0).
struct Decoded {
  int components = kGeometryComponents;
  std::vector<std::uint32_t> known;
  std::vector<std::int8_t> low_plane;
  std::vector<std::uint8_t> negative;
  int last_plane = -1;  ///< the lowest plane the decoder reached (partly or wholly)
  bool complete = false;

  /// Reconstruction in steps: the midpoint of the interval, signed; 0 if insignificant.
  double value(std::size_t i) const { return midpoint(known[i], low_plane[i], negative[i]); }

  /// A magnitude known to lie in [known, known + 2^low_plane) steps, reconstructed at the middle
  /// of that interval, signed (FORMAT.md §5); 0 if insignificant. The encoder's closed loop uses
  /// it with low_plane = 0 for what the decoder reconstructs at full rate.
  static double midpoint(std::uint32_t known, int low_plane, bool negative) {
    if (known == 0) return 0.0;
    const double mid = known + 0.5 * static_cast<double>(std::uint64_t{1} << low_plane);
    return negative ? -mid : mid;
  }
};

/// A coefficient in the transform domain from its reconstruction in steps (Decoded::value, or
/// the encoder's own full-rate midpoint): steps * step / w_j. One function for both sides, so
/// that the encoder's closed loop (local frames) sees bit for bit what the decoder will.
inline double dequantize(double steps, double step, double weight) { return steps * step / weight; }

/// Decodes until the stream ends (decoder exhausted) or every plane down to 0 is done.
Decoded decode(const Forest& forest, int components, int top_plane, RangeDecoder& decoder);

}  // namespace meshlift::zerotree
