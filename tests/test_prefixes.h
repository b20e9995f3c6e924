// Prefix decoding checks shared by the codec tests (procedural and real-mesh streams).
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "meshlift/codec.h"

namespace meshlift::test {

/// RMS distance between two vertex arrays of the same size (xyz per vertex).
inline double rms_error(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size() / 3));
}

/// Cuts `file` at about `cuts` evenly spaced lengths after its header and base mesh. Every prefix
/// must decode to a mesh with `reference`'s vertices, and the RMS error must not grow by more
/// than 5 % from one cut to the next (the midpoint reconstruction of a half-read plane can be
/// marginally worse than the plane above for a few coefficients). Returns (bytes, RMS) per cut.
inline std::vector<std::pair<std::size_t, double>> check_prefixes(const std::vector<std::uint8_t>& file,
                                                                  const std::vector<double>& reference, int cuts) {
  const StreamInfo info = inspect(file);
  REQUIRE(info.status == Status::ok);
  REQUIRE(info.chunks.size() >= 3);
  const std::size_t first = info.chunks[2].offset + 8;  // HEAD and BASE complete, COEF begun
  const std::size_t stride = std::max<std::size_t>(1, (file.size() - first) / static_cast<std::size_t>(cuts - 1));
  std::vector<std::pair<std::size_t, double>> errors;
  double previous = 1e300;
  for (std::size_t cut = first; cut <= file.size(); cut += stride) {
    DecodeOptions o;
    o.max_bytes = cut;
    const DecodeResult r = decode(file, o);
    INFO("cut at " << cut);
    REQUIRE(r.status == Status::ok);
    REQUIRE(r.mesh.positions.size() == reference.size());
    const double error = rms_error(r.mesh.positions, reference);
    CHECK(error <= previous * 1.05 + 1e-15);
    previous = std::min(previous, error);
    errors.emplace_back(cut, error);
  }
  return errors;
}

}  // namespace meshlift::test
