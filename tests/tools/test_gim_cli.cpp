// `meshlift gim`: geometry images written and read back through the built executable.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>
#include <algorithm>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_run.h"
#include "meshlift/mesh_io.h"

namespace fs = std::filesystem;

namespace {

meshlift::test::CliRun run_gim(const std::string& args) { return meshlift::test::run_cli("gim " + args); }
std::filesystem::path gim_scratch() { return meshlift::test::cli_scratch("gim_test"); }

/// An OFF octahedron with its vertices on the ellipsoid x²/4 + y² + z²/0.25 = 1, refined and
/// pushed onto it (`levels` 1:4 splits): written by hand so the test needs no library call.
fs::path write_ellipsoid_off(const fs::path& path) {
  // Start from the octahedron; each split moves midpoints onto the unit sphere.
  std::vector<double> p = {1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  std::vector<int> t = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 1, 0, 5, 2, 1, 5, 3, 2, 5, 0, 3, 5};
  for (int level = 0; level < 3; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = midpoint.find(key); it != midpoint.end()) return it->second;
      double m[3], r = 0;
      for (int k = 0; k < 3; ++k) {
        m[k] = 0.5 * (p[3 * a + k] + p[3 * b + k]);
        r += m[k] * m[k];
      }
      for (int k = 0; k < 3; ++k) p.push_back(m[k] / std::sqrt(r));
      return midpoint[key] = static_cast<int>(p.size() / 3 - 1);
    };
    std::vector<int> refined;
    for (std::size_t f = 0; f < t.size(); f += 3) {
      const int a = t[f], b = t[f + 1], c = t[f + 2], ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      refined.insert(refined.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    t.swap(refined);
  }
  std::ofstream out(path);
  out << "OFF\n" << p.size() / 3 << " " << t.size() / 3 << " 0\n";
  for (std::size_t v = 0; v < p.size(); v += 3) out << 2 * p[v] << " " << p[v + 1] << " " << 0.5 * p[v + 2] << "\n";
  for (std::size_t f = 0; f < t.size(); f += 3) out << "3 " << t[f] << " " << t[f + 1] << " " << t[f + 2] << "\n";
  return path;
}

}  // namespace

TEST_CASE("gim writes PNG and float images of an ellipsoid and reads them back as meshes", "[cli][sphere]") {
  const fs::path dir = gim_scratch();
  const fs::path in = write_ellipsoid_off(dir / "ellipsoid.off");
  const auto png = run_gim(in.string() + " -o " + (dir / "e.png").string() + " --size 17");
  INFO(png.output);
  REQUIRE(png.exit_code == 0);
  CHECK_THAT(png.output, Catch::Contains("0 flipped and 0 degenerate triangles"));
  const auto gim = run_gim(in.string() + " -o " + (dir / "e.gim").string() + " --size 17");
  REQUIRE(gim.exit_code == 0);
  // .gim: header + 17·17·3 float64 samples.
  CHECK(fs::file_size(dir / "e.gim") == 20 + 17 * 17 * 3 * 8);

  REQUIRE(run_gim("--to-mesh " + (dir / "e.png").string() + " -o " + (dir / "from_png.off").string()).exit_code == 0);
  REQUIRE(run_gim("--to-mesh " + (dir / "e.gim").string() + " -o " + (dir / "from_gim.off").string()).exit_code == 0);
  const meshlift::PolygonMesh from_png = meshlift::read_mesh((dir / "from_png.off").string());
  const meshlift::PolygonMesh from_gim = meshlift::read_mesh((dir / "from_gim.off").string());
  // L = 3: 4^4 + 2 vertices, 8·4^3 faces.
  REQUIRE(from_gim.vertex_count() == 258);
  REQUIRE(from_gim.face_count() == 512);
  REQUIRE(from_png.face_indices == from_gim.face_indices);
  // Every vertex on the input's flat faces, so within their chord error (< 0.04 here) of the
  // ellipsoid; the PNG's within 16-bit quantization (box extent / 131070, plus float rounding
  // of the OFF text) of the float image.
  const double extent[3] = {4, 2, 1};
  for (std::size_t v = 0; v < from_gim.vertex_count(); ++v) {
    const double* x = &from_gim.positions[3 * v];
    const double f = x[0] * x[0] / 4 + x[1] * x[1] + x[2] * x[2] / 0.25;
    REQUIRE(f <= 1.0 + 1e-6);
    REQUIRE(f > 0.85);
    for (int k = 0; k < 3; ++k) REQUIRE(std::fabs(from_png.positions[3 * v + k] - x[k]) <= extent[k] / 131070 + 1e-6);
  }
}

TEST_CASE("gim names what makes a mesh unsuitable and points to decimation", "[cli][sphere]") {
  const fs::path dir = gim_scratch();
  // A tetrahedron with one face missing: open.
  std::ofstream(dir / "open.off") << "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const auto open = run_gim((dir / "open.off").string() + " -o " + (dir / "open.png").string());
  CHECK(open.exit_code == 3);
  CHECK_THAT(open.output, Catch::Contains("not closed (3 boundary edges in 1 loops)"));
  CHECK_THAT(open.output, Catch::Contains("use --remesh decimate"));
  CHECK_FALSE(fs::exists(dir / "open.png"));
  // Bad sizes and a non-image are refused.
  std::ofstream(dir / "tet.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  CHECK(run_gim((dir / "tet.off").string() + " -o " + (dir / "t.png").string() + " --size 100").exit_code == 2);
  std::ofstream(dir / "junk.gim") << "not an image";
  const auto junk = run_gim("--to-mesh " + (dir / "junk.gim").string() + " -o " + (dir / "junk.off").string());
  CHECK(junk.exit_code == 3);
  CHECK_THAT(junk.output, Catch::Contains("bad magic"));
  // The tetrahedron itself works: the smallest closed genus-0 mesh.
  CHECK(run_gim((dir / "tet.off").string() + " -o " + (dir / "t.gim").string() + " --size 9").exit_code == 0);
}
