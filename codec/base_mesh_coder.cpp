#include "base_mesh_coder.h"

namespace meshlift::base_mesh {
namespace {

std::uint32_t zigzag(std::int64_t v) { return static_cast<std::uint32_t>(v >= 0 ? 2 * v : -2 * v - 1); }
std::int64_t unzigzag(std::uint32_t u) { return (u & 1) ? -static_cast<std::int64_t>(u >> 1) - 1 : u >> 1; }

}  // namespace

// value + 1 = 1 b_{n-1} ... b_0: n zeros-then-one in unary (models by position), then n bits.
void UintCoder::encode(RangeEncoder& encoder, std::uint32_t value) {
  const std::uint64_t v = std::uint64_t{value} + 1;
  int n = 0;
  while ((v >> (n + 1)) != 0) ++n;
  for (int i = 0; i < n; ++i) encoder.encode(length_[i], 0);
  encoder.encode(length_[n], 1);
  for (int i = n - 1; i >= 0; --i) {
    const int bit = static_cast<int>((v >> i) & 1);
    const int rank = n - 1 - i;
    if (rank < 3)
      encoder.encode(mantissa_[n][rank], bit);
    else
      encoder.encode_direct(static_cast<std::uint32_t>(bit), 1);
  }
}

bool UintCoder::decode(RangeDecoder& decoder, std::uint32_t& value) {
  int n = 0;
  while (true) {
    if (n > 32) return false;
    const int stop = decoder.decode(length_[n]);
    if (decoder.exhausted()) return false;
    if (stop) break;
    ++n;
  }
  std::uint64_t v = 1;
  for (int i = n - 1; i >= 0; --i) {
    const int rank = n - 1 - i;
    const int bit = rank < 3 ? decoder.decode(mantissa_[n][rank]) : static_cast<int>(decoder.decode_direct(1));
    if (decoder.exhausted()) return false;
    v = v << 1 | static_cast<std::uint64_t>(bit);
  }
  if (v - 1 > 0xffffffffu) return false;
  value = static_cast<std::uint32_t>(v - 1);
  return true;
}

std::vector<std::uint8_t> encode_faces(std::span<const std::uint32_t> triangles) {
  RangeEncoder encoder;
  UintCoder first, others;
  std::int64_t previous = 0;
  for (std::size_t f = 0; f + 2 < triangles.size(); f += 3) {
    const std::int64_t a = triangles[f];
    first.encode(encoder, zigzag(a - previous));
    others.encode(encoder, zigzag(static_cast<std::int64_t>(triangles[f + 1]) - a));
    others.encode(encoder, zigzag(static_cast<std::int64_t>(triangles[f + 2]) - a));
    previous = a;
  }
  return encoder.finish();
}

bool decode_faces(std::span<const std::uint8_t> bytes, std::uint32_t vertex_count, std::uint32_t face_count,
                  std::vector<std::uint32_t>& triangles) {
  RangeDecoder decoder(bytes);
  UintCoder first, others;
  triangles.clear();
  triangles.reserve(std::size_t{face_count} * 3);
  std::int64_t previous = 0;
  for (std::uint32_t f = 0; f < face_count; ++f) {
    std::uint32_t u = 0;
    if (!first.decode(decoder, u)) return false;
    const std::int64_t a = previous + unzigzag(u);
    if (a < 0 || a >= vertex_count) return false;
    triangles.push_back(static_cast<std::uint32_t>(a));
    for (int k = 0; k < 2; ++k) {
      if (!others.decode(decoder, u)) return false;
      const std::int64_t b = a + unzigzag(u);
      if (b < 0 || b >= vertex_count) return false;
      triangles.push_back(static_cast<std::uint32_t>(b));
    }
    previous = a;
  }
  return true;
}

}  // namespace meshlift::base_mesh
