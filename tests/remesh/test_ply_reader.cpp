// meshlift's own PLY reader (remesh/ply_reader.h) through read_mesh: ascii, little- and
// big-endian binary with any numeric types, extra elements and properties read past, double
// coordinates kept exactly, hostile counts and values refused with a message, every truncation
// refused or read whole, and the PLY files of the corpus read as OpenMesh's PLY reader reads them
// (but for doubles, which it rounds to floats).
#include <catch2/catch.hpp>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"
#include "test_meshes.h"
#include "test_reader_files.h"

namespace fs = std::filesystem;
using namespace meshlift;

namespace {

/// Appends x as `bytes` bytes in the given order.
template <class T>
void put(std::string& out, T x, bool big_endian) {
  std::uint64_t u = 0;
  std::memcpy(&u, &x, sizeof x);
  for (std::size_t i = 0; i < sizeof x; ++i) {
    const std::size_t shift = 8 * (big_endian ? sizeof x - 1 - i : i);
    out.push_back(static_cast<char>((u >> shift) & 0xff));
  }
}

// A tetrahedron with coordinates no float holds, one quad among its faces.
const std::vector<double> kPositions = {0.1, -0.2, 0.30000000000000004, 1e-310, 2.5, -7, 1.0 / 3, 0, 1, 5, 6, 7};
const std::vector<std::uint32_t> kOffsets = {0, 3, 6, 10};
const std::vector<std::uint32_t> kIndices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1};

/// The tetrahedron in `format`, with extras to read past: a normal and a colour per vertex, an
/// `edge` element between vertices and faces, a flags byte before each face's corners and a
/// texture-coordinate list after them.
std::string tetrahedron(const std::string& format) {
  std::string out = "ply\r\nformat " + format + " 1.0\ncomment made by a test\nobj_info none\n";
  out += "element vertex 4\nproperty double x\nproperty float nx\nproperty double y\nproperty double z\nproperty uchar red\n";
  out += "element edge 2\nproperty int vertex1\nproperty int vertex2\n";
  out += "element face 3\nproperty uchar flags\nproperty list uchar uint vertex_indices\nproperty list ushort float texcoord\n";
  out += "end_header\n";
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  auto number = [&](auto x) {
    if (ascii) {
      char text[64];
      if constexpr (std::is_floating_point_v<decltype(x)>)
        std::snprintf(text, sizeof text, "%.17g ", static_cast<double>(x));
      else
        std::snprintf(text, sizeof text, "%lld ", static_cast<long long>(x));
      out += text;
    } else {
      put(out, x, big);
    }
  };
  for (int v = 0; v < 4; ++v) {
    number(kPositions[3 * v]);
    number(0.5f);
    number(kPositions[3 * v + 1]);
    number(kPositions[3 * v + 2]);
    number(std::uint8_t{200});
    if (ascii) out += "\n";
  }
  for (int e = 0; e < 2; ++e) {
    number(std::int32_t{e});
    number(std::int32_t{e + 1});
    if (ascii) out += "\n";
  }
  for (std::size_t f = 0; f + 1 < kOffsets.size(); ++f) {
    number(std::uint8_t{7});
    number(static_cast<std::uint8_t>(kOffsets[f + 1] - kOffsets[f]));
    for (std::uint32_t c = kOffsets[f]; c < kOffsets[f + 1]; ++c) number(kIndices[c]);
    number(std::uint16_t{2});
    number(0.25f);
    number(0.75f);
    if (ascii) out += "\n";
  }
  return out;
}

}  // namespace

TEST_CASE("PLY reader: ascii, little- and big-endian binary read alike, extras read past, doubles kept", "[ply]") {
  test::Scratch scratch("formats");
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    INFO(format);
    const PolygonMesh m = read_mesh(scratch.write("tet.ply", tetrahedron(format)));
    CHECK(m.positions == kPositions);
    CHECK(m.face_offsets == kOffsets);
    CHECK(m.face_indices == kIndices);
  }
}

TEST_CASE("PLY reader: integer coordinates, negative and huge corner indices", "[ply]") {
  test::Scratch scratch("integers");
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty short x\nproperty int y\nproperty uchar z\n"
      "element face 1\nproperty list int int vertex_index\nend_header\n";
  const PolygonMesh m = read_mesh(scratch.write("ints.ply", header + "-3 +70000 255\n0 0 0\n1 1 1\n3 0 1 2\n"));
  CHECK(m.positions == std::vector<double>{-3, 70000, 255, 0, 0, 0, 1, 1, 1});
  CHECK(m.face_indices == std::vector<std::uint32_t>{0, 1, 2});
  // A negative or out-of-range corner is read_mesh's to report, by face.
  CHECK_THAT(read_error(scratch, "ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"), Catch::Contains("face 0 references vertex"));
  CHECK_THAT(read_error(scratch, "ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 99999999999 2\n"), Catch::Contains("face 0 references vertex"));
}

TEST_CASE("PLY reader: errors name the problem", "[ply]") {
  test::Scratch scratch("errors");
  const std::string vertex3 = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string face1 = "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string ascii = "ply\nformat ascii 1.0\n";
  CHECK_THAT(read_error(scratch, "ply", "PLY\n"), Catch::Contains("not a PLY file"));
  CHECK_THAT(read_error(scratch, "ply", ascii + vertex3), Catch::Contains("no end_header"));
  CHECK_THAT(read_error(scratch, "ply", "ply\n" + vertex3 + "end_header\n"), Catch::Contains("no format line"));
  CHECK_THAT(read_error(scratch, "ply", "ply\nformat ascii 2.0\n"), Catch::Contains("malformed PLY header line"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "element vertex 3.0\n"), Catch::Contains("no valid count"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "element vertex 99999999999999999999999\nend_header\n"), Catch::Contains("claims"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "property float x\n"), Catch::Contains("property before any element"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "element vertex 1\nproperty quad x\n"), Catch::Contains("unknown type"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "element face 1\nproperty list float int vertex_indices\n"),
             Catch::Contains("must be an integer type"));
  CHECK_THAT(read_error(scratch, "ply", ascii + "element vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n"),
             Catch::Contains("lacks an x, y or z"));
  CHECK_THAT(read_error(scratch, "ply", ascii + vertex3 + "element face 1\nproperty list uchar int corners\nend_header\n" + body),
             Catch::Contains("no 'vertex_indices' list"));
  // Bodies after the header `ascii + vertex3 + face1`, and what each is refused for.
  const std::pair<const char*, const char*> bodies[] = {
      {"0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "vertex 1: 'nan' is not a valid number"},
      {"0 0 0\n1 4-5 0\n0 1 0\n3 0 1 2\n", "'4-5' is not a valid number"},
      {"0 0 0\n1 1e39 0\n0 1 0\n3 0 1 2\n", "'1e39' is not a valid number"},
      {"0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "'1.5' is not a valid number"},
      {"0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", "claims -3 entries"},
      {"0 0 0\n1 0 0\n0 1 0\n0\n", "face 0 has no corners"},
      {"0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "ends inside face 0"},
      {"0 0 0\n1 1e5000 0\n0 1 0\n3 0 1 2\n", "'1e5000' is not a valid number"},
      {"0 0 0\n1 0 0\n0 1 0\n3 0 +-1 2\n", "'+-1' is not a valid number"}};
  for (const auto& [bad_body, expected] : bodies)
    CHECK_THAT(read_error(scratch, "ply", ascii + vertex3 + face1 + "end_header\n" + bad_body), Catch::Contains(expected));
  // A value below the float range is zero, as strtof makes it.
  const PolygonMesh tiny = read_mesh(scratch.write("tiny.ply", ascii + vertex3 + face1 + "end_header\n1e-50 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  CHECK(tiny.positions[0] == 0.0);
  // Binary: an element count that the bytes left cannot hold is refused before anything is kept.
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty double x\nproperty double y\n"
                       "property double z\nend_header\n";
  binary += std::string(24 * 10, '\0');
  CHECK_THAT(read_error(scratch, "ply", binary), Catch::Contains("claims 1000 vertex elements"));
}

TEST_CASE("PLY reader: elements of no properties are read past, whatever their counts", "[ply]") {
  // Each such element may claim as many items as the file has bytes; reading them one by one
  // takes the square of the file's size. No timing is asserted: here 10^11 items (1.8 MB), so a
  // reader that walks them hangs this test for many minutes instead of slowing it unnoticed.
  test::Scratch scratch("empty_elements");
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (int i = 0; i < 100000; ++i) header += "element n 1000000\n";
  header += "element vertex 3\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  std::string body;
  for (const double x : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0}) put(body, x, false);
  const PolygonMesh m = read_mesh(scratch.write("empty.ply", header + body));
  CHECK(m.positions == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  // The double precision keeps a value beyond the float range that the file's type holds.
  body.clear();
  for (const double x : {1e300, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0}) put(body, x, false);
  CHECK(read_mesh(scratch.write("wide.ply", header + body)).positions[0] == 1e300);
}

TEST_CASE("PLY reader: every truncation of a file is refused or reads the whole mesh", "[ply]") {
  test::Scratch scratch("truncation");
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    INFO(format);
    const std::string whole = tetrahedron(format);
    for (std::size_t n = 0; n < whole.size(); ++n) {
      INFO(n);
      const std::string path = scratch.write("cut.ply", whole.substr(0, n));
      try {
        const PolygonMesh m = read_mesh(path);
        // An ascii file may lose its last value's digits only: never a face or vertex.
        CHECK(m.face_offsets == kOffsets);
        CHECK(m.positions.size() == kPositions.size());
      } catch (const MeshIOError&) {
      }
    }
  }
}

TEST_CASE("PLY reader: the corpus's PLY files read as OpenMesh's PLY reader reads them", "[corpus][ply]") {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(test::corpus_directory())) {
    if (entry.path().extension() != ".ply") continue;
    INFO(entry.path());
    // OpenMesh's points are floats: a file of doubles (sphere.ply) it rounds, ours keeps.
    test::require_as_openmesh_reads(read_mesh(entry.path().string()), entry.path().string());
    ++files;
  }
  CHECK(files >= 2);
}

TEST_CASE("PLY reader: the common binary layout, read in bulk, reads as the general path does", "[ply]") {
  // Float x, y, z per vertex and a uchar-counted list of int (or uint) corners per face, the
  // layout meshlift writes, is read in bulk where its byte order is this machine's; a big-endian
  // file of the same mesh goes the general way, value by value. Both must give the same mesh, the
  // same refusals at every truncation, and the same messages for a face of no corners and for
  // corners that name no vertex.
  test::Scratch scratch("bulk");
  auto file = [](bool big, const std::string& corner_type, const std::vector<std::vector<std::int64_t>>& faces) {
    std::string out = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(faces.size()) + "\nproperty list uchar " + corner_type + " vertex_indices\nend_header\n";
    for (int v = 0; v < 5; ++v)
      for (int k = 0; k < 3; ++k) put(out, 0.25f * static_cast<float>(v * 3 + k) - 1.0f, big);
    for (const auto& face : faces) {
      put(out, static_cast<std::uint8_t>(face.size()), big);
      for (const std::int64_t c : face) {
        if (corner_type == "int")
          put(out, static_cast<std::int32_t>(c), big);
        else
          put(out, static_cast<std::uint32_t>(c), big);
      }
    }
    return out;
  };
  // What read_mesh gives: the mesh, or its message.
  auto outcome = [&](const std::string& bytes) -> std::pair<std::optional<PolygonMesh>, std::string> {
    try {
      return {read_mesh(scratch.write("m.ply", bytes)), ""};
    } catch (const MeshIOError& e) {
      // The message names the file (the same path for both), then the problem.
      return {std::nullopt, e.what()};
    }
  };
  const std::vector<std::vector<std::int64_t>> faces = {{0, 1, 2}, {0, 2, 3, 4}, {4, 3, 1}, {1, 0, 4}};
  for (const std::string type : {"int", "uint"}) {
    INFO(type);
    const std::string little = file(false, type, faces), big = file(true, type, faces);
    const auto a = outcome(little), b = outcome(big);
    REQUIRE(a.first);
    REQUIRE(b.first);
    CHECK(a.first->positions == b.first->positions);
    CHECK(a.first->face_offsets == std::vector<std::uint32_t>{0, 3, 7, 10, 13});
    CHECK(a.first->face_offsets == b.first->face_offsets);
    CHECK(a.first->face_indices == b.first->face_indices);
    CHECK(a.first->positions[3] == -0.25);  // vertex 1's x: 0.25 * 3 - 1
    // Every cut of the body (the headers differ in length: their format lines).
    const std::size_t little_body = little.find("end_header\n") + 11, big_body = big.find("end_header\n") + 11;
    REQUIRE(little.size() - little_body == big.size() - big_body);
    for (std::size_t n = 0; n < little.size() - little_body; ++n) {
      INFO(n);
      const auto cut_little = outcome(little.substr(0, little_body + n)), cut_big = outcome(big.substr(0, big_body + n));
      CHECK(cut_little.second == cut_big.second);
      CHECK(cut_little.first.has_value() == cut_big.first.has_value());
    }
    // A face of no corners after two good ones; a corner that names no vertex.
    auto no_corners = faces;
    no_corners[2].clear();
    CHECK_THAT(outcome(file(false, type, no_corners)).second, Catch::Contains("face 2 has no corners"));
    CHECK(outcome(file(false, type, no_corners)).second == outcome(file(true, type, no_corners)).second);
    auto beyond = faces;
    beyond[3][1] = type == "int" ? -2 : 0xffffffff;
    CHECK_THAT(outcome(file(false, type, beyond)).second, Catch::Contains("face 3 references vertex (invalid)"));
    CHECK(outcome(file(false, type, beyond)).second == outcome(file(true, type, beyond)).second);
    beyond[3][1] = 5;
    CHECK_THAT(outcome(file(false, type, beyond)).second, Catch::Contains("face 3 references vertex 5 but the file has 5"));
  }
  // A second vertex element without coordinates (its vertices at the origin, as the general path
  // reads them), in both byte orders.
  for (const bool big : {false, true}) {
    std::string two = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element vertex 2\nproperty float nx\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (const float x : {1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f, 8.f, 9.f, 10.f, 11.f}) put(two, x, big);
    put(two, std::uint8_t{3}, big);
    for (const std::int32_t c : {0, 1, 4}) put(two, c, big);
    const auto r = outcome(two);
    REQUIRE(r.first);
    CHECK(r.first->positions == std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0, 0, 0, 0, 0});
  }
}
