// Mesh file round trips through OpenMesh's readers/writers, raw (non-manifold) reading, and
// hostile input: missing files, unknown extensions, random and corrupted bytes.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sys/wait.h>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"
#include "meshlift/validate.h"
#include "test_meshes.h"

namespace fs = std::filesystem;
using namespace meshlift;

namespace {

/// A fresh directory per test case, removed afterwards.
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name) {
    path = fs::temp_directory_path() / ("meshlift_io_" + name + "_" + std::to_string(std::random_device{}()));
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::size_t entries() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator())); }
};

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// OpenMesh 9's readers and writers carry coordinates as 32-bit floats.
double as_float(double x) { return static_cast<double>(static_cast<float>(x)); }

std::vector<std::uint32_t> corners_of(const PolygonMesh& m, std::size_t f) {
  return {m.face_indices.begin() + m.face_offsets[f], m.face_indices.begin() + m.face_offsets[f + 1]};
}

/// Every position equals the float-rounded original, every face is identical.
void require_same_mesh(const PolygonMesh& original, const PolygonMesh& read) {
  REQUIRE(read.vertex_count() == original.vertex_count());
  for (std::size_t i = 0; i < original.positions.size(); ++i) {
    INFO("coordinate " << i);
    REQUIRE(read.positions[i] == as_float(original.positions[i]));
    REQUIRE(std::abs(read.positions[i] - original.positions[i]) <= 1e-6 * std::max(1.0, std::abs(original.positions[i])));
  }
  REQUIRE(read.face_offsets == original.face_offsets);
  REQUIRE(read.face_indices == original.face_indices);
}

/// STL has no shared vertices: the reader merges equal points in order of first use, so compare
/// each face corner by position and check that no vertex was lost or invented.
void require_same_stl_mesh(const PolygonMesh& original, const PolygonMesh& read) {
  REQUIRE(read.vertex_count() == original.vertex_count());
  REQUIRE(read.face_count() == original.face_count());
  for (std::size_t f = 0; f < original.face_count(); ++f) {
    const auto a = corners_of(original, f), b = corners_of(read, f);
    REQUIRE(a.size() == b.size());
    for (std::size_t c = 0; c < a.size(); ++c)
      for (int k = 0; k < 3; ++k) REQUIRE(read.positions[3 * b[c] + k] == as_float(original.positions[3 * a[c] + k]));
  }
}

}  // namespace

TEST_CASE("every format round-trips procedural meshes", "[mesh_io]") {
  ScratchDir dir("roundtrip");
  struct Format {
    std::string ext;
    bool binary;
  };
  const std::vector<Format> formats = {{"obj", false}, {"off", false}, {"ply", false},
                                       {"ply", true},  {"stl", false}, {"stl", true}};
  const std::vector<std::pair<std::string, PolygonMesh>> meshes = {
      {"icosahedron", to_polygon_mesh(test::icosahedron())},
      {"torus", to_polygon_mesh(test::torus(9, 7))},
      {"grid", to_polygon_mesh(test::grid(6))},
      {"cube_quads", test::cube_quads()},
      // Over 4,096 vertices and faces (binary files are made in blocks of that many) and over the
      // writer's 1 MiB buffer, and a quad after the triangles (binary PLY writes the run of
      // triangles first, a block at a time).
      {"torus_then_quad", [] {
         PolygonMesh m = to_polygon_mesh(test::torus(180, 180));
         const auto first = static_cast<std::uint32_t>(m.vertex_count());
         m.positions.insert(m.positions.end(), {5, 0, 0, 6, 0, 0, 6, 1, 0, 5, 1, 0.5});
         m.face_indices.insert(m.face_indices.end(), {first, first + 1, first + 2, first + 3});
         m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_indices.size()));
         return m;
       }()}};
  for (const auto& [name, mesh] : meshes)
    for (const Format& format : formats) {
      const std::string path = dir.file(name + (format.binary ? "_bin." : ".") + format.ext);
      DYNAMIC_SECTION(name << " as " << format.ext << (format.binary ? " binary" : " ascii")) {
        if (format.ext == "stl" && !mesh.is_triangle_mesh()) {
          REQUIRE_THROWS_AS(write_mesh(path, mesh, format.binary), MeshIOError);
          REQUIRE_FALSE(fs::exists(path));
          continue;
        }
        write_mesh(path, mesh, format.binary);
        REQUIRE(dir.entries() == 1);  // no temporary left behind
        const std::string bytes = read_bytes(path);
        if (format.ext == "ply") REQUIRE((bytes.find("format ascii") != std::string::npos) == !format.binary);
        if (format.ext == "stl") REQUIRE((bytes.rfind("solid", 0) == 0) == !format.binary);
        const PolygonMesh read = read_mesh(path);
        if (format.ext == "stl") require_same_stl_mesh(mesh, read);
        else require_same_mesh(mesh, read);
        fs::remove(path);
      }
    }
}

TEST_CASE("the TriangleMesh overload writes the same file", "[mesh_io]") {
  ScratchDir dir("triangle_overload");
  const TriangleMesh mesh = test::torus();
  write_mesh(dir.file("a.off"), mesh);
  write_mesh(dir.file("b.off"), to_polygon_mesh(mesh));
  REQUIRE(read_bytes(dir.file("a.off")) == read_bytes(dir.file("b.off")));
}

TEST_CASE("writing replaces an existing file atomically and refuses what it cannot store", "[mesh_io]") {
  ScratchDir dir("atomic");
  const std::string path = dir.file("mesh.obj");
  write_bytes(path, "old contents");
  write_mesh(path, test::icosahedron());
  REQUIRE(read_mesh(path).face_count() == 20);
  REQUIRE(dir.entries() == 1);

  // A face through one vertex twice is refused, and the old file is untouched.
  PolygonMesh repeated = to_polygon_mesh(test::icosahedron());
  repeated.face_indices[1] = repeated.face_indices[0];
  REQUIRE_THROWS_AS(write_mesh(path, repeated), MeshIOError);
  REQUIRE(read_mesh(path).face_count() == 20);
  REQUIRE(dir.entries() == 1);
  REQUIRE_THROWS_AS(write_mesh(dir.file("repeated.off"), repeated), MeshIOError);
  PolygonMesh out_of_range = to_polygon_mesh(test::icosahedron());
  out_of_range.face_indices[4] = 12;
  REQUIRE_THROWS_AS(write_mesh(dir.file("range.off"), out_of_range), MeshIOError);
  REQUIRE_THROWS_AS(write_mesh(dir.file("mesh.xyz"), test::icosahedron()), MeshIOError);
  REQUIRE_THROWS_AS(write_mesh(dir.file("missing_dir/mesh.off"), test::icosahedron()), MeshIOError);
  REQUIRE(dir.entries() == 1);
}

TEST_CASE("non-manifold meshes and polygons of many corners are written verbatim", "[mesh_io]") {
  ScratchDir dir("write_verbatim");
  // Three triangles on edge (0, 1) (no half-edge mesh holds the third), and a 300-corner
  // polygon (more corners than a PLY uchar count holds).
  PolygonMesh mesh = to_polygon_mesh(test::disk(3));  // vertices 0 (centre), 1, 2, 3
  mesh.positions.insert(mesh.positions.end(), {0, 0, -1, 0, 0, 1});
  mesh.face_indices = {0, 1, 2, 1, 0, 4, 0, 1, 5};
  mesh.face_offsets = {0, 3, 6, 9};
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertex_count());
  for (int i = 0; i < 300; ++i) {
    const double angle = 2 * 3.14159265358979 * i / 300;
    mesh.positions.insert(mesh.positions.end(), {5 + std::cos(angle), 5 + std::sin(angle), 0.125 * i});
    mesh.face_indices.push_back(first + static_cast<std::uint32_t>(i));
  }
  mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
  for (const auto& [name, binary] : {std::pair{"m.off", false}, std::pair{"m.obj", false}, std::pair{"m.ply", false},
                                     std::pair{"mb.ply", true}}) {
    INFO(name);
    write_mesh(dir.file(name), mesh, binary);
    const PolygonMesh read = read_mesh(dir.file(name));
    CHECK(read.face_offsets == mesh.face_offsets);
    CHECK(read.face_indices == mesh.face_indices);
    REQUIRE(read.positions.size() == mesh.positions.size());
    for (std::size_t i = 0; i < read.positions.size(); ++i) CHECK(read.positions[i] == as_float(mesh.positions[i]));
  }
}

TEST_CASE("non-manifold files are read verbatim", "[mesh_io]") {
  ScratchDir dir("nonmanifold");
  // Three triangles sharing edge (0,1), plus a repeated-corner face and an isolated vertex:
  // OpenMesh's own importer would drop faces here.
  const std::string off = "OFF\n6 4 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n5 5 5\n3 0 1 2\n3 1 0 3\n3 0 1 4\n3 2 2 1\n";
  write_bytes(dir.file("fin.off"), off);
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 5 5 5\nf 1 2 3\nf 2 1 4\nf 1 2 5\nf 3 3 2\n";
  write_bytes(dir.file("fin.obj"), obj);
  for (const std::string name : {"fin.off", "fin.obj"}) {
    INFO(name);
    const PolygonMesh m = read_mesh(dir.file(name));
    REQUIRE(m.vertex_count() == 6);
    const MeshReport r = validate_mesh(m);
    REQUIRE(r.non_manifold_edges == 1);
    REQUIRE(m.face_indices == std::vector<std::uint32_t>{0, 1, 2, 1, 0, 3, 0, 1, 4, 2, 2, 1});
    REQUIRE(r.degenerate_faces == 1);
    REQUIRE(r.isolated_vertices == 1);
  }
}

TEST_CASE("unreadable input gives MeshIOError naming the file", "[mesh_io]") {
  ScratchDir dir("errors");
  const auto message_of = [](const std::string& path) {
    try {
      read_mesh(path);
    } catch (const MeshIOError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = dir.file("missing.off");
  REQUIRE_THAT(message_of(missing), Catch::Contains(missing) && Catch::Contains("no such file"));
  write_bytes(dir.file("mesh.xyz"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  REQUIRE_THAT(message_of(dir.file("mesh.xyz")), Catch::Contains("unknown mesh file extension"));
  REQUIRE_THAT(message_of(dir.path.string()), Catch::Contains("directory"));
  write_bytes(dir.file("empty.ply"), "");
  REQUIRE_THAT(message_of(dir.file("empty.ply")), Catch::Contains("empty"));
  write_bytes(dir.file("range.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  REQUIRE_THAT(message_of(dir.file("range.off")), Catch::Contains("face 0 references vertex 7"));
  write_bytes(dir.file("zero.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
  REQUIRE_THAT(message_of(dir.file("zero.obj")), Catch::Contains("face 0 references vertex"));
  // Thrown from inside OpenMesh's reader callbacks and carried out through its frames.
  write_bytes(dir.file("empty_face.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n");
  REQUIRE_THAT(message_of(dir.file("empty_face.off")), Catch::Contains("face 0 has no corners"));
  write_bytes(dir.file("slash.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n");
  REQUIRE_THAT(message_of(dir.file("slash.obj")), Catch::Contains("without a vertex index"));
  write_bytes(dir.file("header.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  REQUIRE_THAT(message_of(dir.file("header.ply")), Catch::Contains("end_header"));
  write_bytes(dir.file("novertex.obj"), "# nothing here\n");
  REQUIRE_THAT(message_of(dir.file("novertex.obj")), Catch::Contains("no vertices"));
  write_bytes(dir.file("bomb.off"), "OFF\n4000000000 4000000000 0\n1 2 3\n");
  REQUIRE_THAT(message_of(dir.file("bomb.off")), Catch::Contains("claims"));
  write_bytes(dir.file("corners.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n");
  REQUIRE_THAT(message_of(dir.file("corners.off")), Catch::Contains("claims"));
  write_bytes(dir.file("bomb.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n");
  REQUIRE_THAT(message_of(dir.file("bomb.ply")), Catch::Contains("claims"));
}

TEST_CASE("random bytes never crash the readers", "[mesh_io]") {
  ScratchDir dir("random");
  std::mt19937 rng(7);
  for (const std::string ext : {"off", "obj", "ply", "stl", "OFF"})
    for (int trial = 0; trial < 8; ++trial) {
      std::string bytes(1 + rng() % 4000, '\0');
      for (char& c : bytes) c = static_cast<char>(rng());
      const std::string path = dir.file("garbage" + std::to_string(trial) + "." + ext);
      write_bytes(path, bytes);
      INFO(path);
      REQUIRE_THROWS_AS(read_mesh(path), MeshIOError);
    }
}

TEST_CASE("truncated and corrupted files either read consistently or throw MeshIOError", "[mesh_io]") {
  ScratchDir dir("corrupt");
  const TriangleMesh mesh = test::torus(5, 4);
  std::mt19937 rng(11);
  for (const auto& [ext, binary] : std::vector<std::pair<std::string, bool>>{
           {"obj", false}, {"off", false}, {"ply", false}, {"ply", true}, {"stl", false}, {"stl", true}}) {
    const std::string source = dir.file(std::string("source") + (binary ? "_bin." : ".") + ext);
    write_mesh(source, mesh, binary);
    const std::string bytes = read_bytes(source);
    const std::string path = dir.file("corrupt." + ext);
    for (int trial = 0; trial < 60; ++trial) {
      std::string damaged = bytes;
      if (trial % 3 == 0) {
        damaged.resize(rng() % bytes.size());
      } else {
        for (int k = 0; k < 1 + trial % 5; ++k) damaged[rng() % damaged.size()] = static_cast<char>(rng());
      }
      write_bytes(path, damaged);
      INFO(ext << (binary ? " binary" : "") << " trial " << trial);
      try {
        const PolygonMesh m = read_mesh(path);
        REQUIRE(m.vertex_count() > 0);
        REQUIRE(m.face_offsets.back() == m.face_indices.size());
        for (const std::uint32_t index : m.face_indices) REQUIRE(index < m.vertex_count());
        validate_mesh(m);
      } catch (const MeshIOError&) {
      }
    }
  }
}

TEST_CASE("meshlift info prints a report or a one-line error", "[mesh_io][cli]") {
  ScratchDir dir("cli");
  const std::string mesh_path = dir.file("torus.off");
  write_mesh(mesh_path, test::torus());
  const std::string out = dir.file("out.txt"), err = dir.file("err.txt");
  const auto run = [&](const std::string& args) {
    const std::string command = std::string(MESHLIFT_CLI) + " info " + args + " >" + out + " 2>" + err;
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  REQUIRE(run(mesh_path) == 0);
  REQUIRE_THAT(read_bytes(out), Catch::Contains("genus 1"));
  REQUIRE(run("--json " + mesh_path) == 0);
  REQUIRE(read_bytes(out).rfind("{", 0) == 0);
  REQUIRE_THAT(read_bytes(out), Catch::Contains("\"genus\": 1"));
  REQUIRE(read_bytes(err).empty());

  REQUIRE(run(dir.file("missing.off")) == 3);
  REQUIRE(read_bytes(err) == "meshlift: " + dir.file("missing.off") + ": no such file\n");
  REQUIRE(read_bytes(out).empty());
  write_bytes(dir.file("stream.mlz"), "MLZ");  // a .mlz cut inside its file header
  REQUIRE(run(dir.file("stream.mlz")) == 3);
  REQUIRE_THAT(read_bytes(err), Catch::Contains("truncated (error 1)"));
  // What the file holds besides positions, faces and colours: a note on stderr, the report as ever.
  write_bytes(dir.file("textured.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n");
  REQUIRE(run(dir.file("textured.obj")) == 0);
  REQUIRE(read_bytes(err) == "meshlift: " + dir.file("textured.obj") +
                                 ": note: not read: texture coordinates (OBJ vt) (1 line); normals (OBJ vn) (1 line) "
                                 "(meshlift keeps the positions, faces and vertex colours)\n");
  REQUIRE_THAT(read_bytes(out), Catch::Contains("faces:                   1"));
}

TEST_CASE("vertex colours are read and written in PLY, OFF and OBJ, as bytes", "[mesh_io]") {
  ScratchDir dir("colours");
  // Over 4,096 vertices (binary PLY writes its vertices a block at a time), each colour a byte.
  PolygonMesh mesh = to_polygon_mesh(test::torus(80, 60));
  std::vector<int> bytes;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    bytes.push_back(static_cast<int>((i * 37 + i / 3) % 256));
    mesh.colors.push_back(bytes.back() / 255.0);
  }
  for (const auto& [ext, binary] : std::vector<std::pair<std::string, bool>>{{"ply", true}, {"ply", false}, {"off", false}, {"obj", false}}) {
    const std::string path = dir.file("coloured" + std::string(binary ? "_bin." : ".") + ext);
    INFO(path);
    write_mesh(path, mesh, binary);
    const PolygonMesh read = read_mesh(path);
    require_same_mesh(mesh, read);
    REQUIRE(read.colors.size() == mesh.colors.size());
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      REQUIRE(std::lround(255 * read.colors[i]) == bytes[i]);
      REQUIRE(std::abs(read.colors[i] - bytes[i] / 255.0) <= 1e-6);
    }
    // The TriangleMesh overload with the colours beside it writes the same file.
    write_mesh(dir.file("again." + ext), to_triangle_mesh(mesh), binary, mesh.colors);
    REQUIRE(read_bytes(dir.file("again." + ext)) == read_bytes(path));
  }
  // STL stores none; a mesh without colours reads back without.
  write_mesh(dir.file("c.stl"), mesh, true);
  REQUIRE(read_mesh(dir.file("c.stl")).colors.empty());
  mesh.colors.pop_back();
  REQUIRE_THROWS_AS(write_mesh(dir.file("bad.ply"), mesh), MeshIOError);
  mesh.colors.clear();
  write_mesh(dir.file("plain.ply"), mesh);
  REQUIRE(read_mesh(dir.file("plain.ply")).colors.empty());
}

TEST_CASE("colours in the forms other tools write them", "[mesh_io]") {
  ScratchDir dir("colour_forms");
  const std::string triangle = "3 0 1 2\n";
  // PLY: float components as they are, scanners' diffuse_ names, ushort over 65535; an element
  // with only two of the three is read past.
  write_bytes(dir.file("a.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property float red\nproperty float green\nproperty float blue\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0 1 0.5 0\n1 0 0 0 0 2\n0 1 0 0.25 0.75 -1\n" +
                  triangle);
  REQUIRE(read_mesh(dir.file("a.ply")).colors == std::vector<double>{1, 0.5, 0, 0, 0, 1, 0.25, 0.75, 0});
  write_bytes(dir.file("b.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar diffuse_red\nproperty uchar diffuse_green\nproperty ushort diffuse_blue\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0 255 0 65535\n1 0 0 0 51 0\n0 1 0 0 0 0\n" + triangle);
  REQUIRE(read_mesh(dir.file("b.ply")).colors == std::vector<double>{1, 0, 1, 0, 0.2, 0, 0, 0, 0});
  write_bytes(dir.file("c.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0 1 2\n1 0 0 3 4\n0 1 0 5 6\n" + triangle);
  REQUIRE(read_mesh(dir.file("c.ply")).colors.empty());
  // A property named twice (red, red, green) is not three colours: none.
  write_bytes(dir.file("twice.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar red\nproperty uchar green\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0 1 2 3\n1 0 0 3 4 5\n0 1 0 5 6 7\n" + triangle);
  REQUIRE(read_mesh(dir.file("twice.ply")).colors.empty());
  // Two vertex elements, only the second with colours: not one per vertex, so none.
  write_bytes(dir.file("two.ply"),
              "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
              "property uchar green\nproperty uchar blue\nelement face 1\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0 9 9 9\n" + triangle);
  const PolygonMesh two = read_mesh(dir.file("two.ply"));
  REQUIRE(two.vertex_count() == 3);
  REQUIRE(two.colors.empty());
  // A binary float colour that is NaN: refused, naming the vertex.
  {
    std::string bytes = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                        "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 6; ++k) {
        const float x = v == 1 && k == 3 ? std::numeric_limits<float>::quiet_NaN() : (k == v ? 1.0f : 0.0f);
        bytes.append(reinterpret_cast<const char*>(&x), sizeof x);
      }
    bytes += '\3';
    for (const std::int32_t c : {0, 1, 2}) bytes.append(reinterpret_cast<const char*>(&c), sizeof c);
    write_bytes(dir.file("nan.ply"), bytes);
    REQUIRE_THROWS_WITH(read_mesh(dir.file("nan.ply")), Catch::Contains("vertex 1: a colour component is NaN"));
  }
  // OFF: integers are 0-255, decimals 0-1 (Geomview); a normal comes first; alpha is ignored.
  write_bytes(dir.file("d.off"), "CNOFF\n3 1 0\n0 0 0 0 0 1 255 0 51 255\n1 0 0 0 0 1 0.5 1 0\n0 1 0 0 0 1 0 0 0 1\n" + triangle);
  REQUIRE(read_mesh(dir.file("d.off")).colors == std::vector<double>{1, 0, 0.2, 0.5, 1, 0, 0, 0, 0});
  write_bytes(dir.file("e.off"), "COFF\n3 1 0\n0 0 0 1 2\n1 0 0 1 2 3\n0 1 0 1 2 3\n" + triangle);
  REQUIRE_THROWS_AS(read_mesh(dir.file("e.off")), MeshIOError);  // a vertex short of its colour
  // OBJ: `v x y z r g b` where every vertex has one; else none (and `v x y z w` is no colour).
  write_bytes(dir.file("f.obj"), "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\nf 1 2 3\n");
  REQUIRE(read_mesh(dir.file("f.obj")).colors == std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 0.5});
  write_bytes(dir.file("g.obj"), "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 0.5\nf 1 2 3\n");
  REQUIRE(read_mesh(dir.file("g.obj")).colors.empty());
  write_bytes(dir.file("h.obj"), "v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nf 1 2 3\n");
  REQUIRE(read_mesh(dir.file("h.obj")).colors.empty());
}

TEST_CASE("what a file holds besides positions, faces and vertex colours is listed as not read", "[mesh_io]") {
  ScratchDir dir("not_read");
  // OBJ: texture coordinates, normals and materials, counted by lines.
  write_bytes(dir.file("a.obj"), "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                                 "usemtl m\nf 1/1/1 2/2/1 3/3/1\n");
  const PolygonMesh obj = read_mesh(dir.file("a.obj"));
  CHECK(obj.face_count() == 1);
  CHECK(obj.not_read == std::vector<std::string>{"texture coordinates (OBJ vt) (3 lines)", "normals (OBJ vn) (1 line)",
                                                 "materials (OBJ mtllib, usemtl) (2 lines)"});
  // PLY: the vertices' and faces' other properties by name, other elements with their counts
  // (an empty one is nothing left out); colours are read, so not listed.
  write_bytes(dir.file("a.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
              "property list uchar int vertex_indices\nproperty list uchar float texcoord\nelement material 2\n"
              "property float shine\nelement edge 0\nproperty int vertex1\nend_header\n"
              "0 0 0 1 0 0 0\n1 0 0 1 0 0 0\n0 1 0 1 0 0 0\n3 0 1 2 6 0 0 1 0 0 1\n0.5\n0.25\n");
  const PolygonMesh ply = read_mesh(dir.file("a.ply"));
  CHECK(ply.colors.size() == 9);
  CHECK(ply.not_read ==
        std::vector<std::string>{"PLY vertex properties 'nx'", "PLY face properties 'texcoord'", "PLY element 'material' (2)"});
  // Names as the file's words are quoted in messages, and at most 8 of a kind listed.
  std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  for (int k = 0; k < 10; ++k) header += "property uchar p" + std::to_string(k) + (k == 0 ? "\x01" : "") + "\n";
  header += "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string body;
  for (int v = 0; v < 3; ++v) body += std::to_string(v == 1) + " " + std::to_string(v == 2) + " 0 0 0 0 0 0 0 0 0 0 0\n";
  write_bytes(dir.file("many.ply"), header + body + "3 0 1 2\n");
  CHECK(read_mesh(dir.file("many.ply")).not_read ==
        std::vector<std::string>{"PLY vertex properties 'p0\\x01', 'p1', 'p2', 'p3', 'p4', 'p5', 'p6', 'p7' and 2 more"});
  // OFF: the header's normals and texture coordinates.
  write_bytes(dir.file("a.off"), "STNOFF\n3 1 0\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\n3 0 1 2\n");
  CHECK(read_mesh(dir.file("a.off")).not_read ==
        std::vector<std::string>{"normals (STNOFF)", "texture coordinates (STNOFF)"});
  // Nothing else: nothing listed.
  write_bytes(dir.file("b.off"), "COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n");
  CHECK(read_mesh(dir.file("b.off")).not_read.empty());
  write_bytes(dir.file("b.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(read_mesh(dir.file("b.obj")).not_read.empty());
}
