// Base mesh connectivity: lossless, through the adaptive range coder. Each face's corners are
// coded as zigzag deltas (first corner from the previous face's first corner, the other two from
// the first) with an adaptive Elias-gamma binarization. This is the simple floor; a valence
// coder would do better on large base meshes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/range_coder.h"

namespace meshlift::base_mesh {

/// Adaptive Elias-gamma code of an unsigned integer: the bit length in unary (one model per
/// position), then the bits below the leading one (the top two modelled per length, the rest direct).
class UintCoder {
 public:
  void encode(RangeEncoder& encoder, std::uint32_t value);
  /// Returns false if the stream ended (decoder exhausted) or the code is not a valid number.
  bool decode(RangeDecoder& decoder, std::uint32_t& value);

 private:
  BitModel length_[33];
  BitModel mantissa_[33][3];
};

std::vector<std::uint8_t> encode_faces(std::span<const std::uint32_t> triangles);

/// Decodes `face_count` faces over `vertex_count` vertices. Returns false on a truncated stream
/// or an index out of range (the caller reports corrupt).
bool decode_faces(std::span<const std::uint8_t> bytes, std::uint32_t vertex_count, std::uint32_t face_count,
                  std::vector<std::uint32_t>& triangles);

}  // namespace meshlift::base_mesh
