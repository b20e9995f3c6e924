// Hostile inputs through the built `meshlift` (issue 7, docs/ERRORS.md): hostile streams,
// malformed meshes, outputs that would overwrite an input, and runs interrupted by a signal
// while writing. Every case checks the exit code, the one-line message and the files left behind.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "test_streams.h"
#include "meshlift/byte_io.h"
#include "meshlift/container.h"

extern char** environ;

namespace fs = std::filesystem;

namespace {

using Run = meshlift::test::CliRun;
using meshlift::test::run_cli;

/// A fresh directory per test case, removed afterwards.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name)
      : dir(fs::temp_directory_path() / ("meshlift_hostile_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string file(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return (dir / name).string();
  }
  std::string file(const std::string& name, const std::vector<std::uint8_t>& bytes) const {
    std::ofstream(dir / name, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return (dir / name).string();
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  /// Names of the files in the directory whose name contains ".tmp-" (temporary outputs).
  std::vector<std::string> temporaries() const {
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().find(".tmp-") != std::string::npos) found.push_back(e.path().filename().string());
    return found;
  }
};

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* kTetrahedron = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

}  // namespace

TEST_CASE("CLI: hostile streams claiming 2^40 vertices or 200 levels are refused with exit 3", "[cli][hostile]") {
  Scratch s("claims");
  const std::string huge = s.file("huge.mlz", meshlift::test::claiming(std::uint64_t{1} << 40, std::uint64_t{1} << 40, 4));
  const std::string deep = s.file("deep.mlz", meshlift::test::claiming(12, 20, 200));
  for (const std::string& command : {"decode " + huge + " -o " + s.path("out.off"), "info " + huge}) {
    const Run r = run_cli(command);
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.output, Catch::Contains("huge.mlz: limit_exceeded (error 6): header claims 1099511627776 base vertices"));
  }
  const Run r = run_cli("decode " + deep + " -o " + s.path("out.off"));
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.output, Catch::Contains("deep.mlz: limit_exceeded (error 6): header claims 200 levels (at most 12)"));
  CHECK_FALSE(fs::exists(s.path("out.off")));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: damaged streams name the status and the byte", "[cli][hostile]") {
  Scratch s("damaged");
  REQUIRE(run_cli("subdivide " + s.file("tet.off", kTetrahedron) + " -o " + s.path("sub.off") + " --scheme loop --levels 2").exit_code == 0);
  REQUIRE(run_cli("encode " + s.path("sub.off") + " -o " + s.path("good.mlz")).exit_code == 0);
  std::string bytes = read_text(s.path("good.mlz"));
  const std::string good = bytes;
  bytes[bytes.size() - 10] ^= 0x20;  // inside the last chunk's payload
  s.file("flipped.mlz", bytes);
  Run r = run_cli("decode " + s.path("flipped.mlz") + " -o " + s.path("out.off"));
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.output, Catch::Contains("flipped.mlz: checksum_mismatch (error 5)"));
  CHECK_THAT(r.output, Catch::Contains("at byte "));
  s.file("magic.mlz", "PK\x03\x04 not a stream");
  r = run_cli("decode " + s.path("magic.mlz") + " -o " + s.path("out.off"));
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.output, Catch::Contains("magic.mlz: bad_magic (error 2)"));
  s.file("short.mlz", good.substr(0, 20));
  r = run_cli("decode " + s.path("short.mlz") + " -o " + s.path("out.off"));
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.output, Catch::Contains("short.mlz: truncated (error 1)"));
  CHECK_FALSE(fs::exists(s.path("out.off")));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: malformed meshes give the documented message through info and encode", "[cli][hostile]") {
  Scratch s("malformed");
  struct Case {
    const char* name;
    std::string text;
    int info_exit;               // info reports defects with exit 0, unreadable files with 3
    const char* info_says;       // in info's output
    const char* encode_says;     // in encode's one-line error (exit 3) or, for 0, its summary
    int encode_exit = 3;
  };
  const std::vector<Case> cases = {
      {"empty.off", "", 3, "empty.off: file is empty", "empty.off: file is empty"},
      {"nan.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 nan 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", 3,
       "nan.off: vertex 2 has a coordinate that is missing or not a finite number",
       "nan.off: vertex 2 has a coordinate that is missing or not a finite number"},
      {"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", 3,
       "inf.obj: OBJ line 3: a vertex coordinate is missing or not a finite number",
       "inf.obj: OBJ line 3: a vertex coordinate is missing or not a finite number"},
      {"fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n", 0,
       "non-manifold edges:      1", "fin.off: 1 non-manifold edge (first: edge 0-1, on more than two faces)"},
      {"pinched.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n", 0,
       "non-manifold vertices:   1", "pinched.off: 1 non-manifold vertex (first: vertex 0, where separate fans of faces meet)"},
      {"points.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n", 0, "triangle codec:          mesh has no faces",
       "points.off: mesh has no faces"},
      {"soup.off",
       "OFF\n9 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n0 0 2\n1 0 2\n0 1 2\n3 0 1 2\n3 3 4 5\n3 6 7 8\n", 0,
       "components:              3", "soup.off: polygon soup: 3 faces in 3 separate pieces"},
      {"flipped.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 3 2\n", 0, "consistently oriented:   no",
       "flipped.off: 1 edge is traversed in the same direction by both faces: orientation is inconsistent (first: edge 0-2)"},
      {"flat.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n0 0 1\n3 0 1 2\n3 0 3 1\n3 1 3 2\n3 2 3 0\n", 0,
       "zero-area faces:         1", "flat.off: 4 vertices -> decimation", 0},
      // A cube of six unwelded quads: each piece is remeshed apart, and a note says why.
      {"unwelded.off", "OFF\n24 6 0\n0 0 0\n0 1 0\n1 1 0\n1 0 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n1 0 0\n1 1 0\n1 1 1\n1 0 1\n1 1 0\n0 1 0\n0 1 1\n1 1 1\n0 1 0\n0 0 0\n0 0 1\n0 1 1\n4 0 1 2 3\n4 4 5 6 7\n4 8 9 10 11\n4 12 13 14 15\n4 16 17 18 19\n4 20 21 22 23\n", 0,
       "duplicate vertices:      16", "unwelded.off: note: 16 vertices lie exactly on other vertices", 0},
      {"line.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n3 0 1 2\n3 0 2 3\n", 0, "zero-area faces:         2",
       "line.off: every face has zero area (its corners on a line or at one point): there is no surface to remesh"},
      {"beyond_float.off", "OFF\n3 1 0\n0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n", 3,
       "beyond_float.off: vertex 1 has a coordinate that is missing or not a finite number",
       "beyond_float.off: vertex 1 has a coordinate that is missing or not a finite number"},
  };
  for (const Case& c : cases) {
    const std::string input = s.file(c.name, c.text);
    const Run info = run_cli("info " + input);
    INFO(c.name << " info:\n" << info.output);
    CHECK(info.exit_code == c.info_exit);
    CHECK_THAT(info.output, Catch::Contains(c.info_says));
    const Run encode = run_cli("encode " + input + " -o " + s.path("out.mlz"));
    INFO(c.name << " encode:\n" << encode.output);
    CHECK(encode.exit_code == c.encode_exit);
    if (c.encode_exit != 0) {
      CHECK_THAT(encode.output, Catch::Contains(std::string("meshlift: ") + s.path(c.encode_says)));
      CHECK_FALSE(fs::exists(s.path("out.mlz")));
    } else {
      CHECK_THAT(encode.output, Catch::Contains(s.path(c.encode_says)));
      CHECK(run_cli("decode " + s.path("out.mlz") + " -o " + s.path("out.off")).exit_code == 0);
      fs::remove(s.path("out.mlz"));
    }
  }
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: a mesh the remesher refuses gets a line saying what to do", "[cli][hostile]") {
  Scratch s("what_to_do");
  struct Case {
    const char* name;
    const char* text;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"points.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n", "what to do: a point cloud"},
      {"fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
       "what to do: keep at most two faces on each edge"},
      {"pinched.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n",
       "what to do: give each fan of faces its own copy of the vertex"},
      {"flipped.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 3 2\n",
       "what to do: --orient repairs it: run the command again with --orient"},
  };
  for (const Case& c : cases)
    for (const char* command : {"remesh ", "encode "}) {
      const Run run = run_cli(command + s.file(c.name, c.text) + " -o " + s.path("out.ply"));
      INFO(command << c.name << ":\n" << run.output);
      CHECK(run.exit_code == 3);
      CHECK_THAT(run.output, Catch::Contains(s.path(c.name) + ": " + c.says));
    }
  // A refusal for another reason than the mesh's validity says nothing more.
  const Run flat = run_cli("remesh " + s.file("line.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n3 0 1 2\n3 0 2 3\n") +
                           " -o " + s.path("out.ply"));
  CHECK(flat.exit_code == 3);
  CHECK_THAT(flat.output, !Catch::Contains("what to do"));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: --weld joins an unwelded cube's faces into one closed surface before remeshing", "[cli][hostile]") {
  Scratch s("weld");
  const std::string input = s.file("pieces.off", "OFF\n24 6 0\n0 0 0\n0 1 0\n1 1 0\n1 0 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n1 0 0\n1 1 0\n1 1 1\n1 0 1\n1 1 0\n0 1 0\n0 1 1\n1 1 1\n0 1 0\n0 0 0\n0 0 1\n0 1 1\n4 0 1 2 3\n4 4 5 6 7\n4 8 9 10 11\n4 12 13 14 15\n4 16 17 18 19\n4 20 21 22 23\n");
  const Run apart = run_cli("remesh " + input + " -o " + s.path("apart.off"));
  INFO(apart.output);
  REQUIRE(apart.exit_code == 0);
  CHECK_THAT(apart.output, Catch::Contains("note: 16 vertices lie exactly on other vertices"));
  CHECK_THAT(run_cli("info " + s.path("apart.off")).output, Catch::Contains("components:              6"));
  CHECK_THAT(run_cli("info " + input).output, Catch::Contains("with --weld:             triangle codec ok"));
  const Run welded = run_cli("remesh " + input + " -o " + s.path("welded.off") + " --weld");
  INFO(welded.output);
  REQUIRE(welded.exit_code == 0);
  CHECK_THAT(welded.output, Catch::Contains("pieces.off: welded: 16 coincident vertices joined"));
  CHECK_THAT(welded.output, !Catch::Contains("note: "));
  const Run info = run_cli("info " + s.path("welded.off"));
  CHECK_THAT(info.output, Catch::Contains("components:              1"));
  CHECK_THAT(info.output, Catch::Contains("closed"));
  // Two tetrahedra that only touch at a corner, each with a vertex of its own there: joined, that
  // corner would be non-manifold, and the note says so instead of advising --weld.
  const std::string touching = s.file("touching.off",
                                      "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n-1 0 0\n0 -1 0\n0 0 -1\n"
                                      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 5 6\n3 4 7 5\n3 4 6 7\n3 5 7 6\n");
  const Run apart_tets = run_cli("remesh " + touching + " -o " + s.path("tets.off"));
  INFO(apart_tets.output);
  CHECK(apart_tets.exit_code == 0);
  CHECK_THAT(apart_tets.output, Catch::Contains("note: 1 vertices lie exactly on other vertices"));
  CHECK_THAT(apart_tets.output, Catch::Contains("joined they would not make a mesh the remesher takes: 1 non-manifold vertex"));
  // encode takes the same flag.
  const Run encode = run_cli("encode " + input + " -o " + s.path("welded.mlz") + " --weld");
  CHECK(encode.exit_code == 0);
  CHECK_THAT(encode.output, Catch::Contains("welded: 16 coincident vertices joined"));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: --orient turns over the faces written the other way, where remesh refused them", "[cli][hostile]") {
  Scratch s("orient");
  // An octahedron with two faces written in the other turn.
  const std::string input = s.file("shuffled.off",
                                   "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
                                   "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 4 3 0\n3 2 0 5\n3 1 2 5\n3 5 1 3\n3 3 0 5\n");
  const Run refused = run_cli("remesh " + input + " -o " + s.path("out.off"));
  CHECK(refused.exit_code == 3);
  CHECK_THAT(refused.output, Catch::Contains("orientation is inconsistent"));
  CHECK_THAT(run_cli("info " + input).output, Catch::Contains("with --orient:           triangle codec ok"));
  const Run oriented = run_cli("remesh " + input + " -o " + s.path("out.off") + " --orient");
  INFO(oriented.output);
  CHECK(oriented.exit_code == 0);
  CHECK_THAT(oriented.output, Catch::Contains("shuffled.off: oriented: 2 faces turned over in 1 components"));
  CHECK_THAT(run_cli("info " + s.path("out.off")).output, Catch::Contains("consistently oriented:   yes"));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: coordinates near the float limits round trip and beyond them nothing is written", "[cli][hostile]") {
  Scratch s("float_limits");
  // Near the largest and smallest normal floats: the codec keeps them finite.
  for (const char* scale : {"3e38", "1e-37"}) {
    const std::string tet = std::string("OFF\n4 4 0\n0 0 0\n") + scale + " 0 0\n0 " + scale + " 0\n0 0 -" + scale +
                            "\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    INFO("scale " << scale);
    REQUIRE(run_cli("subdivide " + s.file("tet.off", tet) + " -o " + s.path("sub.off") + " --scheme loop --levels 2").exit_code == 0);
    REQUIRE(run_cli("encode " + s.path("sub.off") + " -o " + s.path("sub.mlz")).exit_code == 0);
    const Run decode = run_cli("decode " + s.path("sub.mlz") + " -o " + s.path("dec.off"));
    CHECK(decode.exit_code == 0);
    const Run info = run_cli("info " + s.path("dec.off"));
    CHECK(info.exit_code == 0);
    CHECK_THAT(info.output, Catch::Contains("non-finite vertices:     0"));
  }
  // A butterfly overshoot of a tetrahedron spanning the float range leaves it: refused (exit 4).
  const std::string max = "OFF\n4 4 0\n-3.4e38 -3.4e38 -3.4e38\n3.4e38 -3.4e38 3.4e38\n-3.4e38 3.4e38 3.4e38\n"
                          "3.4e38 3.4e38 -3.4e38\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const Run r = run_cli("subdivide " + s.file("max.off", max) + " -o " + s.path("max_sub.off") + " --scheme butterfly --levels 2");
  INFO(r.output);
  CHECK(r.exit_code == 4);
  CHECK_THAT(r.output, Catch::Contains("max_sub.off: vertex 4 has coordinate"));
  CHECK_THAT(r.output, Catch::Contains("outside the 32-bit float range"));
  CHECK_FALSE(fs::exists(s.path("max_sub.off")));
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: every command refuses to write over its input", "[cli][hostile]") {
  Scratch s("same_output");
  const std::string tet = s.file("tet.off", kTetrahedron);
  REQUIRE(run_cli("subdivide " + tet + " -o " + s.path("sub.off") + " --scheme loop --levels 1").exit_code == 0);
  REQUIRE(run_cli("encode " + s.path("sub.off") + " -o " + s.path("sub.mlz")).exit_code == 0);
  const std::string sub = s.path("sub.off"), mlz = s.path("sub.mlz");
  fs::create_symlink(mlz, s.path("link.mlz"));
  const std::string sub_before = read_text(sub), mlz_before = read_text(mlz);
  for (const std::string& command :
       {"subdivide " + sub + " -o " + sub + " --scheme loop --levels 1", "limit " + sub + " -o " + sub + " --scheme loop",
        "fit " + sub + " -o " + sub + " --scheme loop", "encode " + sub + " -o " + sub,
        "decode " + mlz + " -o " + mlz, "truncate " + mlz + " --bytes 50 -o " + mlz,
        "truncate " + mlz + " --bytes 50 -o " + s.path("link.mlz"),
        "truncate " + mlz + " --psnr 60 --reference " + sub + " -o " + sub, "stream " + mlz + " --every 40 --csv " + mlz,
        "stream " + mlz + " --every 40 --reference " + sub + " --csv " + sub}) {
    const Run r = run_cli(command);
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 4);
    CHECK_THAT(r.output, Catch::Contains("it is the input file"));
  }
  CHECK(read_text(sub) == sub_before);
  CHECK(read_text(mlz) == mlz_before);
  CHECK(s.temporaries().empty());
}

TEST_CASE("CLI: a real-number option given nan or inf is a bad argument, not ignored", "[cli][hostile]") {
  // CLI11's Range and PositiveNumber let "nan" through; `encode --psnr nan` used to write the
  // whole stream as if no target had been given.
  Scratch s("non_finite");
  const std::string tet = s.file("tet.off", kTetrahedron);
  REQUIRE(run_cli("encode " + tet + " -o " + s.path("t.mlz")).exit_code == 0);
  for (const std::string& command :
       {"encode " + tet + " -o " + s.path("a.mlz") + " --psnr nan", "encode " + tet + " -o " + s.path("a.mlz") + " --bpv nan",
        "encode " + tet + " -o " + s.path("a.mlz") + " --psnr inf",
        "truncate " + s.path("t.mlz") + " -o " + s.path("a.mlz") + " --psnr nan --reference " + tet,
        "remesh " + tet + " -o " + s.path("a.ply") + " --density nan",
        "remesh " + tet + " -o " + s.path("a.ply") + " --feature-angle nan",
        "fit " + tet + " -o " + s.path("a.off") + " --tolerance nan", "rd " + tet + " -o " + s.path("rd") + " --bpv 1,nan"}) {
    const Run r = run_cli(command);
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 2);
  }
  CHECK_FALSE(fs::exists(s.path("a.mlz")));
  CHECK_FALSE(fs::exists(s.path("a.ply")));
  CHECK_FALSE(fs::exists(s.path("a.off")));
}

TEST_CASE("CLI: a run interrupted by a signal leaves the complete output or none", "[cli][hostile]") {
  // A subdivision big enough that writing takes a while (ascii OBJ of 131 k vertices), killed
  // with SIGINT or SIGTERM at delays spread over its whole run time (and once not at all): whatever
  // the moment, the directory holds no temporary file, and an output file, if any, is the whole mesh.
  Scratch s("interrupt");
  const std::string tet = s.file("tet.off", kTetrahedron);
  const auto start = std::chrono::steady_clock::now();
  REQUIRE(run_cli("subdivide " + tet + " -o " + s.path("reference.obj") + " --scheme loop --levels 8").exit_code == 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string reference = read_text(s.path("reference.obj"));
  REQUIRE(reference.size() > 4000000);
  int killed = 0, finished = 0;
  for (int step = 0; step <= 12; ++step) {
    const auto delay = std::chrono::duration<double>(seconds * step / 10);
    const std::string out = s.path("out.obj");
    fs::remove(out);
    const std::string cli = MESHLIFT_CLI;
    std::vector<std::string> args = {cli, "subdivide", tet, "-o", out, "--scheme", "loop", "--levels", "8"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    REQUIRE(posix_spawn(&pid, cli.c_str(), &actions, nullptr, argv.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&actions);
    // The last run is not interrupted: on a loaded machine a run can take longer than 1.1x the
    // reference run, and then no signal would come late enough for a finished run (seen in CI
    // runs sharing the machine).
    if (step < 12) {
      std::this_thread::sleep_for(delay);
      ::kill(pid, step % 2 ? SIGINT : SIGTERM);
    }
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    if (WIFSIGNALED(status)) ++killed;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) ++finished;
    INFO("signal after " << delay.count() << " s of a " << seconds << " s run");
    CHECK(s.temporaries().empty());
    if (fs::exists(out)) CHECK(read_text(out) == reference);
  }
  CHECK(killed > 0);
  CHECK(finished > 0);
}
