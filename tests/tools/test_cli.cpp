// Drives the built `meshlift` executable: exit codes, one-line messages, files left untouched.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>

#include "cli_run.h"

namespace fs = std::filesystem;

namespace {

using Run = meshlift::test::CliRun;
Run run(const std::string& args) { return meshlift::test::run_cli(args); }
fs::path scratch() { return meshlift::test::cli_scratch("cli_test"); }

fs::path write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A tetrahedron, consistently oriented, as OFF text.
const char* kTetrahedron = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

long count_lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

/// An OFF file as the CLI writes it: its coordinates and each face's corners, in file order.
struct OffFile {
  std::vector<double> positions;
  std::vector<std::vector<int>> faces;
};
OffFile read_off(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string magic;
  int vertices = 0, faces = 0, edges = 0;
  in >> magic >> vertices >> faces >> edges;
  OffFile off{std::vector<double>(3 * static_cast<std::size_t>(vertices)), std::vector<std::vector<int>>(faces)};
  for (double& x : off.positions) in >> x;
  for (std::vector<int>& face : off.faces) {
    int n = 0;
    in >> n;
    face.resize(static_cast<std::size_t>(n));
    for (int& corner : face) in >> corner;
  }
  return off;
}

/// The largest difference between two coordinate arrays of the same length.
double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

TEST_CASE("subdivide writes the refined mesh and refuses to overwrite its input", "[cli]") {
  const fs::path dir = scratch();
  const fs::path in = write_file(dir / "tet.off", kTetrahedron);
  const auto ok = run("subdivide " + in.string() + " -o " + (dir / "tet_loop.off").string() + " --scheme loop --levels 2");
  REQUIRE(ok.exit_code == 0);
  // V_2 = 4 + 6 + 24 = 34 vertices, F_2 = 4 * 16 = 64 faces.
  std::istringstream header(read_file(dir / "tet_loop.off"));
  std::string magic;
  int v = 0, f = 0;
  header >> magic >> v >> f;
  CHECK(v == 34);
  CHECK(f == 64);

  const std::string before = read_file(in);
  const auto refused = run("subdivide " + in.string() + " -o " + in.string() + " --scheme loop");
  CHECK(refused.exit_code == 4);
  CHECK_THAT(refused.output, Catch::Contains("it is the input file"));
  CHECK(read_file(in) == before);
  fs::remove_all(dir);
}

TEST_CASE("bad input gets a one-line message and a non-zero exit - no output file", "[cli]") {
  const fs::path dir = scratch();
  const fs::path out = dir / "out.off";
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"empty.off", "", "empty.off"},
      {"garbage.off", "this is not a mesh\n\x01\x02\x03", "garbage.off"},
      {"fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n", "non-manifold"},
      {"quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", "triangles"},
      {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "vertex 1 has a coordinate that is missing or not a finite number"},
      {"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "not a finite number"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    const fs::path in = write_file(dir / c.name, c.text);
    const auto r = run("subdivide " + in.string() + " -o " + out.string() + " --scheme loop");
    CHECK(r.exit_code == 3);
    CHECK(count_lines(r.output) == 1);
    CHECK_THAT(r.output, Catch::Contains(c.expect));
    CHECK_FALSE(fs::exists(out));
  }
  const auto missing = run("subdivide " + (dir / "missing.off").string() + " -o " + out.string());
  CHECK(missing.exit_code == 3);
  CHECK(count_lines(missing.output) == 1);
  const auto usage = run("subdivide " + (dir / "fin.off").string() + " -o " + out.string() + " --scheme nonsense");
  CHECK(usage.exit_code == 2);
  fs::remove_all(dir);
}

TEST_CASE("subdivide puts new levels on top of a level-ordered input's hierarchy", "[cli]") {
  // The tetrahedron subdivided twice, then that output once more: the same faces, vertex for
  // vertex, as the tetrahedron subdivided three times at once (the output is in level order
  // through all three levels), and the same points to the files' float precision.
  const fs::path dir = scratch();
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  const std::string two = (dir / "two.off").string(), three = (dir / "three.off").string(),
                    again = (dir / "again.off").string();
  for (const std::string scheme : {"loop", "butterfly"}) {
    INFO(scheme);
    REQUIRE(run("subdivide " + tet.string() + " -o " + two + " --scheme " + scheme + " --levels 2").exit_code == 0);
    REQUIRE(run("subdivide " + two + " -o " + again + " --scheme " + scheme + " --levels 1").exit_code == 0);
    REQUIRE(run("subdivide " + tet.string() + " -o " + three + " --scheme " + scheme + " --levels 3").exit_code == 0);
    const OffFile a = read_off(again), b = read_off(three);
    REQUIRE(a.positions.size() == b.positions.size());
    REQUIRE(a.faces.size() == b.faces.size());
    CHECK(largest_difference(a.positions, b.positions) < 1e-6);
    CHECK(a.faces == b.faces);
  }
  fs::remove_all(dir);
}

TEST_CASE("fit writes a control mesh whose Loop limit interpolates the input", "[cli]") {
  const fs::path dir = scratch();
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  const std::string fine = (dir / "tet1.off").string(), fitted = (dir / "fit.off").string(),
                    limit = (dir / "limit.off").string();
  REQUIRE(run("subdivide " + tet.string() + " -o " + fine + " --scheme loop --levels 1").exit_code == 0);
  const auto r = run("fit " + fine + " -o " + fitted + " --scheme loop");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("converged"));
  // The limit points of the fitted control mesh are the input's vertices (to float precision).
  REQUIRE(run("limit " + fitted + " -o " + limit + " --scheme loop").exit_code == 0);
  const OffFile a = read_off(fine), b = read_off(limit);
  REQUIRE(a.positions.size() == b.positions.size());
  CHECK(largest_difference(a.positions, b.positions) < 1e-5);
  CHECK(run("fit " + fine + " -o " + fine).exit_code == 4);  // never over the input
  fs::remove_all(dir);
}

TEST_CASE("info reports topology and exits non-zero on unreadable files", "[cli]") {
  const fs::path dir = scratch();
  const fs::path in = write_file(dir / "tet.off", kTetrahedron);
  const auto r = run("info " + in.string() + " --json");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("\"euler_characteristic\": 2"));
  CHECK_THAT(r.output, Catch::Contains("\"closed\": true"));
  CHECK_THAT(r.output, Catch::Contains("\"self_intersecting_pairs\": 0"));
  // Two tetrahedra, the second moved by (1/4, 1/4, 1/4): its first corner is inside the first.
  const fs::path crossed = write_file(dir / "crossed.off",
                                      "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n.25 .25 .25\n1.25 .25 .25\n.25 1.25 .25\n"
                                      ".25 .25 1.25\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n");
  const auto c = run("info " + crossed.string());
  REQUIRE(c.exit_code == 0);
  CHECK_THAT(c.output, Catch::Contains("self-intersections:"));
  CHECK_THAT(c.output, Catch::Contains("pairs of faces cross (first: faces"));
  CHECK(run("info " + (dir / "missing.off").string()).exit_code == 3);
  fs::remove_all(dir);
}

TEST_CASE("encode - decode - truncate and stream a subdivided mesh - damaged files give numbered errors", "[cli][codec]") {
  const fs::path dir = scratch();
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  const std::string fine = (dir / "tet3.off").string(), mlz = (dir / "tet3.mlz").string();
  REQUIRE(run("subdivide " + tet.string() + " -o " + fine + " --scheme loop --levels 3").exit_code == 0);
  // A mesh that is not a manifold is refused, naming the problem, and nothing is written.
  const fs::path fin = write_file(dir / "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const auto refused = run("encode " + fin.string() + " -o " + mlz);
  CHECK(refused.exit_code == 3);
  CHECK_THAT(refused.output, Catch::Contains("non-manifold"));
  CHECK_FALSE(fs::exists(mlz));

  const auto encoded = run("encode " + fine + " -o " + mlz + " --scheme butterfly");
  REQUIRE(encoded.exit_code == 0);
  CHECK_THAT(encoded.output, Catch::Contains("bits/vertex"));
  const auto decoded = run("decode " + mlz + " -o " + (dir / "dec.off").string() + " --stats");
  REQUIRE(decoded.exit_code == 0);
  CHECK_THAT(decoded.output, Catch::Contains("vertices/s"));
  // On one thread or two, the same file.
  for (const char* threads : {"1", "2"}) {
    const std::string out = (dir / (std::string("dec_threads") + threads + ".off")).string();
    const auto again = run("decode " + mlz + " -o " + out + " --stats --threads " + threads);
    REQUIRE(again.exit_code == 0);
    CHECK_THAT(again.output, Catch::Contains(std::string("--threads ") + threads));
    CHECK(read_file(out) == read_file(dir / "dec.off"));
  }
  std::istringstream header(read_file(dir / "dec.off"));
  std::string magic;
  int v = 0, f = 0;
  header >> magic >> v >> f;
  CHECK(v == 130);  // 4 + 6 + 24 + 96
  CHECK(f == 256);

  const std::size_t size = fs::file_size(mlz);
  REQUIRE(run("truncate " + mlz + " --bytes " + std::to_string(size / 2) + " -o " + (dir / "half.mlz").string()).exit_code == 0);
  CHECK(fs::file_size(dir / "half.mlz") <= size / 2 + 4);
  REQUIRE(run("decode " + (dir / "half.mlz").string() + " -o " + (dir / "half_a.off").string()).exit_code == 0);
  REQUIRE(run("decode " + mlz + " --bytes " + std::to_string(size / 2) + " -o " + (dir / "half_b.off").string()).exit_code == 0);
  CHECK(read_file(dir / "half_a.off") == read_file(dir / "half_b.off"));
  // A cut before anything decodes, even inside the 8-byte file header, is refused as such (not as
  // a damaged input), and nothing is written.
  for (const int bytes : {7, 20}) {
    const auto early = run("truncate " + mlz + " --bytes " + std::to_string(bytes) + " -o " + (dir / "early.mlz").string());
    CHECK(early.exit_code == 3);
    CHECK_THAT(early.output, Catch::Contains("a cut at " + std::to_string(bytes) + " bytes falls inside the header or the base mesh"));
    CHECK_FALSE(fs::exists(dir / "early.mlz"));
  }

  const auto streamed = run("stream " + mlz + " --every 100 -o " + (dir / "frames").string() + " --reference " + fine +
                            " --csv " + (dir / "frames.csv").string());
  REQUIRE(streamed.exit_code == 0);
  const std::string csv = read_file(dir / "frames.csv");
  CHECK(count_lines(csv) >= 2);
  // The whole file decodes within 16-bit precision of the reference: PSNR well above 80 dB
  // (a reference in the wrong vertex order would give a few dB).
  const std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  CHECK(std::stod(last.substr(last.rfind(',') + 1)) > 80.0);

  // --psnr: the shortest prefix whose decode is within 60 dB of the input by the surface metric
  // (METRIC.md), as `compare` measures the decoded file; one byte less is not (the bisection's
  // resolution is a byte below 512 bytes, and both take the same 100,000 samples on so small a
  // mesh); a target beyond the whole stream writes it whole and says so.
  auto compared_psnr = [&](const std::string& mlz_file) {
    const std::string decoded_file = mlz_file + ".off";
    REQUIRE(run("decode " + mlz_file + " -o " + decoded_file).exit_code == 0);
    const auto compared = run("compare " + fine + " " + decoded_file);
    REQUIRE(compared.exit_code == 0);
    REQUIRE_THAT(compared.output, Catch::Contains("PSNR: "));
    return std::stod(compared.output.substr(compared.output.find("PSNR: ") + 6));
  };
  const std::string target = (dir / "p60.mlz").string();
  const auto p60 = run("encode " + fine + " -o " + target + " --scheme butterfly --psnr 60");
  REQUIRE(p60.exit_code == 0);
  REQUIRE_THAT(p60.output, Catch::Contains("--psnr 60: cut at " + std::to_string(fs::file_size(target)) + " of "));
  REQUIRE(fs::file_size(target) < 512);
  CHECK(fs::file_size(target) < size);
  CHECK(compared_psnr(target) >= 60.0);
  // The file is the whole stream cut at n bytes (truncate_file: its checksum makes it up to 4
  // bytes longer); the cut at n - 1 decodes short of the target.
  std::size_t n = fs::file_size(target) - 4;
  auto cut_at = [&](std::size_t bytes) {
    const std::string cut_file = (dir / ("p60_" + std::to_string(bytes) + ".mlz")).string();
    REQUIRE(run("truncate " + mlz + " --bytes " + std::to_string(bytes) + " -o " + cut_file).exit_code == 0);
    return cut_file;
  };
  while (n < fs::file_size(target) && read_file(cut_at(n)) != read_file(target)) ++n;
  REQUIRE(read_file(cut_at(n)) == read_file(target));
  CHECK(compared_psnr(cut_at(n - 1)) < 60.0);
  // truncate --psnr cuts the whole file where encode --psnr does: the same bytes.
  const std::string cut60 = (dir / "t60.mlz").string();
  const auto t60 = run("truncate " + mlz + " -o " + cut60 + " --psnr 60 --reference " + fine);
  REQUIRE(t60.exit_code == 0);
  CHECK_THAT(t60.output, Catch::Contains("--psnr 60: the first " + std::to_string(n) + " bytes decode "));
  CHECK(read_file(cut60) == read_file(target));
  CHECK(run("truncate " + mlz + " -o " + cut60 + " --psnr 60").exit_code == 2);  // no reference
  CHECK(run("truncate " + mlz + " -o " + cut60).exit_code == 2);                // neither --bytes nor --psnr
  {  // A damaged file is refused with its status before any prefix is measured.
    std::string damaged = read_file(mlz);
    damaged[damaged.size() - 6] = static_cast<char>(damaged[damaged.size() - 6] ^ 0x10);
    const fs::path damaged_path = write_file(dir / "damaged.mlz", damaged);
    const auto refused_cut = run("truncate " + damaged_path.string() + " -o " + (dir / "t_damaged.mlz").string() +
                                 " --psnr 60 --reference " + fine);
    CHECK(refused_cut.exit_code == 3);
    CHECK_THAT(refused_cut.output, Catch::Contains("checksum_mismatch (error 5)"));
    CHECK(count_lines(refused_cut.output) == 1);  // no measure of a file that does not decode
    CHECK_FALSE(fs::exists(dir / "t_damaged.mlz"));
  }
  const std::string beyond = (dir / "p300.mlz").string();
  const auto p300 = run("encode " + fine + " -o " + beyond + " --scheme butterfly --psnr 300");
  REQUIRE(p300.exit_code == 0);
  CHECK_THAT(p300.output, Catch::Contains("--psnr 300 is out of reach: the whole stream decodes to "));
  CHECK(read_file(beyond) == read_file(mlz));

  // Flip a byte in the last chunk's payload: checksum_mismatch, error 5, no output written.
  std::string bytes = read_file(mlz);
  bytes[bytes.size() - 6] = static_cast<char>(bytes[bytes.size() - 6] ^ 0x10);
  write_file(dir / "bad.mlz", bytes);
  const auto bad = run("decode " + (dir / "bad.mlz").string() + " -o " + (dir / "bad.off").string());
  CHECK(bad.exit_code == 3);
  CHECK_THAT(bad.output, Catch::Contains("checksum_mismatch (error 5)"));
  CHECK(count_lines(bad.output) == 1);
  CHECK_FALSE(fs::exists(dir / "bad.off"));
  const auto not_mlz = run("decode " + tet.string() + " -o " + (dir / "x.off").string());
  CHECK(not_mlz.exit_code == 3);
  CHECK_THAT(not_mlz.output, Catch::Contains("bad_magic"));
  const auto truncate_not_mlz = run("truncate " + tet.string() + " --bytes 7 -o " + (dir / "x.mlz").string());
  CHECK(truncate_not_mlz.exit_code == 3);
  CHECK_THAT(truncate_not_mlz.output, Catch::Contains("bad_magic"));
  fs::remove_all(dir);
}

TEST_CASE("encode's default scheme is the wavelet that predicts the mesh best", "[cli][codec]") {
  // Subdivided by a scheme with zero details, the mesh has zero details for that scheme's wavelet
  // alone: auto takes it (and `info` agrees with what the summary line says).
  const fs::path dir = scratch();
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  for (const std::string scheme : {"linear", "butterfly", "loop"}) {
    INFO(scheme);
    const std::string fine = (dir / ("tet_" + scheme + ".off")).string(), mlz = (dir / ("tet_" + scheme + ".mlz")).string();
    REQUIRE(run("subdivide " + tet.string() + " -o " + fine + " --scheme " + scheme + " --levels 3").exit_code == 0);
    const auto encoded = run("encode " + fine + " -o " + mlz);
    REQUIRE(encoded.exit_code == 0);
    // An input taken over as it is has no remesh error: the finest step stays 2^-16.
    CHECK_THAT(encoded.output, Catch::Contains("auto: " + scheme + ", 16-bit precision ->"));
    CHECK_THAT(run("info " + mlz).output, Catch::Contains("wavelet:      " + scheme));
  }
}

namespace {

/// A smooth colour of a point, as bytes.
std::array<int, 3> colour_of(const double* p) {
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = static_cast<int>(std::lround(127.5 + 127.5 * std::sin(3 * p[k] + k)));
  return c;
}

/// The vertices of an ascii PLY that meshlift wrote with colours: x y z r g b per line.
std::vector<std::array<double, 6>> read_coloured_ply(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string line;
  std::size_t vertices = 0;
  bool coloured = false;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    coloured |= line == "property uchar red";
  }
  std::vector<std::array<double, 6>> out;
  if (!coloured) return out;
  for (std::size_t v = 0; v < vertices; ++v) {
    std::array<double, 6> row{};
    for (double& x : row) in >> x;
    out.push_back(row);
  }
  return out;
}

}  // namespace

TEST_CASE("vertex colours go through encode, decode, stream and remesh", "[cli][codec][colour]") {
  const fs::path dir = scratch();
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  const std::string fine = (dir / "tet4.off").string();
  REQUIRE(run("subdivide " + tet.string() + " -o " + fine + " --scheme loop --levels 4").exit_code == 0);
  // The same mesh with a colour per vertex (COFF, bytes).
  const OffFile off = read_off(fine);
  std::ostringstream coff;
  coff.precision(9);
  coff << "COFF\n" << off.positions.size() / 3 << " " << off.faces.size() << " 0\n";
  for (std::size_t v = 0; v < off.positions.size() / 3; ++v) {
    const std::array<int, 3> c = colour_of(&off.positions[3 * v]);
    coff << off.positions[3 * v] << " " << off.positions[3 * v + 1] << " " << off.positions[3 * v + 2] << " " << c[0] << " "
         << c[1] << " " << c[2] << " 255\n";
  }
  for (const auto& face : off.faces) coff << "3 " << face[0] << " " << face[1] << " " << face[2] << "\n";
  const fs::path coloured = write_file(dir / "tet4c.off", coff.str());
  CHECK_THAT(run("info " + coloured.string()).output, Catch::Contains("vertex colours:"));
  CHECK_THAT(run("info " + fine).output, !Catch::Contains("vertex colours:"));
  CHECK_THAT(run("info " + coloured.string() + " --json").output, Catch::Contains("\"vertex_colours\": true"));
  CHECK_THAT(run("info " + fine + " --json").output, Catch::Contains("\"vertex_colours\": false"));
  const std::string mlz = (dir / "c.mlz").string();
  REQUIRE(run("encode " + coloured.string() + " -o " + mlz).exit_code == 0);
  CHECK_THAT(run("info " + mlz).output, Catch::Contains("the vertices' colour"));
  // Whole, every vertex's colour comes back within a byte of its own (the channel's step is
  // 2^-9 of each component's range); a prefix carries colours too, further off.
  double whole_error = 0, prefix_error = 0;
  for (const bool whole : {true, false}) {
    const std::string out = (dir / (whole ? "whole.ply" : "prefix.ply")).string();
    REQUIRE(run("decode " + mlz + " -o " + out + (whole ? "" : " --bytes " + std::to_string(fs::file_size(mlz) / 3))).exit_code == 0);
    const auto rows = read_coloured_ply(out);
    REQUIRE(rows.size() == off.positions.size() / 3);
    double sum = 0, worst = 0;
    for (const auto& row : rows) {
      const std::array<int, 3> expected = colour_of(row.data());
      for (std::size_t k = 0; k < 3; ++k) {
        const double d = std::abs(row[3 + k] - expected[k]);
        sum += d;
        worst = std::max(worst, d);
      }
    }
    (whole ? whole_error : prefix_error) = sum / static_cast<double>(3 * rows.size());
    // compare measures the colours too: the input's at each decoded vertex against the decoded.
    const auto compared = run("compare " + coloured.string() + " " + out + " --json");
    REQUIRE(compared.exit_code == 0);
    const std::size_t at = compared.output.find("\"colour\": {\"rms\": ");
    REQUIRE(at != std::string::npos);
    const std::size_t mean_at = compared.output.find("\"mean\": ", at);
    CHECK(std::abs(255 * std::stod(compared.output.substr(mean_at + 8)) - sum / static_cast<double>(3 * rows.size())) < 0.5);
    // (colour_of the decoded position, which differs from the input's in its last bits: a byte
    // rounded the other way at most.)
    if (whole) CHECK(worst <= 1.0);
  }
  CHECK(whole_error < 0.25);
  CHECK(prefix_error > whole_error);
  // Coarser colours (--colour-bits 6): a smaller file; 0 bits is refused as a bad argument.
  const std::string coarse = (dir / "c6.mlz").string();
  REQUIRE(run("encode " + coloured.string() + " -o " + coarse + " --colour-bits 6").exit_code == 0);
  CHECK(fs::file_size(coarse) < fs::file_size(mlz));
  CHECK(run("encode " + coloured.string() + " -o " + coarse + " --colour-bits 0").exit_code == 2);
  // The file without colours is smaller and decodes without them.
  REQUIRE(run("encode " + fine + " -o " + (dir / "plain.mlz").string()).exit_code == 0);
  CHECK(fs::file_size(dir / "plain.mlz") < fs::file_size(mlz));
  REQUIRE(run("decode " + (dir / "plain.mlz").string() + " -o " + (dir / "plain.ply").string()).exit_code == 0);
  CHECK(read_coloured_ply((dir / "plain.ply").string()).empty());
  // A viewer's frames and a remesh written out have them too.
  REQUIRE(run("stream " + mlz + " --every 2000 -o " + (dir / "frames").string()).exit_code == 0);
  for (const auto& frame : fs::directory_iterator(dir / "frames"))
    CHECK_THAT(read_file(frame.path()), Catch::Contains("property uchar red"));
  REQUIRE(run("remesh " + coloured.string() + " -o " + (dir / "remesh.ply").string()).exit_code == 0);
  CHECK(read_coloured_ply((dir / "remesh.ply").string()).size() == off.positions.size() / 3);
  fs::remove_all(dir);
}

TEST_CASE("encode codes a remesh to 15 bits where its own error is far above that step", "[cli][codec]") {
  const fs::path dir = scratch();
  // A bumpy closed surface that is not semi-regular: the tetrahedron Loop-subdivided 5 times and
  // displaced by ripples, then a vertex added inside a face (its face split in three), so that no
  // hierarchy is found and it is remeshed by decimation.
  const fs::path tet = write_file(dir / "tet.off", kTetrahedron);
  const std::string fine = (dir / "fine.off").string();
  REQUIRE(run("subdivide " + tet.string() + " -o " + fine + " --scheme loop --levels 5").exit_code == 0);
  OffFile off = read_off(fine);
  for (std::size_t i = 0; i < off.positions.size(); i += 3) {
    const double x = off.positions[i], y = off.positions[i + 1], z = off.positions[i + 2];
    const double ripple = 1 + 0.04 * std::sin(23 * x) * std::cos(19 * y) + 0.03 * std::sin(29 * z);
    for (int k = 0; k < 3; ++k) off.positions[i + static_cast<std::size_t>(k)] = 0.25 + (off.positions[i + static_cast<std::size_t>(k)] - 0.25) * ripple;
  }
  const std::vector<int> face = off.faces.back();
  off.faces.pop_back();
  const int centre = static_cast<int>(off.positions.size() / 3);
  for (int k = 0; k < 3; ++k)
    off.positions.push_back((off.positions[3 * face[0] + k] + off.positions[3 * face[1] + k] + off.positions[3 * face[2] + k]) / 3);
  for (int i = 0; i < 3; ++i) off.faces.push_back({face[i], face[(i + 1) % 3], centre});
  std::ostringstream text;
  text.precision(17);
  text << "OFF\n" << off.positions.size() / 3 << " " << off.faces.size() << " 0\n";
  for (std::size_t i = 0; i < off.positions.size(); i += 3)
    text << off.positions[i] << " " << off.positions[i + 1] << " " << off.positions[i + 2] << "\n";
  for (const auto& f : off.faces) text << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  const fs::path input = write_file(dir / "split.off", text.str());
  const auto encoded = run("encode " + input.string() + " -o " + (dir / "a.mlz").string());
  REQUIRE(encoded.exit_code == 0);
  REQUIRE_THAT(encoded.output, Catch::Contains("remesh error: PSNR"));
  const std::string psnr = encoded.output.substr(encoded.output.find("remesh error: PSNR ") + 19);
  REQUIRE(std::stod(psnr) < 85);  // a remesh farther than 85 dB from its input ...
  CHECK_THAT(encoded.output, Catch::Contains("15-bit precision"));  // ... is coded to 2^-15 of the diagonal
  // A --psnr target keeps 16 bits (the target is met within the stream); --bits overrides both.
  const auto target = run("encode " + input.string() + " -o " + (dir / "p.mlz").string() + " --psnr 70");
  REQUIRE(target.exit_code == 0);
  CHECK_THAT(target.output, Catch::Contains("16-bit precision"));
  // The target is the error against the input, not against the remesh: as compare measures the
  // decode, and as stream measures each prefix against a reference that is not the encoded mesh.
  auto compared_psnr = [&](const std::string& mlz_file) {
    const std::string decoded = mlz_file + ".off";
    REQUIRE(run("decode " + mlz_file + " -o " + decoded).exit_code == 0);
    const auto compared = run("compare " + input.string() + " " + decoded);
    REQUIRE(compared.exit_code == 0);
    return std::stod(compared.output.substr(compared.output.find("PSNR: ") + 6));
  };
  CHECK(compared_psnr((dir / "p.mlz").string()) >= 70.0);
  // A target beyond the automatic remesh: a denser one is made and kept, and reaches it.
  const double beyond_remesh = std::stod(psnr) + 1;
  const std::string closer = (dir / "closer.mlz").string();
  const auto denser = run("encode " + input.string() + " -o " + closer + " --psnr " + std::to_string(beyond_remesh));
  REQUIRE(denser.exit_code == 0);
  CHECK_THAT(denser.output, Catch::Contains("short of the target: remeshing at ~"));
  CHECK_THAT(denser.output, Catch::Contains("): kept"));
  CHECK(compared_psnr(closer) >= beyond_remesh);
  const std::string csv = (dir / "a.csv").string();
  const auto streamed = run("stream " + (dir / "a.mlz").string() + " --every 3000 --reference " + input.string() + " --csv " + csv);
  REQUIRE(streamed.exit_code == 0);
  CHECK_THAT(streamed.output, Catch::Contains("not the encoded mesh: PSNR of the decoded surface against it"));
  const std::string rows = read_file(csv);
  const std::string last = rows.substr(rows.rfind('\n', rows.size() - 2) + 1);
  CHECK(std::abs(std::stod(last.substr(last.rfind(',') + 1)) - compared_psnr((dir / "a.mlz").string())) < 0.002);
  const auto asked = run("encode " + input.string() + " -o " + (dir / "b.mlz").string() + " --bits 12");
  REQUIRE(asked.exit_code == 0);
  CHECK_THAT(asked.output, Catch::Contains("12-bit precision"));
  CHECK(fs::file_size(dir / "b.mlz") < fs::file_size(dir / "a.mlz"));
  fs::remove_all(dir);
}
