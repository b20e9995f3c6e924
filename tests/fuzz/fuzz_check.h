// Shared by the fuzz targets: what every decode must satisfy, checked with abort() so a
// violation is a crash libFuzzer records (and the replay programs report) like any other.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "meshlift/codec.h"

namespace meshlift::fuzz {

/// Limits small enough that one input can never take more than ~100 MB or a few seconds;
/// the caps themselves are what the fuzzers test, not their default values.
inline DecodeOptions fuzz_options() {
  DecodeOptions options;
  options.limits.max_vertices = std::uint64_t{1} << 18;
  options.limits.max_base_vertices = std::uint64_t{1} << 14;
  options.limits.max_base_faces = std::uint64_t{1} << 15;
  return options;
}

[[noreturn]] inline void violated(const char* what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

/// ok: a mesh with finite coordinates and every index in range; otherwise a numbered status
/// (1..8), a message and an empty mesh.
inline void check_result(const DecodeResult& r) {
  if (r.status == Status::ok) {
    const TriangleMesh& m = r.mesh;
    if (m.positions.size() % 3 != 0 || m.triangles.size() % 3 != 0) violated("array sizes");
    if (m.triangles.empty()) violated("ok without faces");
    for (double x : m.positions)
      if (!std::isfinite(x)) violated("non-finite coordinate");
    for (std::uint32_t i : m.triangles)
      if (i >= m.vertex_count()) violated("index out of range");
    if (r.level < 0 || r.level > r.levels) violated("level out of range");
    for (const VertexChannel& c : r.channels) {
      if (c.components < 1 || c.values.size() != m.vertex_count() * static_cast<std::size_t>(c.components))
        violated("channel size");
      for (double x : c.values)
        if (!std::isfinite(x)) violated("non-finite channel value");
    }
  } else {
    const int code = static_cast<int>(r.status);
    if (code < 1 || code > 8) violated("unnumbered status");
    if (r.message.empty()) violated("error without a message");
    if (!r.mesh.positions.empty() || !r.mesh.triangles.empty() || !r.channels.empty()) violated("error with a mesh");
  }
}

}  // namespace meshlift::fuzz
