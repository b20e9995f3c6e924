// Codec throughput on a >= 2 M-vertex semi-regular mesh: encode and decode (whole file and a
// ~2 bits/vertex prefix), with the decode split into its stages, and peak memory.
//   cmake -B build -DMESHLIFT_BENCH=ON && cmake --build build --target bench_codec && ./build/bench_codec
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "test_meshes.h"
#include "meshlift/codec.h"

using namespace meshlift;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Icosahedron refined twice (320 faces), Loop-subdivided 7 levels and displaced by a smooth
// bumpy field plus a small deterministic roughness: 2.6 M vertices with detail at every level.
SemiRegularMesh test_mesh(int levels) {
  const TriangleMesh m = test::icosahedron();
  const TriangleMesh base = refine_linear(m, 2).finest();
  SemiRegularMesh mesh = refine_linear(base, levels);
  std::fill(mesh.positions.begin() + static_cast<std::ptrdiff_t>(base.positions.size()), mesh.positions.end(), 0.0);
  WaveletTransform(mesh.hierarchy, {Scheme::loop, false}).synthesize(mesh.positions);
  for (std::size_t i = 0; i < mesh.positions.size(); i += 3) {
    const double x = mesh.positions[i], y = mesh.positions[i + 1], z = mesh.positions[i + 2];
    const std::uint64_t hash = (i * 0x9E3779B97F4A7C15ull) >> 40;
    const double rough = 2e-4 * (static_cast<double>(hash % 1000) / 1000.0 - 0.5);
    const double bump = 1 + 0.05 * std::sin(7 * x + 1) * std::cos(5 * y) + 0.02 * std::sin(23 * z) + rough;
    for (int k = 0; k < 3; ++k) mesh.positions[i + k] *= bump;
  }
  return mesh;
}

}  // namespace

int main() {
  constexpr int levels = 7;
  const SemiRegularMesh mesh = test_mesh(levels);
  const double V = mesh.hierarchy.vertex_count(levels);
  std::printf("mesh: %.0f vertices, %d levels, base %u vertices\n", V, levels, mesh.hierarchy.vertex_count(0));

  auto t0 = std::chrono::steady_clock::now();
  const auto file = encode(mesh, {});
  const double encode_s = seconds_since(t0);
  std::printf("encode: %.2f s (%.2f M vertices/s), %zu bytes, %.2f bits/vertex at 16-bit precision\n", encode_s,
              V / encode_s / 1e6, file.size(), 8.0 * file.size() / V);

  const std::size_t two_bpv = static_cast<std::size_t>(2 * V / 8);
  for (std::size_t budget : {two_bpv, file.size()}) {
    DecodeOptions o;
    o.max_bytes = budget;
    double best = 1e300;
    DecodeResult r;
    for (int rep = 0; rep < 3; ++rep) {
      t0 = std::chrono::steady_clock::now();
      r = decode(file, o);
      best = std::min(best, seconds_since(t0));
    }
    std::printf("decode %zu bytes (%.2f bpv): %.3f s, %.2f M output vertices/s, bit plane %d\n", r.bytes_used,
                8.0 * r.bytes_used / V, best, V / best / 1e6, r.bit_plane);
  }

  // Stages of a decode, timed separately.
  t0 = std::chrono::steady_clock::now();
  const SemiRegularHierarchy h(mesh.hierarchy.topology(0), levels);
  const double hierarchy_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const WaveletTransform transform(h, {Scheme::loop, false});
  const double tables_s = seconds_since(t0);
  std::vector<double> values = mesh.positions;
  t0 = std::chrono::steady_clock::now();
  transform.synthesize(values);
  const double synthesis_s = seconds_since(t0);
  std::printf("stages: hierarchy %.3f s, stencil tables %.3f s, synthesis %.3f s (the rest of a decode is the\n"
              "        container, base mesh and coefficient decoding)\n",
              hierarchy_s, tables_s, synthesis_s);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory: %.0f MiB (%.0f bytes per vertex, encoder and decoder together)\n",
              usage.ru_maxrss / 1024.0, usage.ru_maxrss * 1024.0 / V);
  return 0;
}
