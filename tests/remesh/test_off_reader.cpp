// meshlift's own OFF reader (remesh/off_reader.h) through read_mesh: the Geomview grammar
// (keyword prefixes, comments, colours, polygons, line endings), hostile counts and indices with
// errors naming the element and line, every-byte truncation, and the libcgal-demo corpus read
// exactly as OpenMesh's OFF reader reads it.
#include <catch2/catch.hpp>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"
#include "test_meshes.h"
#include "test_reader_files.h"

namespace fs = std::filesystem;
using namespace meshlift;

namespace {

using test::Scratch;

/// read_mesh on `text` saved as an .off file.
PolygonMesh read_text(const Scratch& scratch, const std::string& text) {
  return read_mesh(scratch.write("mesh.off", text));
}

/// The message read_mesh throws for `text` saved as an .off file (test::read_error).
std::string error_for(const Scratch& scratch, const std::string& text) { return test::read_error(scratch, "off", text); }

/// The tetrahedron every variant below spells in its own way.
const std::vector<double> kTetPositions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
const std::vector<std::uint32_t> kTetOffsets = {0, 3, 6, 9, 12};
const std::vector<std::uint32_t> kTetIndices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
const std::string kTet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

void require_tet(const PolygonMesh& m) {
  REQUIRE(m.positions == kTetPositions);
  REQUIRE(m.face_offsets == kTetOffsets);
  REQUIRE(m.face_indices == kTetIndices);
}

/// OpenMesh's OFF reader as the oracle: vertices and faces exactly as it hands them to an
/// importer (OpenMesh's own ImporterT would drop or split non-manifold faces).
struct RecordingImporter : OpenMesh::IO::ImporterT<OpenMesh::PolyMesh_ArrayKernelT<>> {
  using Base = OpenMesh::IO::ImporterT<OpenMesh::PolyMesh_ArrayKernelT<>>;
  explicit RecordingImporter(OpenMesh::PolyMesh_ArrayKernelT<>& mesh) : Base(mesh) {}
  PolygonMesh recorded;
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    recorded.positions.insert(recorded.positions.end(), {p[0], p[1], p[2]});
    return Base::add_vertex(p);
  }
  OpenMesh::FaceHandle add_face(const VHandles& corners) override {
    for (const auto vh : corners) recorded.face_indices.push_back(static_cast<std::uint32_t>(vh.idx()));
    recorded.face_offsets.push_back(static_cast<std::uint32_t>(recorded.face_indices.size()));
    return OpenMesh::FaceHandle();
  }
};

PolygonMesh read_with_openmesh(const std::string& path) {
  OpenMesh::PolyMesh_ArrayKernelT<> mesh;
  RecordingImporter importer(mesh);
  OpenMesh::IO::Options options;
  // Its complaints about colour specs ("Error in file format") go to std::cerr: keep them out.
  std::ostringstream complaints;
  std::streambuf* const cerr = std::cerr.rdbuf(complaints.rdbuf());
  const bool read = OpenMesh::IO::IOManager().read(path, importer, options);
  std::cerr.rdbuf(cerr);
  REQUIRE(read);
  return importer.recorded;
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("OFF reader: every corpus .off file reads as OpenMesh's OFF reader reads it", "[corpus][off]") {
  // OpenMesh's reader knows no comments: it takes the first line as the keyword line (and cannot
  // read the files that open with comment lines) and reads "# vertices" as numbers (all zeros for
  // cube_poly.off and prim.off). Its oracle reading is of a copy with every comment removed and
  // the lines before the keyword dropped. It also reads a face colour only under a C keyword;
  // files with face colours under plain OFF (listed, and checked to be misread by OpenMesh as
  // they are) are compared with OpenMesh reading them as COFF.
  const std::map<std::string, const char*> face_colours_under_plain_off = {{"quint_tris.off", ".7 0 0 after each face"}};
  Scratch scratch("corpus");
  std::size_t compared = 0, with_comments = 0;
  for (const auto& entry : fs::directory_iterator(test::corpus_directory())) {
    if (entry.path().extension() != ".off") continue;
    const std::string name = entry.path().filename().string();
    INFO(name);
    std::string text = file_text(entry.path().string());
    std::string oracle_path = entry.path().string();
    if (text.find('#') != std::string::npos) {
      ++with_comments;
      for (std::size_t hash; (hash = text.find('#')) != std::string::npos;)
        text.erase(hash, text.find_first_of("\r\n", hash) - hash);
      text.erase(0, text.find_first_not_of(" \t\r\n"));
      oracle_path = scratch.write("uncommented.off", text);
    }
    if (face_colours_under_plain_off.count(name)) {
      const PolygonMesh misread = read_with_openmesh(oracle_path);
      bool short_face = false;
      for (std::size_t f = 0; f < misread.face_count(); ++f) short_face |= misread.face_size(f) < 3;
      REQUIRE(short_face);
      REQUIRE(text.rfind("OFF\n", 0) == 0);
      oracle_path = scratch.write("as_coff.off", "C" + text);
    }
    const PolygonMesh expected = read_with_openmesh(oracle_path);
    const PolygonMesh read = read_mesh(entry.path().string());
    REQUIRE(read.vertex_count() > 0);
    REQUIRE(read.positions == expected.positions);  // both float values, compared exactly
    REQUIRE(read.face_offsets == expected.face_offsets);
    REQUIRE(read.face_indices == expected.face_indices);
    ++compared;
  }
  // libcgal-demo's data/meshes: 138 .off files, 9 of them with comments.
  CHECK(compared == 138);
  CHECK(with_comments == 9);
  REQUIRE(compared > 0);
}

TEST_CASE("OFF reader: comments, keyword variants and per-vertex extras", "[off]") {
  Scratch scratch("variants");
  const std::map<std::string, std::string> spellings = {
      {"plain", kTet},
      {"comments everywhere",
       "# made by hand\n\nOFF # keyword\n# counts next\n4 4 0\n0 0 0 # origin\n1 0 0#x\n0 1 0\n\n0 0 1\n"
       "# faces\n3 0 2 1\n3 0 1 3 # a comment after a face\n3 0 3 2\n3 1 2 3\n# end\n"},
      {"no keyword", "4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"counts on the keyword line", "OFF 4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"no edge count", "OFF\n4 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"records across lines", "OFF\n4\n4 0\n0\n0 0\n1 0 0\n0 1 0\n0 0 1\n3\n0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"tabs, signs, exponents", "OFF\n4\t4\t0\n+0 -0e0 0.\n1e0 0 0\n0 .1E1 0\n0 0 1.000\n3 +0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3"},
      {"COFF, RGBA integers", "COFF\n4 4 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n0 0 1 9 9 9 9\n"
                              "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"COFF, RGB floats and comments", "COFF\n4 4 0\n0 0 0 0.9 0 0 #red\n1 0 0 0 0.9 0#green\n0 1 0 0 0 .9\n"
                                        "0 0 1 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"NOFF", "NOFF\n4 4 0\n0 0 0 0 0 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"CNOFF", "CNOFF\n4 4 0\n0 0 0 0 0 -1 1 0 0 1\n1 0 0 1 0 0 0 1 0 1\n0 1 0 0 1 0 0 0 1 1\n0 0 1 0 0 1 1 1 1\n"
                "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"STOFF", "STOFF\n4 4 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n0 0 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"STCNOFF", "STCNOFF\n4 4 0\n0 0 0 0 0 -1 1 0 0 0 0\n1 0 0 1 0 0 0 1 0 1 1 0\n0 1 0 0 1 0 0 0 1 0 1\n"
                  "0 0 1 0 0 1 1 1 1 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"nOFF, dimension 3", "nOFF 3\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"4OFF, homogeneous", "4OFF\n4 4 0\n0 0 0 1\n2 0 0 2\n0 -3 0 -3\n0 0 0.5 0.5\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"face colours under OFF",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 255 0 0\n3 0 1 3 .7 0 0\n3 0 3 2 5\n3 1 2 3 0.1 0.2 0.3 1\n"},
      {"face colours under COFF", "COFF\n4 4 0\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n0 0 1 1 1 1\n"
                                  "3 0 2 1 255 0 0 255\n3 0 1 3\n3 0 3 2 7\n3 1 2 3 0.5 0.5 0.5\n"},
      {"CRLF", "OFF\r\n4 4 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n3 0 2 1 1 0 0\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n"},
      {"CR only", "OFF\r4 4 0\r0 0 0\r1 0 0\r0 1 0\r0 0 1\r3 0 2 1 1 0 0\r3 0 1 3 1 0 0\r3 0 3 2\r3 1 2 3\r"},
      {"UTF-8 byte-order mark", "\xEF\xBB\xBFOFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"data after the last face", kTet + "3 0 1 2\nwhatever follows\n"},
  };
  for (const auto& [name, text] : spellings) {
    INFO(name);
    require_tet(read_text(scratch, text));
  }
}

TEST_CASE("OFF reader: polygons, repeated corners and coordinates are kept as written", "[off]") {
  Scratch scratch("polygons");
  // A unit cube's bottom as a quad, a pentagon, a triangle with a repeated corner.
  const PolygonMesh m = read_text(scratch,
                                  "OFF\n6 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0.25\n-1e-50 3.4e38 0.1\n"
                                  "4 0 1 2 3\n5 0 1 2 4 3 0.5 0.5 0.5\n3 5 5 0\n");
  REQUIRE(m.face_offsets == std::vector<std::uint32_t>{0, 4, 9, 12});
  REQUIRE(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 3, 0, 1, 2, 4, 3, 5, 5, 0});
  // Float parsing, correctly rounded; a value below the float range becomes -0.
  REQUIRE(m.positions[12] == double(0.5f));
  REQUIRE(m.positions[13] == double(1.5f));
  REQUIRE(m.positions[14] == double(0.25f));
  REQUIRE(m.positions[15] == 0.0);
  REQUIRE(std::signbit(m.positions[15]));
  REQUIRE(m.positions[16] == double(3.4e38f));
  REQUIRE(m.positions[17] == double(0.1f));
  REQUIRE(m.positions[17] != 0.1);
}

TEST_CASE("OFF reader: errors name the element, the token and the line", "[off]") {
  Scratch scratch("errors");
  const std::string vertices = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";  // faces start on line 7
  const std::vector<std::pair<std::string, std::string>> cases = {
      {vertices + "3 0 1 2\n3 1 2 9\n", "face 1 references vertex 9 but the file has 4 vertices (line 8)"},
      {vertices + "3 0 1 2\n3 1 -1 2\n", "face 1 references vertex -1 but the file has 4 vertices (line 8)"},
      {vertices + "3 0 1 99999999999999999999999\n", "face 0 references vertex 99999999999999999999999 but the file has 4 vertices (line 7)"},
      {vertices + "3 0 1 2.0\n", "face 0 has corner '2.0', not a vertex index (line 7)"},
      {vertices + "3 0 1 2\n0\n", "face 1 has no corners (line 8)"},
      {vertices + "3 0 1 2\n2 0 1\n", "face 1 has 2 corners, fewer than 3 (line 8)"},
      {vertices + "3 0 1 2\n-3 0 1 2\n", "face 1 has -3 corners, fewer than 3 (line 8)"},
      {vertices + "3 0 1 2\n5 0 1 2 3 0\n", "face 1 claims 5 corners, more than the file's 4 vertices (line 8)"},
      {vertices + "3 0 1 2\nx 0 1 2\n", "face 1 has corner count 'x', not an integer (line 8)"},
      {vertices + "3 0 1 2\n", "file ends before face 1 of 2 (line 8)"},
      {vertices + "3 0 1 2\n3 0 1", "face 1 claims 3 corners, more than the remaining 4 bytes of the file hold (line 8)"},
      {vertices + "3 0 1 2\n3 0 1 # cut short\n", "file ends in face 1 of 2 (line 9)"},
      {"OFF\n4 2 0\n0 0 0\n1 0 0\n# a comment line\n0 nan 0\n0 0 1\n3 0 1 2\n3 1 2 3\n",
       "vertex 2 has a coordinate that is missing or not a finite number: 'nan' (line 6)"},
      {"OFF\n2 0 0\n0 0 0\n1 inf 0\n", "vertex 1 has a coordinate that is missing or not a finite number: 'inf' (line 4)"},
      {"OFF\n2 0 0\n0 0 0\n1 1e39 0\n", "vertex 1 has a coordinate that is missing or not a finite number: '1e39' (line 4)"},
      {"OFF\n2 0 0\n0 0 0\n1 0x1p3 0\n", "vertex 1 has a coordinate that is missing or not a finite number: '0x1p3' (line 4)"},
      {"OFF\n2 0 0\n0 0 0 # padding\n1 0\n", "vertex 1 has a coordinate that is missing or not a finite number: end of file (line 5)"},
      {"OFF\n1 0 0\n1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32 33 34 35 36 37 38 39\n"
       "x123456789012345678901234567890123456789012345678901234567890 0 0\n",
       "no error"},
      {"OFF\n1 0 0\nx123456789012345678901234567890123456789012345678901234567890 0 0\n",
       "vertex 0 has a coordinate that is missing or not a finite number: 'x123456789012345678901234567890123456789...' (line 3)"},
      {std::string("OFF\n1 0 0\n0 \x01\xff\0 0\n", 18),
       "vertex 0 has a coordinate that is missing or not a finite number: '\\x01\\xff\\x00' (line 3)"},
      {"4OFF\n1 0 0\n1 1 1 0\n", "vertex 0 has a coordinate that is missing or not a finite number: w = '0' (line 3)"},
      {"NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0\n0 1 0 0 0 1\n3 0 1 2\n",
       "vertex 1 has 0 numbers after its coordinates, but the NOFF header declares at least 3 (normal: 3, colour: 3 or 4, "
       "texture coordinates: 2) (line 4)"},
      {"NOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "vertex 0 has 0 numbers after its coordinates, but the NOFF header declares at least 3 (normal: 3, colour: 3 or 4, "
       "texture coordinates: 2) (line 3)"},
      {"COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 1 0\n0 1 0 0 0 1\n3 0 1 2\n",
       "vertex 1 has 2 numbers after its coordinates, but the COFF header declares at least 3 (normal: 3, colour: 3 or 4, "
       "texture coordinates: 2) (line 4)"},
      {"OFF BINARY\n", "binary OFF is not supported (only ascii OFF is read) (line 1)"},
      {"NCOFF\n3 1 0\n", "unknown OFF header keyword 'NCOFF' (expected [ST][C][N][4][n]OFF) (line 1)"},
      {"ply\nformat ascii 1.0\n", "unknown OFF header keyword 'ply' (expected [ST][C][N][4][n]OFF) (line 1)"},
      {"nOFF 2\n3 1 0\n0 0\n1 0\n0 1\n3 0 1 2\n", "nOFF vertex dimension '2' is not supported (only 3) (line 1)"},
      {"OFF\n", "OFF header has no vertex and face counts (line 2)"},
      {"# only a comment\n\n", "OFF header has no vertex and face counts (line 3)"},
      {"OFF\n4 x 0\n", "OFF header has no vertex and face counts (line 2)"},
      {"OFF\n-4 1 0\n0 0 0\n", "OFF header has a negative count (-4 vertices, 1 faces) (line 2)"},
      {"OFF\n4 -1 0\n0 0 0\n", "OFF header has a negative count (4 vertices, -1 faces) (line 2)"},
      {"OFF\n0 2 0-3\n", "file has no vertices (line 2)"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    REQUIRE(error_for(scratch, text) == message);
  }
}

TEST_CASE("OFF reader: counts beyond what the file can hold are refused, exactly at the byte budget", "[off]") {
  Scratch scratch("counts");
  REQUIRE(error_for(scratch, "OFF\n4000000000 4000000000 0\n1 2 3\n") ==
          "OFF header claims 4000000000 vertices and 4000000000 faces, more than the remaining 6 bytes of the file hold "
          "(line 2)");
  REQUIRE(error_for(scratch, "OFF\n99999999999999999999999 1 0\n0 0 0\n") ==
          "OFF header claims 99999999999999999999999 vertices and 1 faces, more than the remaining 6 bytes of the file "
          "hold (line 2)");
  REQUIRE(error_for(scratch, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n") ==
          "face 0 claims 4000000000 corners, more than the file's 3 vertices (line 6)");
  // The budget is exact: V vertices and F faces need at least 2 (3V + F) - 1 bytes after the
  // counts line (a face counted by its corner count; its corners are held to the bytes left when
  // it is read). 3 vertices and 1 face: 19 bytes get past the counts, 18 do not.
  const std::string data = "0 0 0\n1 0 0\n0 1 0\n0";
  REQUIRE(data.size() == 19);
  REQUIRE(error_for(scratch, "OFF\n3 1 0\n" + data) == "face 0 has no corners (line 6)");
  REQUIRE(error_for(scratch, "OFF\n3 1 0\n" + data.substr(0, 18)) ==
          "OFF header claims 3 vertices and 1 faces, more than the remaining 18 bytes of the file hold (line 2)");
  REQUIRE(read_text(scratch, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2").face_indices == std::vector<std::uint32_t>{0, 1, 2});
  // A face's corners are held to the bytes left as well: 40 corners cannot fit in 8 bytes.
  std::string many = "OFF\n40 1 0\n";
  for (int v = 0; v < 40; ++v) many += "0 0 0\n";
  REQUIRE(error_for(scratch, many + "40 0 1 2\n") == "face 0 claims 40 corners, more than the remaining 7 bytes of the file hold (line 43)");
}

TEST_CASE("OFF reader: every truncation of a file is refused or reads the whole mesh", "[off]") {
  Scratch scratch("truncation");
  // Multi-digit indices on the last line: a cut inside them makes another valid number, which
  // no text format can notice, so a prefix may read only once the last face's last token has begun.
  const std::string text = "COFF # a comment\r\n12 3 0\r\n" + [] {
    std::string v;
    for (int i = 0; i < 12; ++i) v += std::to_string(i) + " 0." + std::to_string(i) + " -1e-2 255 0 0\r\n";
    return v;
  }() + "3 0 1 2 1 0 0\r\n4 3 4 5 6\r\n5 7 8 9 10 11";
  const std::size_t last_token = text.rfind(' ') + 1;
  const PolygonMesh whole = read_text(scratch, text);
  REQUIRE(whole.face_offsets == std::vector<std::uint32_t>{0, 3, 7, 12});
  for (std::size_t cut = 0; cut < text.size(); ++cut) {
    INFO("cut at byte " << cut);
    const std::string prefix = text.substr(0, cut);
    if (cut > last_token) {
      const PolygonMesh m = read_text(scratch, prefix);
      REQUIRE(m.positions == whole.positions);
      REQUIRE(m.face_offsets == whole.face_offsets);
      continue;
    }
    const std::string message = error_for(scratch, prefix);
    const bool expected = message == "file is empty" || message.find("claims") != std::string::npos ||
                          message.find("has a coordinate that is missing or not a finite number") != std::string::npos ||
                          message.rfind("file ends", 0) == 0 ||
                          message.rfind("OFF header has no vertex and face counts", 0) == 0 ||
                          message.rfind("unknown OFF header keyword", 0) == 0 ||
                          message.rfind("file has no vertices", 0) == 0 ||
                          message.find("numbers after its coordinates") != std::string::npos;
    INFO(message);
    REQUIRE(expected);
  }
}
