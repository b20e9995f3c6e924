// Spherical parametrization and geometry-image remeshing figures: for each mesh file given,
// the parametrization's time, peak memory, stretch and bijectivity check, then the sampling time
// for each image size.  Usage: bench_sphere MESH... [--sizes 65,129,257]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "meshlift/geometry_image.h"
#include "meshlift/mesh_io.h"
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
      std::printf("  n = %d: %u vertices, sampled in %.3f s\n", n,
                  remesh.hierarchy.vertex_count(remesh.hierarchy.levels()), seconds_since(sample_start));
    }
    std::fflush(stdout);
  }
  return 0;
}
