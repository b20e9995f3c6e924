// Drives the built `meshlift` executable: exit codes, one-line messages, files left untouched.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct Run {
  int exit_code;
  std::string output;  // stdout and stderr together
};

Run run(const std::string& args) {
  const std::string command = std::string(MESHLIFT_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("meshlift_cli_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

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

TEST_CASE("bad input gets a one-line message and a non-zero exit, no output file", "[cli]") {
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
      {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "vertices"},
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

TEST_CASE("info reports topology and exits non-zero on unreadable files", "[cli]") {
  const fs::path dir = scratch();
  const fs::path in = write_file(dir / "tet.off", kTetrahedron);
  const auto r = run("info " + in.string() + " --json");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("\"euler_characteristic\": 2"));
  CHECK_THAT(r.output, Catch::Contains("\"closed\": true"));
  CHECK(run("info " + (dir / "missing.off").string()).exit_code == 3);
  fs::remove_all(dir);
}
