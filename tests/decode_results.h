// Two decode results compared field by field, arrays bit for bit: what the streaming Decoder,
// decode_into() and decode() must agree on (codec tests and the streaming fuzz target).
#pragma once

#include <cstring>
#include <vector>

#include "meshlift/codec.h"

namespace meshlift::test {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

inline bool same_result(const DecodeResult& a, const DecodeResult& b) {
  if (a.status != b.status || a.message != b.message || a.level != b.level || a.levels != b.levels ||
      a.bit_plane != b.bit_plane || a.base_vertices_decoded != b.base_vertices_decoded ||
      a.bytes_used != b.bytes_used || a.complete != b.complete || a.channels.size() != b.channels.size())
    return false;
  for (std::size_t c = 0; c < a.channels.size(); ++c)
    if (a.channels[c].components != b.channels[c].components || !same_bits(a.channels[c].values, b.channels[c].values))
      return false;
  return same_bits(a.mesh.positions, b.mesh.positions) && same_bits(a.mesh.triangles, b.mesh.triangles);
}

}  // namespace meshlift::test
