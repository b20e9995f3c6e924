// Wavefront OBJ geometry. See obj_reader.h.
#include "obj_reader.h"

#include "file_text.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <system_error>

namespace meshlift {
using file_text::fail;

PolygonMesh read_obj(const std::string& path, std::string_view text) {
  PolygonMesh mesh;
  bool every_vertex_coloured = true;
  // Lines of the kinds a mesh of positions, faces and colours leaves out, counted for not_read.
  std::size_t texture_lines = 0, normal_lines = 0, material_lines = 0, other_lines = 0;
  text = file_text::without_byte_order_mark(text);
  std::size_t at = 0, line_number = 0;
  while (at < text.size()) {
    // The next line, ended by LF, CRLF or CR, without its comment.
    std::size_t end = at;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    std::string_view line = text.substr(at, end - at);
    at = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const auto where = [&] { return "OBJ line " + std::to_string(line_number); };
    std::size_t in_line = 0;
    const auto word = [&] { return file_text::next_word(line, in_line); };
    const std::string_view keyword = word();
    if (keyword == "v") {
      for (int k = 0; k < 3; ++k) {
        const std::optional<float> x = file_text::parse_decimal<float>(word());
        if (!x) fail(path, where() + ": a vertex coordinate is missing or not a finite number");
        mesh.positions.push_back(*x);
      }
      // `v x y z r g b`: a vertex colour (decimals 0-1, as MeshLab writes it); kept where every
      // vertex has one. Anything else after the coordinates (w) is ignored.
      if (every_vertex_coloured) {
        std::optional<double> rgb[3];
        for (auto& c : rgb) c = file_text::parse_decimal<double>(word());
        every_vertex_coloured = rgb[0] && rgb[1] && rgb[2] && word().empty();
        if (every_vertex_coloured)
          for (const auto& c : rgb) mesh.colors.push_back(std::clamp(*c, 0.0, 1.0));
        else
          mesh.colors = {};  // one vertex without: none kept (and none read from here on)
      }
    } else if (keyword == "f") {
      const std::size_t first = mesh.face_indices.size();
      const auto vertices = static_cast<std::int64_t>(mesh.vertex_count());
      for (std::string_view corner = word(); !corner.empty(); corner = word()) {
        const std::string_view index = corner.substr(0, corner.find('/'));
        if (index.empty()) fail(path, where() + " has a face corner without a vertex index");
        const std::optional<long long> i = file_text::parse_integer(index);
        if (!i) fail(path, where() + ": face corner " + file_text::quoted(corner) + " has no integer vertex index");
        // 1-based; negative: back from the last vertex so far. 0 and beyond (saturated): no vertex.
        const std::int64_t v = *i > 0 ? *i - 1 : *i < 0 ? vertices + *i : -1;
        mesh.face_indices.push_back(v >= 0 && v < std::int64_t{kNone} ? static_cast<std::uint32_t>(v) : kNone);
      }
      if (mesh.face_indices.size() == first) fail(path, "face " + std::to_string(mesh.face_count()) + " has no corners");
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
    } else if (keyword == "vt") {
      ++texture_lines;
    } else if (keyword == "vn") {
      ++normal_lines;
    } else if (keyword == "mtllib" || keyword == "usemtl") {
      ++material_lines;
    } else if (keyword == "l" || keyword == "p" || keyword == "vp" || keyword == "curv" || keyword == "surf") {
      ++other_lines;
    }
  }
  if (!every_vertex_coloured || mesh.colors.empty()) mesh.colors = {};
  const auto note = [&](std::size_t lines, const char* what) {
    if (lines > 0) mesh.not_read.push_back(std::string(what) + " (" + std::to_string(lines) + (lines == 1 ? " line)" : " lines)"));
  };
  note(texture_lines, "texture coordinates (OBJ vt)");
  note(normal_lines, "normals (OBJ vn)");
  note(material_lines, "materials (OBJ mtllib, usemtl)");
  note(other_lines, "points, lines, curves or surfaces (OBJ p, l, vp, curv, surf)");
  return mesh;
}

}  // namespace meshlift
