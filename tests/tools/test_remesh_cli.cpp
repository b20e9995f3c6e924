// meshlift remesh, and encode on meshes without subdivision connectivity.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "test_meshes.h"

namespace fs = std::filesystem;

namespace {

using meshlift::test::run_cli;

/// A UV sphere with bumps (no subdivision connectivity: poles of valence `sides`), as OFF; with
/// `quads`, the bands between rings are quads.
fs::path write_bumpy_sphere(const fs::path& path, int rings = 24, int sides = 32, bool quads = false) {
  std::ofstream f(path);
  const int vertices = 2 + (rings - 1) * sides, faces = (quads ? sides * rings : 2 * sides * (rings - 1));
  f << "OFF\n" << vertices << " " << faces << " 0\n";
  auto point = [&](double theta, double phi) {
    const double r = 1 + 0.1 * std::sin(3 * theta) * std::cos(2 * phi);
    f << r * std::sin(theta) * std::cos(phi) << " " << r * std::sin(theta) * std::sin(phi) << " " << r * std::cos(theta) << "\n";
  };
  point(0, 0);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sides; ++j) point(M_PI * i / rings, 2 * M_PI * j / sides);
  point(M_PI, 0);
  auto ring = [&](int i, int j) { return 1 + (i - 1) * sides + (j % sides); };
  const int south = vertices - 1;
  for (int j = 0; j < sides; ++j) f << "3 0 " << ring(1, j) << " " << ring(1, j + 1) << "\n";
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      if (quads) {
        f << "4 " << ring(i, j) << " " << ring(i + 1, j) << " " << ring(i + 1, j + 1) << " " << ring(i, j + 1) << "\n";
        continue;
      }
      f << "3 " << ring(i, j) << " " << ring(i + 1, j) << " " << ring(i + 1, j + 1) << "\n";
      f << "3 " << ring(i, j) << " " << ring(i + 1, j + 1) << " " << ring(i, j + 1) << "\n";
    }
  for (int j = 0; j < sides; ++j) f << "3 " << south << " " << ring(rings - 1, j + 1) << " " << ring(rings - 1, j) << "\n";
  return path;
}

/// The number after "PSNR" and an optional colon (remesh prints "PSNR 68.6 dB", compare "PSNR: 44.8 dB").
double psnr_in(const std::string& output) {
  auto at = output.find("PSNR");
  REQUIRE(at != std::string::npos);
  at += 4;
  if (output[at] == ':') ++at;
  return std::stod(output.substr(at));
}

}  // namespace

TEST_CASE("remesh writes a level-ordered semi-regular mesh that encode takes over as it is", "[cli][remesh]") {
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli");
  const fs::path in = write_bumpy_sphere(dir / "bumpy.off");
  const std::string out = (dir / "bumpy_sr.ply").string();
  const auto remeshed = run_cli("remesh " + in.string() + " -o " + out + " --levels 2 --binary");
  INFO(remeshed.output);
  REQUIRE(remeshed.exit_code == 0);
  CHECK_THAT(remeshed.output, Catch::Contains("decimation remesh"));
  CHECK_THAT(remeshed.output, Catch::Contains("0 flipped and 0 degenerate"));
  CHECK(psnr_in(remeshed.output) > 60);
  REQUIRE(fs::exists(out));
  // Its hierarchy comes back from the file: encode does not remesh it again.
  const auto encoded = run_cli("encode " + out + " -o " + (dir / "bumpy.mlz").string() + " --scheme butterfly");
  INFO(encoded.output);
  REQUIRE(encoded.exit_code == 0);
  CHECK_THAT(encoded.output, Catch::Contains("already semi-regular"));
  CHECK_THAT(encoded.output, Catch::Contains("2 levels"));
  // The sphere remesher on the same closed genus-0 input: the octahedron refined twice.
  const auto sphere = run_cli("remesh " + in.string() + " -o " + (dir / "bumpy_sphere.ply").string() + " --method sphere --levels 3");
  INFO(sphere.output);
  REQUIRE(sphere.exit_code == 0);
  CHECK_THAT(sphere.output, Catch::Contains("sphere remesh: base 6, 3 levels, 258 vertices"));
  fs::remove_all(dir);
}

TEST_CASE("encode remeshes a mesh without subdivision connectivity and refuses bad input", "[cli][remesh]") {
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli2");
  const fs::path in = write_bumpy_sphere(dir / "bumpy.off");
  const std::string mlz = (dir / "bumpy.mlz").string(), decoded = (dir / "decoded.ply").string();
  const auto encoded = run_cli("encode " + in.string() + " -o " + mlz + " --levels 2 --bpv 8 --scheme butterfly");
  INFO(encoded.output);
  REQUIRE(encoded.exit_code == 0);
  CHECK_THAT(encoded.output, Catch::Contains("decimation remesh"));
  REQUIRE(run_cli("decode " + mlz + " -o " + decoded).exit_code == 0);
  const auto compared = run_cli("compare " + in.string() + " " + decoded);
  INFO(compared.output);
  REQUIRE(compared.exit_code == 0);
  CHECK(psnr_in(compared.output) > 50);  // 8 bits per input vertex, against the original
  // The sphere remesher names why it cannot take an open mesh, and points to decimate.
  const fs::path open = dir / "open.off";
  std::ofstream(open) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  const auto refused = run_cli("remesh " + open.string() + " -o " + (dir / "x.ply").string() + " --method sphere");
  CHECK(refused.exit_code == 3);
  CHECK_THAT(refused.output, Catch::Contains("not closed"));
  CHECK_THAT(refused.output, Catch::Contains("decimate"));
  CHECK_FALSE(fs::exists(dir / "x.ply"));
  fs::remove_all(dir);
}

TEST_CASE("remesh and encode split a quad mesh's faces into triangles first, and say so", "[cli][remesh]") {
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli_quads");
  const fs::path in = write_bumpy_sphere(dir / "quads.off", 24, 32, true);
  const auto info = run_cli("info " + in.string());
  REQUIRE(info.exit_code == 0);
  CHECK_THAT(info.output, Catch::Contains("triangles required"));
  CHECK_THAT(info.output, Catch::Contains("as encode takes it:      704 quads and 0 larger polygons split into 1408 "
                                          "triangles; triangle codec ok"));
  const auto remeshed = run_cli("remesh " + in.string() + " -o " + (dir / "r.ply").string());
  INFO(remeshed.output);
  REQUIRE(remeshed.exit_code == 0);
  // 22 bands of 32 quads between the polar caps' triangles.
  CHECK_THAT(remeshed.output, Catch::Contains("704 quads and 0 larger polygons split into 1408 triangles"));
  CHECK(psnr_in(remeshed.output.substr(remeshed.output.find("remesh error"))) > 60);
  const std::string mlz = (dir / "q.mlz").string(), decoded = (dir / "q.ply").string();
  REQUIRE(run_cli("encode " + in.string() + " -o " + mlz + " --bpv 8").exit_code == 0);
  REQUIRE(run_cli("decode " + mlz + " -o " + decoded).exit_code == 0);
  const auto compared = run_cli("compare " + in.string() + " " + decoded);
  INFO(compared.output);
  REQUIRE(compared.exit_code == 0);
  CHECK(psnr_in(compared.output.substr(compared.output.find("PSNR"))) > 50);
  fs::remove_all(dir);
}

TEST_CASE("remesh --density sets the vertex count and --least-squares brings the remesh closer", "[cli][remesh]") {
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli3");
  const fs::path in = write_bumpy_sphere(dir / "bumpy.off");
  auto remesh = [&](const std::string& options) {
    const auto r = run_cli("remesh " + in.string() + " -o " + (dir / "out.ply").string() + " --levels 2 " + options);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    // "... 12345 vertices (1.99x the input) ..."
    const auto x = r.output.find("x the input");
    REQUIRE(x != std::string::npos);
    const auto open = r.output.rfind('(', x);
    return std::make_pair(std::stod(r.output.substr(open + 1, x - open - 1)), psnr_in(r.output));
  };
  const auto [ratio2, psnr2] = remesh("--density 2");
  const auto [ratio4, psnr4] = remesh("--density 4");
  const auto [ratio4_on_surface, psnr4_on_surface] = remesh("--density 4 --least-squares 0");
  CHECK(ratio2 > 1.7);
  CHECK(ratio2 < 2.3);
  CHECK(ratio4 > 3.5);
  CHECK(ratio4 < 4.5);
  CHECK(ratio4_on_surface == ratio4);
  CHECK(psnr4 > psnr2);
  // The least-squares rounds centre the chord error on the surface: measurably closer.
  CHECK(psnr4 > psnr4_on_surface + 1);
  // Out-of-range values are refused before anything is read or written.
  for (const char* bad : {"--density 0.5", "--density many", "--least-squares -1"}) {
    const auto r = run_cli("remesh " + in.string() + " -o " + (dir / "bad.ply").string() + " " + bad);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_FALSE(fs::exists(dir / "bad.ply"));
  }
  fs::remove_all(dir);
}

TEST_CASE("remesh says when its levels make far more vertices than the density asks for", "[cli][remesh]") {
  // 738 vertices: six levels over the sphere's smallest automatic base (8 vertices) make 24,578.
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli_deep");
  const fs::path in = write_bumpy_sphere(dir / "bumpy.off");
  const auto deep = run_cli("remesh " + in.string() + " -o " + (dir / "deep.ply").string() + " --levels 6");
  INFO(deep.output);
  REQUIRE(deep.exit_code == 0);
  CHECK_THAT(deep.output, Catch::Contains("note: 6 levels over a base of 8 vertices make 33x the input's vertices (the "
                                          "fewest the automatic base size takes for this mesh's topology); each level "
                                          "fewer divides that by about 4"));
  // The remesh of 5 levels has that base too (RemeshOptions::level_by_level_from).
  CHECK_THAT(deep.output, Catch::Contains("level 6 placed on the finished remesh of 5 levels, which has the same base"));
  const auto shallow = run_cli("remesh " + in.string() + " -o " + (dir / "shallow.ply").string() + " --levels 3");
  INFO(shallow.output);
  REQUIRE(shallow.exit_code == 0);
  CHECK_THAT(shallow.output, !Catch::Contains("levels over a base"));
  fs::remove_all(dir);
}

TEST_CASE("remesh refines a cube as it is, and says so", "[cli][remesh]") {
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli_cube");
  const fs::path in = dir / "cube.off";
  std::ofstream(in) << "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                       "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const auto r = run_cli("remesh " + in.string() + " -o " + (dir / "cube.ply").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("base 8, 3 levels, 386 vertices"));
  CHECK_THAT(r.output, Catch::Contains("the base is the input itself and the remesh its midpoint refinement, on the "
                                       "input (a small input"));
  CHECK_THAT(r.output, Catch::Contains("0 flipped and 0 degenerate"));
  CHECK(psnr_in(r.output.substr(r.output.find("remesh error"))) > 200);  // rounding only (was 57 dB)
  CHECK_THAT(r.output, !Catch::Contains("levels over a base"));
  fs::remove_all(dir);
}

TEST_CASE("remesh --snap puts a faceted input's corners and creases back into the remesh", "[cli][remesh][snap]") {
  // A coarse bumpy sphere (10 rings of 12 faces: its edges turn by 15-40 degrees) remeshed at
  // ~8x: without --snap the remesh cuts every crease by a chord.
  const fs::path dir = meshlift::test::cli_scratch("remesh_cli_snap");
  const fs::path in = write_bumpy_sphere(dir / "faceted.off", 10, 12);
  auto remesh = [&](const std::string& options) {
    const auto r = run_cli("remesh " + in.string() + " -o " + (dir / "out.ply").string() + " --density 8 " + options);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    return std::make_pair(psnr_in(r.output), r.output.find(": snap: ") != std::string::npos);
  };
  const auto [plain_db, plain_said] = remesh("");
  const auto [snapped_db, snapped_said] = remesh("--snap");
  INFO("without --snap " << plain_db << " dB, with " << snapped_db);
  CHECK_FALSE(plain_said);
  CHECK(snapped_said);
  CHECK(snapped_db > plain_db + 1);
  fs::remove_all(dir);
}

TEST_CASE("encode measures finer tangents where the remesh follows feature lines, and keeps what it measures closer",
          "[cli][remesh][corpus]") {
  // Two CAD parts whose remeshes follow their feature lines: on fandisk the tangents at shift 1
  // decode closer to the input at 1-8 bits per input vertex (its creases pay for tangential error),
  // on blade those at the default shift 2 do (docs/RESULTS.md, "Finer tangents where the remesh
  // follows creases"). A smooth mesh is not measured, and a --tangent-shift given is kept.
  const fs::path dir = meshlift::test::cli_scratch("encode_cli_tangents");
  // Encodes `input` with `options`; returns the chosen shift's line (empty if none) and the
  // tangent step the file's header holds, as `info` prints it.
  auto encode = [&](const std::string& input, const std::string& options) {
    const fs::path out = dir / "out.mlz";
    const auto r = run_cli("encode " + input + " -o " + out.string() + " " + options);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const auto info = run_cli("info " + out.string());
    REQUIRE(info.exit_code == 0);
    const auto at = r.output.find("follows feature lines");
    const std::string line = at == std::string::npos ? "" : r.output.substr(at, r.output.find('\n', at) - at);
    const auto step = info.output.find("tangents at step x 2^");
    REQUIRE(step != std::string::npos);
    return std::make_pair(line, std::stoi(info.output.substr(step + 21)));
  };
  // "... tangent shift S (... A dB from the input on average, against B with shift T)": A >= B.
  auto chosen_is_closer = [](const std::string& line) {
    const auto a = line.find("vertex: ") + 8, b = line.find("against ") + 8;
    return std::stod(line.substr(a)) >= std::stod(line.substr(b));
  };
  const std::string fandisk = meshlift::test::corpus_mesh_path("fandisk"), blade = meshlift::test::corpus_mesh_path("blade");
  {
    const auto [line, shift] = encode(fandisk, "");
    INFO(line);
    CHECK_THAT(line, Catch::Contains("tangent shift 1 ("));
    CHECK(shift == 1);
    CHECK(chosen_is_closer(line));
  }
  {
    const auto [line, shift] = encode(blade, "");
    INFO(line);
    CHECK_THAT(line, Catch::Contains("tangent shift 2 ("));
    CHECK(shift == 2);
    CHECK(chosen_is_closer(line));
  }
  {
    const auto [line, shift] = encode(fandisk, "--tangent-shift 2");
    CHECK(line.empty());
    CHECK(shift == 2);
  }
  {
    const auto [line, shift] = encode(write_bumpy_sphere(dir / "smooth.off").string(), "");
    CHECK(line.empty());
    CHECK(shift == 2);
  }
  fs::remove_all(dir);
}
