// Lifting transform throughput: synthesis and analysis in output vertices per second, one
// thread, per scheme, and the hierarchy's memory per vertex.
//   cmake -B build -DMESHLIFT_BENCH=ON && cmake --build build --target bench_lifting && ./build/bench_lifting
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "test_meshes.h"
#include "meshlift/lifting.h"

using namespace meshlift;

namespace {

// Icosahedron refined twice (320 faces, base valences 5 and 6): the ~500-face base of the issue.
TriangleMesh base_mesh() {
  const TriangleMesh m = test::icosahedron();
  return refine_linear(m, 2).finest();
}

template <class F>
double best_seconds(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

long peak_rss_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

}  // namespace

int main() {
  constexpr int levels = 7;
  const TriangleMesh base = base_mesh();
  const SemiRegularMesh mesh = refine_linear(base, levels);
  const double vertices = mesh.hierarchy.vertex_count(levels);
  std::printf("base: %zu faces, %zu vertices; L = %d; finest: %.0f vertices, %zu faces\n", base.face_count(),
              base.vertex_count(), levels, vertices, mesh.hierarchy.triangles(levels).size() / 3);
  std::printf("hierarchy (all levels' connectivity + coefficient tree): %.1f bytes/vertex\n",
              mesh.hierarchy.memory_bytes() / vertices);
  std::printf("positions: %.1f bytes/vertex\n\n", 24.0);
  std::printf("%-16s %14s %14s %14s %12s\n", "scheme", "synth Mvert/s", "analyze Mvert/s", "tables B/vert", "build s");

  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> noise(-1e-3, 1e-3);
  std::vector<double> coefficients = mesh.positions;
  for (double& x : coefficients) x += noise(rng);

  const WaveletOptions all[] = {{Scheme::linear, false}, {Scheme::linear, true}, {Scheme::butterfly, false},
                                {Scheme::butterfly, true}, {Scheme::loop, false}};
  for (const WaveletOptions& options : all) {
    const auto t0 = std::chrono::steady_clock::now();
    const WaveletTransform transform(mesh.hierarchy, options);
    const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<double> values = coefficients;
    const double analyze = best_seconds(3, [&] {
      values = coefficients;
      transform.analyze(values);
    });
    std::vector<double> work = values;
    const double synth = best_seconds(5, [&] {
      std::copy(values.begin(), values.end(), work.begin());
      transform.synthesize(work);
    });
    // The copies inside the timed lambdas are part of the figure: a conservative measure.
    const std::string name = std::string(to_string(options.scheme)) +
                             (options.mean_preserving_update && options.scheme != Scheme::loop ? "+update" : "");
    std::printf("%-16s %14.1f %14.1f %14.1f %12.2f\n", name.c_str(), vertices / synth / 1e6, vertices / analyze / 1e6,
                transform.memory_bytes() / vertices, build);
  }
  std::printf("\npeak resident memory: %.1f MiB (%.0f bytes per finest vertex)\n", peak_rss_kib() / 1024.0,
              peak_rss_kib() * 1024.0 / vertices);
  return 0;
}
