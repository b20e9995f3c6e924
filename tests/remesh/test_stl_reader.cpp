// meshlift's own STL reader (remesh/stl_reader.h) through read_mesh: binary and ascii, corners
// merged into vertices by exact position in the order of first use, errors naming the facet or
// the sizes, and every truncation refused or read whole.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"
#include "test_reader_files.h"

using namespace meshlift;

namespace {

void put_float(std::string& out, float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, 4);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((u >> (8 * i)) & 0xff));
}

/// A binary STL of `triangles` (9 floats each), its header starting with `header`.
std::string binary_stl(const std::vector<std::vector<float>>& triangles, const std::string& header = "test") {
  std::string out = header;
  out.resize(80, ' ');
  const auto n = static_cast<std::uint32_t>(triangles.size());
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((n >> (8 * i)) & 0xff));
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) put_float(out, 0.0f);  // the normal, ignored
    for (const float x : t) put_float(out, x);
    out += std::string(2, '\0');
  }
  return out;
}

}  // namespace

TEST_CASE("STL reader: binary corners merge by exact position, in the order of first use", "[stl]") {
  test::Scratch scratch("binary");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Two triangles on a shared edge (one corner there written -0 instead of +0), then a triangle
  // with a NaN corner, twice: NaN equals nothing, so each NaN corner is a vertex of its own.
  const std::vector<std::vector<float>> triangles = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                     {1, 0, 0, -0.0f, 1, 0, 1, 1, 0},
                                                     {nan, 0, 0, 1, 1, 0, 2, 2, 2},
                                                     {nan, 0, 0, 2, 2, 2, 1, 1, 0}};
  // A header that starts with "solid" (some exporters write one): the exact size says binary.
  for (const std::string header : {"binary", "solid but binary"}) {
    INFO(header);
    const PolygonMesh m = read_mesh(scratch.write("m.stl", binary_stl(triangles, header)));
    REQUIRE(m.vertex_count() == 7);
    CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 1, 2, 3, 4, 3, 5, 6, 5, 3});
    CHECK(m.positions[3 * 2] == 0.0);
    CHECK(std::isnan(m.positions[3 * 4]));
    CHECK(std::isnan(m.positions[3 * 6]));
  }
}

TEST_CASE("STL reader: infinite corners are vertices of their own, as weld.h defines coincident", "[stl]") {
  test::Scratch scratch("infinite");
  const float inf = std::numeric_limits<float>::infinity();
  const PolygonMesh m = read_mesh(scratch.write(
      "inf.stl", binary_stl({{inf, 0, 0, 1, 0, 0, 0, 1, 0}, {inf, 0, 0, 0, 1, 0, 1, 0, 0}})));
  CHECK(m.vertex_count() == 4);
  CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 3, 2, 1});
}

TEST_CASE("STL reader: ascii facets, names, white space and line ends", "[stl]") {
  test::Scratch scratch("ascii");
  const std::string text =
      "solid my part\r\n  facet normal 0 0 1\r\n    outer loop\r\n      vertex 0 0 0\r\n      vertex 1 0 0\r\n"
      "      vertex 0 1 0\r\n    endloop\r\n  endfacet\r\nfacet normal 0 0 1 outer loop vertex 1 0 0 vertex +1 1e0 0\n"
      "vertex 0 1 0 endloop endfacet\nendsolid my part\n";
  const PolygonMesh m = read_mesh(scratch.write("a.stl", text));
  CHECK(m.positions == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2});
  // endsolid may be missing; coordinates are floats as strtof rounds them.
  const PolygonMesh f = read_mesh(scratch.write(
      "b.stl", "solid\nfacet normal 0 0 0\nouter loop\nvertex 0.1 0 0\nvertex 1 0 0\nvertex 0 1e-50 0\nendloop\nendfacet\n"));
  CHECK(f.positions[0] == static_cast<double>(0.1f));
  CHECK(f.positions[7] == 0.0);
}

TEST_CASE("STL reader: several solids, and keywords in capitals", "[stl]") {
  test::Scratch scratch("solids");
  const std::string text =
      "SOLID part one\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\n"
      "ENDSOLID part one\nsolid part two\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid part two\n";
  const PolygonMesh m = read_mesh(scratch.write("parts.stl", text));
  CHECK(m.positions == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2});
  CHECK_THAT(read_error(scratch, "stl", text + "garbage\n"), Catch::Contains("expected 'solid' or the end of the file after 'endsolid'"));
}

TEST_CASE("STL reader: errors name the facet or the sizes", "[stl]") {
  test::Scratch scratch("errors");
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  CHECK_THAT(read_error(scratch, "stl", "hello"), Catch::Contains("not an STL file"));
  std::string binary = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}});
  CHECK_THAT(read_error(scratch, "stl", binary + "x"), Catch::Contains("binary STL claims 1 triangles: 134 bytes, but the file has 135"));
  binary[80] = '\xff';  // claims 255 triangles
  CHECK_THAT(read_error(scratch, "stl", binary), Catch::Contains("claims 255 triangles"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\n" + facet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"),
             Catch::Contains("ascii STL facet 1: expected 'vertex', found 'endloop'"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\n" + facet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                                      "vertex 0 1 0\nvertex 1 1 1\nendloop\nendfacet\n"),
             Catch::Contains("expected 'endloop', found 'vertex'"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\n" + facet + "vertex 0 0 0\n"), Catch::Contains("expected 'facet' or 'endsolid'"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 nan 0\n"),
             Catch::Contains("'nan' is not a finite coordinate"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 1e39 0\n"),
             Catch::Contains("'1e39' is not a finite coordinate"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 1e5000 0\n"),
             Catch::Contains("'1e5000' is not a finite coordinate"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0"),
             Catch::Contains("'' is not a finite coordinate"));
  CHECK_THAT(read_error(scratch, "stl", "solid x\nendsolid x\n"), Catch::Contains("no vertices"));
}

TEST_CASE("STL reader: every truncation of a file is refused or reads whole facets", "[stl]") {
  test::Scratch scratch("truncation");
  const std::string ascii =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  const std::string binary = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});
  for (const std::string& whole : {ascii, binary})
    for (std::size_t n = 0; n <= whole.size(); ++n) {
      INFO(n);
      try {
        const PolygonMesh m = read_mesh(scratch.write("cut.stl", whole.substr(0, n)));
        CHECK(m.face_count() >= 1);
        CHECK(m.face_indices.size() == 3 * m.face_count());
      } catch (const MeshIOError&) {
      }
    }
}
