// The surface metric's speed on ~100k-triangle pairs: two procedural tori (100,000 and 100,352
// faces, different connectivity) and, when the corpus is present, refined_elephant (88,928
// faces) against a noisy copy of itself. Prints the time with the default sample count
// (BVH builds + sampling + both directions) at 1 and 2 threads.
//   cmake -B build -DMESHLIFT_BENCH=ON && cmake --build build --target bench_metric && ./build/bench_metric
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "meshlift/mesh_io.h"
#include "meshlift/metric.h"
#include "test_meshes.h"

using namespace meshlift;

namespace {

/// User + system CPU time of the process (on a shared machine the wall time also measures the
/// neighbours' load; the CPU time does not).
double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

void run(const char* name, const TriangleMesh& reference, const TriangleMesh& test) {
  for (unsigned threads : {1u, 2u}) {
    MetricOptions options;
    options.threads = threads;
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const SurfaceDistance d = surface_distance(reference, test, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - cpu0;
    const std::size_t points = d.reference_to_test.area_samples + d.reference_to_test.vertex_samples +
                               d.test_to_reference.area_samples + d.test_to_reference.vertex_samples;
    std::printf("%-34s %zu + %zu faces, %u thread%s: %.3f s wall, %.3f s CPU, %zu points (%.2f M queries/s), "
                "PSNR %.3f dB, Hausdorff/diag %.3e\n",
                name, reference.face_count(), test.face_count(), threads, threads > 1 ? "s" : "", seconds, cpu, points,
                static_cast<double>(points) / seconds * 1e-6, d.psnr_db(), d.hausdorff_relative());
  }
}

}  // namespace

int main() {
  const TriangleMesh a = test::perturbed(test::torus(250, 200), 1e-3, 1);  // 100,000 faces
  const TriangleMesh b = test::perturbed(test::torus(224, 224), 1e-3, 2);  // 100,352 faces
  run("tori", a, b);

  const char* corpus = std::getenv("MESHLIFT_CORPUS");
  const std::filesystem::path elephant =
      std::filesystem::path(corpus && *corpus ? corpus : ".cache/corpus/meshes") / "refined_elephant.off";
  if (std::filesystem::exists(elephant)) {
    const TriangleMesh original = to_triangle_mesh(read_mesh(elephant.string()));
    const double diagonal = bounding_box_diagonal(original.positions);
    run("refined_elephant vs noisy copy", original, test::perturbed(original, 1e-4 * diagonal, 3));
  } else {
    std::printf("refined_elephant.off not found (set MESHLIFT_CORPUS; scripts/corpus.sh fetches it)\n");
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak RSS: %.1f MiB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  return 0;
}
