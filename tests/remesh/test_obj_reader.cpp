// meshlift's own OBJ reader (remesh/obj_reader.h) through read_mesh: the statements it keeps
// and those it skips, corner forms and relative indices, line endings, errors naming the line,
// every truncation, and a file with texture and normal indices read as OpenMesh's OBJ reader
// reads it.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"
#include "test_meshes.h"
#include "test_reader_files.h"

using namespace meshlift;

TEST_CASE("OBJ reader: vertices and faces kept, every other statement skipped", "[obj]") {
  test::Scratch scratch("grammar");
  // A BOM, CRLF and lone-CR line ends, comments, w and colours after coordinates, texture and
  // normal statements, groups and materials, lines and points, all four corner forms, relative
  // and signed indices, and faces before the vertices they name.
  const std::string text =
      "\xEF\xBB\xBF# a test\r\nmtllib a.mtl\r\no thing\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\rv 0 1 0 # third\n"
      "vt 0 0\nvn 0 0 1\ng side\nusemtl red\ns 1\n"
      "f 1 2 3\nf 1/1 2/1 +3/1\nf 1//1 3//1 4//1\nf -3/1/1 -2/1/1 -1/1/1\nl 1 2\np 3\nf 1 2 5\nv 0 0 1\nv\t2 2 2\n";
  const PolygonMesh m = read_mesh(scratch.write("grammar.obj", text));
  CHECK(m.positions == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 2, 2, 2});
  CHECK(m.face_offsets == std::vector<std::uint32_t>{0, 3, 6, 9, 12, 15});
  // -3..-1 with 3 vertices read so far: 0, 1, 2; faces 1//1 3//1 4//1 and 1 2 5 name vertices
  // listed after them.
  CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 1, 4});
  // Coordinates are floats, as strtof rounds them.
  const PolygonMesh f = read_mesh(scratch.write("float.obj", "v 0.1 1e-50 3.4e38\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  CHECK(f.positions[0] == static_cast<double>(0.1f));
  CHECK(f.positions[1] == 0.0);
  CHECK(f.positions[2] == static_cast<double>(3.4e38f));
}

TEST_CASE("OBJ reader: errors name the line", "[obj]") {
  test::Scratch scratch("errors");
  const std::string three = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  CHECK(read_error(scratch, "obj", "v 0 0\n") == "OBJ line 1: a vertex coordinate is missing or not a finite number");
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 nan 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 inf 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 1e39 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 0x10 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 1e5000 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "v 1 +-1 0\n"), Catch::Contains("OBJ line 4: a vertex coordinate"));
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2 +-1\n"), Catch::Contains("'+-1' has no integer vertex index"));
  CHECK(read_error(scratch, "obj", three + "f /1 2 3\n") == "OBJ line 4 has a face corner without a vertex index");
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 x 3\n"), Catch::Contains("OBJ line 4: face corner 'x' has no integer vertex index"));
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2.5 3\n"), Catch::Contains("'2.5' has no integer vertex index"));
  CHECK(read_error(scratch, "obj", three + "f\n") == "face 0 has no corners");
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2 0\n"), Catch::Contains("face 0 references vertex"));
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2 4\n"), Catch::Contains("face 0 references vertex 3 but the file has 3"));
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2 -4\n"), Catch::Contains("face 0 references vertex"));
  CHECK_THAT(read_error(scratch, "obj", three + "f 1 2 99999999999999999999999\n"), Catch::Contains("face 0 references vertex"));
  CHECK_THAT(read_error(scratch, "obj", "# no vertex\nf 1 2 3\n"), Catch::Contains("no vertices"));
}

TEST_CASE("OBJ reader: every truncation of a file is refused or reads what it holds", "[obj]") {
  test::Scratch scratch("truncation");
  const std::string whole = "v 0.5 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1/1/1 3/1/1 2/1/1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  for (std::size_t n = 0; n <= whole.size(); ++n) {
    INFO(n);
    try {
      const PolygonMesh m = read_mesh(scratch.write("cut.obj", whole.substr(0, n)));
      CHECK(m.vertex_count() <= 4);
      CHECK(m.face_count() <= 4);
    } catch (const MeshIOError&) {
    }
  }
}

TEST_CASE("OBJ reader: a file with texture and normal indices reads as OpenMesh's OBJ reader reads it", "[obj]") {
  // A torus of quads and triangles, its corners in all the forms, against OpenMesh's reader.
  test::Scratch scratch("oracle");
  const TriangleMesh torus = test::torus(12, 9);
  std::string text = "# torus\nvt 0 0\nvn 0 0 1\n";
  char line[128];
  for (std::size_t v = 0; v < torus.vertex_count(); ++v) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", torus.positions[3 * v], torus.positions[3 * v + 1],
                  torus.positions[3 * v + 2]);
    text += line;
  }
  const char* forms[] = {"%u", "%u/1", "%u//1", "%u/1/1"};
  for (std::size_t f = 0; f < torus.face_count(); ++f) {
    text += "f";
    for (int i = 0; i < 3; ++i) {
      text += " ";
      std::snprintf(line, sizeof line, forms[(f + i) % 4], torus.triangles[3 * f + i] + 1);
      text += line;
    }
    text += "\n";
  }
  const std::string path = scratch.write("torus.obj", text);
  test::require_as_openmesh_reads(read_mesh(path), path);
}
