// Base mesh connectivity (FORMAT.md §4): a face-by-face traversal in the spirit of Edgebreaker
// (Rossignac 1999). Faces are visited across "gates", the open edges of the region coded so far,
// newest gate first (so the traversal spirals like Edgebreaker's); for each gate one symbol says
// what lies across it: the boundary, a face whose third vertex closes the front on the right or
// on the left (an open edge at a gate vertex), a face with a vertex never seen before, or
// (rarely: where the front touches itself) any other vertex, coded as how many open edges along
// the front from the gate it lies (most often two), else as how many labels back it was given.
// Contexts: the previous symbol and the faces already around the gate vertex; the models start
// from probabilities measured on decimated bases. Vertices are numbered in the order the
// traversal first meets them and faces in the order it codes them, so a new vertex costs only its
// symbol: `canonical_order` (codec.h) puts a mesh in that order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/range_coder.h"

namespace meshlift::base_mesh {

/// Adaptive Elias-gamma code of an unsigned integer: the bit length in unary (one model per
/// position), then the bits below the leading one (the top three modelled per length, the rest direct).
class UintCoder {
 public:
  void encode(RangeEncoder& encoder, std::uint32_t value);
  /// Returns false if the stream ended (decoder exhausted) or the code is not a valid number.
  bool decode(RangeDecoder& decoder, std::uint32_t& value);

 private:
  BitModel length_[33];
  BitModel mantissa_[33][3];
};

/// The traversal order of a triangle list: face k of the coded order is old face `face[k]`
/// rotated so that its corner 0 is old corner `rotation[k]`; old vertex v gets label `label[v]`
/// (vertices no face uses get the last labels, in their old order).
struct CodingOrder {
  std::vector<std::uint32_t> face, rotation, label;
  /// How the split vertices were coded (FORMAT.md §4): by a walk left of the gate, right of it,
  /// or by their label.
  std::size_t left_walks = 0, right_walks = 0, split_labels = 0;
};

/// Codes the faces (which must form a manifold, consistently oriented mesh over `vertex_count`
/// vertices) and returns the bytes; `order` receives the traversal order, which the decoder
/// reproduces: decode_faces returns the faces relabelled and reordered by it.
std::vector<std::uint8_t> encode_faces(std::span<const std::uint32_t> triangles, std::uint32_t vertex_count,
                                       CodingOrder* order = nullptr);

/// Decodes `face_count` faces over `vertex_count` vertices. Returns false on a truncated stream
/// or an impossible symbol (the caller reports corrupt).
bool decode_faces(std::span<const std::uint8_t> bytes, std::uint32_t vertex_count, std::uint32_t face_count,
                  std::vector<std::uint32_t>& triangles);

}  // namespace meshlift::base_mesh
