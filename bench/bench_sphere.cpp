// Spherical parametrization and geometry-image remeshing figures: for each mesh file given,
// the parametrization's time, peak memory, stretch and bijectivity check, then for each image
// size the sampling time and the remesh's distance to the original by the Metro-style surface
// metric (metric.h: area samples and vertices of both surfaces, exact distances both ways,
// symmetric RMS = the larger direction, PSNR = 20·log10(bbox diagonal of the original / RMS),
// Hausdorff relative to the diagonal; CODEC-NOTES §7).
// Usage: bench_sphere MESH... [--sizes 65,129,257]   (one mesh per run for its own peak memory)
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "meshlift/geometry_image.h"
#include "meshlift/mesh_io.h"
#include "meshlift/metric.h"
#include "meshlift/spherical_parametrization.h"

namespace {

double peak_megabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> paths;
  std::vector<int> sizes = {65, 129, 257};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) sizes.push_back(std::stoi(item));
    } else {
      paths.push_back(arg);
    }
  }
  if (paths.empty()) {
    std::fprintf(stderr, "usage: bench_sphere MESH... [--sizes 65,129,257]\n");
    return 2;
  }
  for (const std::string& path : paths) {
    const meshlift::TriangleMesh mesh = meshlift::to_triangle_mesh(meshlift::read_mesh(path));
    const auto start = std::chrono::steady_clock::now();
    const meshlift::SphericalParametrization p = meshlift::parametrize_sphere(mesh);
    const double seconds = seconds_since(start);
    std::printf("%s: %zu vertices, %zu faces: parametrization %.2f s, peak RSS %.1f MB, stretch %.4f, "
                "flipped %zu, degenerate %zu, coverage %.9f\n",
                path.c_str(), mesh.vertex_count(), mesh.face_count(), seconds, peak_megabytes(), p.stretch,
                p.check.flipped_triangles, p.check.degenerate_triangles, p.check.coverage);
    for (const int n : sizes) {
      const auto sample_start = std::chrono::steady_clock::now();
      const meshlift::SemiRegularMesh remesh =
          meshlift::sample_sphere_remesh(mesh, p.sphere, meshlift::geometry_image_levels(n));
      const double sample_seconds = seconds_since(sample_start);
      const meshlift::SurfaceDistance d = meshlift::surface_distance(mesh, remesh.finest());
      std::printf("  n = %d: %u vertices, sampled in %.3f s; RMS original->remesh %.3e, remesh->original %.3e "
                  "(x diagonal), Hausdorff %.3e; PSNR %.2f dB\n",
                  n, remesh.hierarchy.vertex_count(remesh.hierarchy.levels()), sample_seconds,
                  d.reference_to_test.rms / d.diagonal, d.test_to_reference.rms / d.diagonal, d.hausdorff_relative(),
                  d.psnr_db());
    }
    std::printf("  peak RSS after sampling and measuring: %.1f MB\n", peak_megabytes());
    std::fflush(stdout);
  }
  return 0;
}
