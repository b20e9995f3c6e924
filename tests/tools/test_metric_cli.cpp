// `meshlift compare` and `meshlift rd` driven through the built executable: known distances,
// exit codes and messages, the sweep's table and its error rows.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code;
  std::string out, err;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("meshlift_metric_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Runs the CLI with stdout and stderr captured separately.
Result run(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command =
      std::string(MESHLIFT_CLI) + " " + args + " > " + out.string() + " 2> " + err.string() + " < /dev/null";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

/// n x n grid over [0,1]^2 at height z, as OFF text.
std::string grid_off(int n, double z, double scale = 1) {
  std::ostringstream s;
  s << "OFF\n" << n * n << " " << 2 * (n - 1) * (n - 1) << " 0\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) s << scale * j / (n - 1) << " " << scale * i / (n - 1) << " " << scale * z << "\n";
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n + 1, d = a + n;
      s << "3 " << a << " " << b << " " << c << "\n3 " << a << " " << c << " " << d << "\n";
    }
  return s.str();
}

fs::path write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

/// The number after `"key": ` in a JSON text (NaN when absent or null).
double json_value(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return NAN;
  const char* start = json.c_str() + at + key.size() + 4;
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  return end == start ? NAN : value;
}

/// Rows of a CSV with no quoted commas in the fields this test reads, keyed by column name.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::istringstream in(slurp(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream h(line);
  for (std::string field; std::getline(h, field, ',');) header.push_back(field);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::size_t column = 0, start = 0;
    bool quoted = false;
    std::string field;
    for (std::size_t i = 0; i <= line.size(); ++i) {
      const char c = i < line.size() ? line[i] : ',';
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) {
        if (column < header.size()) row[header[column]] = field;
        ++column;
        field.clear();
        start = i + 1;
      } else if (c != '"') {
        field += c;
      }
    }
    (void)start;
    rows.push_back(row);
  }
  return rows;
}

const char* kOctahedron =
    "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
    "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";

}  // namespace

TEST_CASE("compare of a plane and its offset copy reports the offset", "[cli][metric]") {
  const fs::path dir = scratch_dir("offset");
  const fs::path a = write(dir / "a.off", grid_off(6, 0)), b = write(dir / "b.off", grid_off(6, 0.125));
  const Result r = run("compare " + a.string() + " " + b.string() + " --json --samples 5000", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(std::abs(json_value(r.out, "rms") - 0.125) < 1e-12);
  CHECK(std::abs(json_value(r.out, "hausdorff") - 0.125) < 1e-12);
  CHECK(std::abs(json_value(r.out, "hausdorff_relative") - 0.125 / std::sqrt(2.0)) < 1e-12);
  CHECK(std::abs(json_value(r.out, "psnr_db") - 20 * std::log10(std::sqrt(2.0) / 0.125)) < 1e-9);
  CHECK(r.err.empty());
  // The table form says the same.
  const Result table = run("compare " + a.string() + " " + b.string() + " --samples 5000", dir);
  REQUIRE(table.exit_code == 0);
  CHECK_THAT(table.out, Catch::Contains("PSNR: 21.072 dB"));
  fs::remove_all(dir);
}

TEST_CASE("compare is deterministic across thread counts", "[cli][metric]") {
  const fs::path dir = scratch_dir("threads");
  const fs::path a = write(dir / "a.off", kOctahedron), b = write(dir / "b.off", grid_off(5, 0.3));
  const Result one = run("compare " + a.string() + " " + b.string() + " --json --threads 1", dir);
  const Result three = run("compare " + a.string() + " " + b.string() + " --json --threads 3", dir);
  REQUIRE(one.exit_code == 0);
  REQUIRE(one.out == three.out);
  CHECK(json_value(one.out, "rms") > 0.1);
  fs::remove_all(dir);
}

TEST_CASE("compare rejects empty and missing meshes and warns on different scales", "[cli][metric]") {
  const fs::path dir = scratch_dir("bad");
  const fs::path a = write(dir / "a.off", grid_off(4, 0));
  const fs::path points = write(dir / "points.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  Result r = run("compare " + a.string() + " " + points.string(), dir);
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.err, Catch::Contains("points.off: the mesh has no faces"));
  r = run("compare " + (dir / "missing.off").string() + " " + a.string(), dir);
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.err, Catch::Contains("missing.off"));
  r = run("compare " + a.string() + " " + a.string() + " --samples lots", dir);
  CHECK(r.exit_code == 2);

  const fs::path huge = write(dir / "huge.off", grid_off(4, 0, 1000));
  r = run("compare " + a.string() + " " + huge.string() + " --json --samples 2000", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.err, Catch::Contains("warning") && Catch::Contains("100x"));
  CHECK(json_value(r.out, "hausdorff") > 900);
  fs::remove_all(dir);
}

TEST_CASE("rd writes a row per scheme and budget with PSNR rising along the prefixes", "[cli][rd]") {
  const fs::path dir = scratch_dir("rd");
  const fs::path octahedron = write(dir / "octahedron.off", kOctahedron);
  const fs::path semi_regular = dir / "bumpy.off";
  // Butterfly-subdivided: smooth but not what the linear or Loop predictors give, so every
  // level carries details. 1026 vertices.
  REQUIRE(run("subdivide " + octahedron.string() + " -o " + semi_regular.string() + " --scheme butterfly --levels 4",
              dir).exit_code == 0);
  const fs::path unreadable = write(dir / "broken.off", "OFF\nthis is not a mesh\n");
  const fs::path out = dir / "out";
  const Result r = run("rd " + semi_regular.string() + " " + unreadable.string() +
                           " --schemes linear,loop --bpv 4,8,16,32 --separate --draco-qp 8,12 --samples 20000 -o " +
                           out.string(),
                       dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  REQUIRE(fs::exists(out / "rd.csv"));
  REQUIRE(fs::exists(out / "rd.json"));
  CHECK(slurp(out / "rd.csv").rfind(
            "mesh,input_vertices,codec,scheme,kind,param,bytes,bpv,psnr_db,rms_rel,hausdorff_rel,encode_s,decode_s,"
            "peak_rss_mb,error,update,tangent_shift\n", 0) == 0);
  const auto rows = read_csv(out / "rd.csv");
  const bool draco = std::system("command -v draco_encoder > /dev/null && command -v draco_decoder > /dev/null") == 0;

  std::map<std::string, std::vector<std::pair<double, double>>> prefix_psnr;  // bytes, PSNR
  std::size_t separate = 0, draco_rows = 0, broken_rows = 0;
  std::vector<double> draco_psnr;
  for (const auto& row : rows) {
    if (row.at("mesh") == "broken") {
      ++broken_rows;
      CHECK_FALSE(row.at("error").empty());
      CHECK(row.at("psnr_db").empty());
      continue;
    }
    INFO(row.at("codec") << " " << row.at("scheme") << " " << row.at("kind") << " " << row.at("param") << ": "
                         << row.at("error"));
    REQUIRE(row.at("mesh") == "bumpy");
    REQUIRE(row.at("input_vertices") == "1026");
    REQUIRE(row.at("error").empty());
    const double bytes = std::stod(row.at("bytes")), bpv = std::stod(row.at("bpv"));
    CHECK(std::abs(bpv - 8 * bytes / 1026) < 1e-3);
    // The update step is the default for linear; Loop has its own; Draco's rows have none.
    CHECK(row.at("update") == (row.at("codec") == "draco" ? "" : row.at("scheme") == "linear" ? "1" : "0"));
    // Local frames with the default shift (a semi-regular input follows no feature line); none for Draco.
    CHECK(row.at("tangent_shift") == (row.at("codec") == "draco" ? "" : "2"));
    CHECK(std::stod(row.at("peak_rss_mb")) > 0);
    CHECK(std::stod(row.at("hausdorff_rel")) >= std::stod(row.at("rms_rel")));
    if (row.at("kind") == "prefix") {
      CHECK(bytes <= std::stod(row.at("param")) * 1026 / 8);
      prefix_psnr[row.at("scheme")].push_back({bytes, std::stod(row.at("psnr_db"))});
    } else if (row.at("kind") == "separate") {
      ++separate;
    } else {
      REQUIRE(row.at("codec") == "draco");
      ++draco_rows;
      draco_psnr.push_back(std::stod(row.at("psnr_db")));
    }
  }
  CHECK(broken_rows >= 1);
  REQUIRE(prefix_psnr.size() == 2);
  for (const auto& [scheme, psnr] : prefix_psnr) {
    INFO(scheme);
    REQUIRE(psnr.size() == 4);
    // Rising with the budget; a budget above the whole stream's size gets the whole stream
    // again (the same bytes, the same PSNR), which only the largest budgets may do; a prefix a
    // few bytes short of the whole stream lacks only plane 0's last refinement bits, below the
    // CSV's 0.001 dB.
    CHECK(psnr[1].first > psnr[0].first);
    CHECK(psnr[2].first > psnr[1].first);
    for (std::size_t i = 1; i < psnr.size(); ++i) {
      if (psnr[i].first == psnr[i - 1].first)
        CHECK(psnr[i].second == psnr[i - 1].second);
      else if (psnr[i].first < psnr[i - 1].first + 8)
        CHECK(psnr[i].second >= psnr[i - 1].second);
      else
        CHECK(psnr[i].second > psnr[i - 1].second);
    }
    CHECK(psnr.front().second > 20);
  }
  CHECK(separate == 8);
  if (draco) {
    REQUIRE(draco_rows == 2);
    CHECK(draco_psnr[1] > draco_psnr[0] + 10);  // 4 more quantization bits: ~24 dB
  } else {
    CHECK(draco_rows == 0);
  }
  // The JSON has the same rows.
  const std::string json = slurp(out / "rd.json");
  std::size_t objects = 0;
  for (std::size_t at = json.find("{\"mesh\""); at != std::string::npos; at = json.find("{\"mesh\"", at + 1)) ++objects;
  CHECK(objects == rows.size());
  if (fs::exists("/usr/bin/python3")) {
    // Valid JSON with the CSV's columns (absent numbers as null), the same number of rows.
    const std::string check = "/usr/bin/python3 -c \"import csv, json, sys; j = json.load(open(sys.argv[1])); "
                              "c = list(csv.DictReader(open(sys.argv[2]))); "
                              "sys.exit(0 if len(j) == len(c) and all(list(r) == list(c[0]) for r in j) else 1)\" " +
                              (out / "rd.json").string() + " " + (out / "rd.csv").string();
    CHECK(std::system(check.c_str()) == 0);
  }
  CHECK_THAT(r.err, Catch::Contains("broken"));
  fs::remove_all(dir);
}

TEST_CASE("rd keeps going past a mesh the remesher rejects and past failed encodes", "[cli][rd]") {
  const fs::path dir = scratch_dir("rd_errors");
  const fs::path octahedron = write(dir / "octahedron.off", kOctahedron);
  const fs::path fine = dir / "fine.off";
  REQUIRE(run("subdivide " + octahedron.string() + " -o " + fine.string() + " --scheme loop --levels 3", dir).exit_code == 0);
  // Three faces on one edge: not a manifold, so remesh() throws and the mesh gets one error row.
  const fs::path fin = write(dir / "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const fs::path out = dir / "out";
  // 40 bits is finer than the quantizer's 31-bit magnitudes allow at 3 levels: every encode
  // throws, each of its rows says so, and the sweep goes on.
  const Result r = run("rd " + fin.string() + " " + fine.string() +
                           " --schemes linear,butterfly --bpv 8,16 --bits 40 --draco-qp 10 --samples 5000 -o " +
                           out.string(),
                       dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto rows = read_csv(out / "rd.csv");
  std::size_t remesh_errors = 0, encode_errors = 0;
  for (const auto& row : rows) {
    if (row.at("codec") != "meshlift") continue;
    if (row.at("mesh") == "fin") {
      CHECK_THAT(row.at("error"), Catch::Contains("remesh"));
      ++remesh_errors;
    } else {
      CHECK(row.at("error").rfind("encode: precision_bits 40", 0) == 0);
      CHECK(row.at("bytes").empty());
      CHECK(row.at("psnr_db").empty());
      ++encode_errors;
    }
  }
  CHECK(remesh_errors == 1);
  CHECK(encode_errors == 4);  // 2 schemes x 2 budgets
  if (std::system("command -v draco_encoder > /dev/null && command -v draco_decoder > /dev/null") == 0) {
    // Draco is still measured on both: the non-manifold mesh and the one whose encodes failed.
    std::size_t good_draco = 0;
    for (const auto& row : rows)
      if (row.at("codec") == "draco" && row.at("error").empty() && !row.at("psnr_db").empty()) ++good_draco;
    CHECK(good_draco == 2);
  }
  CHECK_THAT(r.err, Catch::Contains("fin meshlift: remesh"));
  fs::remove_all(dir);
}
