// STL, ascii and binary. See stl_reader.h.
#include "stl_reader.h"

#include "exact_positions.h"
#include "file_text.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

namespace meshlift {
namespace {

using file_text::fail;
using file_text::quoted;

using Point = std::array<float, 3>;

/// Corners to vertices: corners at the same position (exact_positions.h) are one vertex,
/// numbered in the order of first use.
class Vertices {
 public:
  explicit Vertices(std::size_t expected) : table_(expected) {}
  std::uint32_t of(const Point& p, PolygonMesh& mesh) {
    const auto v = static_cast<std::uint32_t>(mesh.vertex_count());
    mesh.positions.insert(mesh.positions.end(), {p[0], p[1], p[2]});
    const std::uint32_t first = table_.first_at(mesh.positions, v);
    if (first != v) mesh.positions.resize(3 * std::size_t{v});  // there already
    return first;
  }

 private:
  ExactPositions table_;
};

float little_endian_float(const char* b) {
  std::uint32_t u = 0;
  for (int i = 0; i < 4; ++i) u |= std::uint32_t{static_cast<unsigned char>(b[i])} << (8 * i);
  return std::bit_cast<float>(u);
}

void add_triangle(PolygonMesh& mesh, Vertices& vertices, const Point (&corners)[3]) {
  for (const Point& p : corners) mesh.face_indices.push_back(vertices.of(p, mesh));
  mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
}

PolygonMesh read_binary(std::string_view bytes, std::uint32_t triangles) {
  PolygonMesh mesh;
  mesh.face_offsets.reserve(std::size_t{triangles} + 1);
  mesh.face_indices.reserve(3 * std::size_t{triangles});
  Vertices vertices(triangles / 2);
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const char* record = bytes.data() + 84 + 50 * std::size_t{t};
    Point corners[3];
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) corners[c][k] = little_endian_float(record + 12 + 12 * c + 4 * k);
    add_triangle(mesh, vertices, corners);
  }
  return mesh;
}

/// Whether `word` is `keyword` (lower case), in any letter case (exporters write SOLID, FACET, ...).
bool is(std::string_view word, std::string_view keyword) {
  return word.size() == keyword.size() && std::equal(word.begin(), word.end(), keyword.begin(), [](char a, char b) {
           return (a >= 'A' && a <= 'Z' ? static_cast<char>(a - 'A' + 'a') : a) == b;
         });
}

PolygonMesh read_ascii(const std::string& path, std::string_view text) {
  std::size_t at = 0;
  auto word = [&] { return file_text::next_word(text, at); };
  // The rest of the current line (a solid's name).
  auto skip_line = [&] {
    while (at < text.size() && text[at] != '\n' && text[at] != '\r') ++at;
  };
  PolygonMesh mesh;
  Vertices vertices(text.size() / 200);  // ~260 bytes per ascii facet: ~1.5 vertices per facet
  word();  // "solid", checked by the caller
  skip_line();
  for (std::size_t facet = 0;;) {
    const auto where = [&] { return "ascii STL facet " + std::to_string(facet); };
    const auto found = [](std::string_view w) { return w.empty() ? std::string("the end of the file") : quoted(w); };
    const auto expect = [&](std::string_view expected) {
      const std::string_view w = word();
      if (!is(w, expected)) fail(path, where() + ": expected '" + std::string(expected) + "', found " + found(w));
    };
    const std::string_view w = word();
    if (w.empty()) break;  // endsolid may be missing at the end
    if (is(w, "endsolid")) {
      // Then the end of the file, or another solid (files of several parts).
      skip_line();
      const std::string_view next = word();
      if (next.empty()) break;
      if (!is(next, "solid")) fail(path, "ascii STL: expected 'solid' or the end of the file after 'endsolid', found " + found(next));
      skip_line();
      continue;
    }
    if (!is(w, "facet")) fail(path, where() + ": expected 'facet' or 'endsolid', found " + found(w));
    expect("normal");
    for (int k = 0; k < 3; ++k) word();  // the normal: not kept
    expect("outer");
    expect("loop");
    Point corners[3];
    for (Point& p : corners) {
      expect("vertex");
      for (float& x : p) {
        const std::string_view number = word();
        const std::optional<float> value = file_text::parse_decimal<float>(number);
        if (!value) fail(path, where() + ": " + quoted(number) + " is not a finite coordinate");
        x = *value;
      }
    }
    expect("endloop");
    expect("endfacet");
    add_triangle(mesh, vertices, corners);
    ++facet;
  }
  return mesh;
}

}  // namespace

PolygonMesh read_stl(const std::string& path, std::string_view bytes) {
  if (bytes.size() >= 84) {
    std::uint32_t triangles = 0;
    for (int i = 0; i < 4; ++i) triangles |= std::uint32_t{static_cast<unsigned char>(bytes[80 + i])} << (8 * i);
    if (84 + 50 * std::uint64_t{triangles} == bytes.size()) return read_binary(bytes, triangles);
    if (!is(bytes.substr(0, 5), "solid"))
      fail(path, "binary STL claims " + std::to_string(triangles) + " triangles: " +
                     std::to_string(84 + 50 * std::uint64_t{triangles}) + " bytes, but the file has " +
                     std::to_string(bytes.size()));
  } else if (!is(bytes.substr(0, 5), "solid")) {
    fail(path, "not an STL file: " + std::to_string(bytes.size()) +
                   " bytes, shorter than a binary header, and no 'solid' at the start");
  }
  return read_ascii(path, bytes);
}

}  // namespace meshlift
