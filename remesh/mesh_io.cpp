#include "meshlift/mesh_io.h"

#include "file_text.h"
#include "obj_reader.h"
#include "off_reader.h"
#include "ply_reader.h"
#include "stl_reader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <string_view>
#include <type_traits>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <span>
#include <sstream>
#include <system_error>

namespace meshlift {
namespace {

namespace fs = std::filesystem;

/// Lower-case extension without the dot ("" if none).
std::string extension_of(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

bool is_supported_extension(const std::string& ext) {
  return ext == "obj" || ext == "off" || ext == "ply" || ext == "stl";
}

using file_text::fail;

std::string random_suffix() {
  std::random_device device;
  std::ostringstream out;
  out << std::hex;
  out.width(8);
  out.fill('0');
  out << (static_cast<std::uint32_t>(device()) & 0xffffffffu);
  return out.str();
}


/// The first `size` bytes of a file (every reader parses the whole file in memory), in storage
/// that is not cleared first (a 126 MB file: 10-15 ms less).
struct FileBytes {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
  std::string_view view() const { return {data.get(), size}; }
};
FileBytes contents_of(const std::string& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  FileBytes bytes{std::make_unique_for_overwrite<char[]>(static_cast<std::size_t>(size)), 0};
  in.read(bytes.data.get(), static_cast<std::streamsize>(size));
  bytes.size = static_cast<std::size_t>(in.gcount());
  return bytes;
}

}  // namespace

PolygonMesh read_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "no such file");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not a mesh file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot read file size: " + ec.message());
  if (!std::ifstream(path, std::ios::binary).is_open()) fail(path, "cannot open file for reading");
  if (!is_supported_extension(ext))
    fail(path, "unknown mesh file extension '" + ext + "' (supported: obj, off, ply, stl)");
  if (size == 0) fail(path, "file is empty");

  PolygonMesh mesh;
  {
    const FileBytes file = contents_of(path, size);  // released once parsed
    const std::string_view bytes = file.view();
    mesh = ext == "off"   ? read_off(path, bytes)
           : ext == "ply" ? read_ply(path, bytes)
           : ext == "obj" ? read_obj(path, bytes)
                          : read_stl(path, bytes);
  }
  if (mesh.vertex_count() == 0) fail(path, "file has no vertices");
  const std::size_t vertex_count = mesh.vertex_count();
  // One pass over the corners (vectorized: 30 -> 9-12 ms for 20 M corners), the faces walked only to
  // name the first bad one.
  if (std::all_of(mesh.face_indices.begin(), mesh.face_indices.end(), [&](std::uint32_t v) { return v < vertex_count; }))
    return mesh;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c)
      if (mesh.face_indices[c] >= vertex_count)
        fail(path, "face " + std::to_string(f) + " references vertex " +
                       (mesh.face_indices[c] == kNone ? std::string("(invalid)") : std::to_string(mesh.face_indices[c])) +
                       " but the file has " + std::to_string(vertex_count) + " vertices");
  return mesh;
}

namespace {

// ---- Writers ----
// Written straight from the arrays (no half-edge mesh in between, so any faces are stored as
// given, non-manifold ones too), a buffer at a time. Coordinates are stored as 32-bit floats
// (what PLY's `property float` and binary STL hold; the ascii formats get the same values), in
// text as the shortest digits that read back to the same float (std::to_chars).

/// The faces of a TriangleMesh or a PolygonMesh, alike for the writers.
struct TriangleFaces {
  const std::vector<std::uint32_t>& triangles;
  std::size_t count() const { return triangles.size() / 3; }
  std::size_t size(std::size_t) const { return 3; }
  const std::uint32_t* corners(std::size_t f) const { return triangles.data() + 3 * f; }
};
struct PolygonFaces {
  const PolygonMesh& mesh;
  std::size_t count() const { return mesh.face_count(); }
  std::size_t size(std::size_t f) const { return mesh.face_size(f); }
  const std::uint32_t* corners(std::size_t f) const { return mesh.face_indices.data() + mesh.face_offsets[f]; }
};

/// x's bytes at `at`, little-endian whatever the machine's order.
template <class T>
void store_little_endian(char* at, T x) {
  static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4);
  using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>;
  const auto bits = std::bit_cast<Bits>(x);
  for (std::size_t i = 0; i < sizeof(T); ++i) at[i] = static_cast<char>((bits >> (8 * i)) & 0xff);
}

/// Bytes to a stream through a buffer of kBufferBytes; the stream's state is checked by the caller.
class Output {
 public:
  explicit Output(std::ofstream& out) : out_(out) { buffer_.reserve(kBufferBytes + kSlack); }
  ~Output() { flush(); }
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  void text(std::string_view s) {
    buffer_.append(s);
    maybe_flush();
  }
  /// The float nearest x, in the shortest digits that read back to it.
  void number(float x) {
    char digits[32];
    const auto r = std::to_chars(digits, digits + sizeof digits, x);
    buffer_.append(digits, static_cast<std::size_t>(r.ptr - digits));
  }
  void integer(std::uint64_t x) {
    char digits[24];
    const auto r = std::to_chars(digits, digits + sizeof digits, x);
    buffer_.append(digits, static_cast<std::size_t>(r.ptr - digits));
  }
  void character(char c) {
    buffer_.push_back(c);
    maybe_flush();
  }
  /// Little-endian, whatever the machine's order.
  template <class T>
  void little_endian(T x) {
    char bytes[sizeof(T)];
    store_little_endian(bytes, x);
    buffer_.append(bytes, sizeof(T));
    maybe_flush();
  }
  /// Room for n more bytes at the end of the buffer, for the caller to fill before any other
  /// call: binary records made in place, a block at a time, instead of one append per value.
  char* room(std::size_t n) {
    const std::size_t at = buffer_.size();
    buffer_.resize(at + n);
    return buffer_.data() + at;
  }
  /// After room(): writes the buffer out if it is full.
  void filled() { maybe_flush(); }
  void flush() {
    if (!buffer_.empty()) out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20, kSlack = 4096;
  void maybe_flush() {
    if (buffer_.size() >= kBufferBytes) flush();
  }
  std::ofstream& out_;
  std::string buffer_;
};

/// A vertex as the file stores it.
std::array<float, 3> stored_point(const std::vector<double>& positions, std::uint32_t v) {
  return {static_cast<float>(positions[3 * std::size_t{v}]), static_cast<float>(positions[3 * std::size_t{v} + 1]),
          static_cast<float>(positions[3 * std::size_t{v} + 2])};
}

void write_point(Output& out, const std::array<float, 3>& p) {
  out.number(p[0]);
  out.character(' ');
  out.number(p[1]);
  out.character(' ');
  out.number(p[2]);
}

/// Colour component k of vertex v as a byte: round(255 c), c clamped to [0, 1].
std::uint8_t colour_byte(std::span<const double> colors, std::size_t v, int k) {
  return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(colors[3 * v + static_cast<std::size_t>(k)], 0.0, 1.0)));
}

/// " r g b" of vertex v, 0-255.
void write_colour(Output& out, std::span<const double> colors, std::size_t v) {
  for (int k = 0; k < 3; ++k) {
    out.character(' ');
    out.integer(colour_byte(colors, v, k));
  }
}

template <class Faces>
void write_off(Output& out, const std::vector<double>& positions, const Faces& faces, std::span<const double> colors) {
  const std::size_t V = positions.size() / 3;
  out.text(colors.empty() ? "OFF\n" : "COFF\n");
  out.integer(V);
  out.character(' ');
  out.integer(faces.count());
  out.text(" 0\n");
  for (std::uint32_t v = 0; v < V; ++v) {
    write_point(out, stored_point(positions, v));
    if (!colors.empty()) write_colour(out, colors, v);
    out.character('\n');
  }
  for (std::size_t f = 0; f < faces.count(); ++f) {
    out.integer(faces.size(f));
    for (std::size_t c = 0; c < faces.size(f); ++c) {
      out.character(' ');
      out.integer(faces.corners(f)[c]);
    }
    out.character('\n');
  }
}

template <class Faces>
void write_obj(Output& out, const std::vector<double>& positions, const Faces& faces, std::span<const double> colors) {
  const std::size_t V = positions.size() / 3;
  out.text("# " + std::to_string(V) + " vertices, " + std::to_string(faces.count()) + " faces\n");
  for (std::uint32_t v = 0; v < V; ++v) {
    out.text("v ");
    write_point(out, stored_point(positions, v));
    // A colour as MeshLab writes it, `v x y z r g b` in [0, 1]: the byte the other formats store.
    if (!colors.empty())
      for (int k = 0; k < 3; ++k) {
        out.character(' ');
        out.number(static_cast<float>(colour_byte(colors, v, k) / 255.0));
      }
    out.character('\n');
  }
  for (std::size_t f = 0; f < faces.count(); ++f) {
    out.character('f');
    for (std::size_t c = 0; c < faces.size(f); ++c) {
      out.character(' ');
      out.integer(std::uint64_t{faces.corners(f)[c]} + 1);  // OBJ counts from 1
    }
    out.character('\n');
  }
}

template <class Faces>
void write_ply(Output& out, const std::vector<double>& positions, const Faces& faces, bool binary,
               std::span<const double> colors) {
  const std::size_t V = positions.size() / 3;
  std::size_t largest = 0;
  for (std::size_t f = 0; f < faces.count(); ++f) largest = std::max(largest, faces.size(f));
  const bool byte_counts = largest <= 255;  // a face's corner count in a uchar where it fits
  out.text(std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") + " 1.0\nelement vertex " +
           std::to_string(V) + "\nproperty float x\nproperty float y\nproperty float z\n" +
           (colors.empty() ? "" : "property uchar red\nproperty uchar green\nproperty uchar blue\n") + "element face " +
           std::to_string(faces.count()) + "\nproperty list " + (byte_counts ? "uchar" : "int") +
           " int vertex_indices\nend_header\n");
  // Binary vertices, and triangles with a uchar count, are made in place a block at a time.
  constexpr std::size_t kBlock = 4096;
  if (binary && colors.empty()) {
    for (std::size_t first = 0; first < V; first += kBlock) {
      const std::size_t n = std::min(kBlock, V - first);
      char* at = out.room(12 * n);
      for (std::size_t i = 0; i < 3 * n; ++i) store_little_endian(at + 4 * i, static_cast<float>(positions[3 * first + i]));
      out.filled();
    }
  } else if (binary) {
    for (std::size_t first = 0; first < V; first += kBlock) {
      const std::size_t n = std::min(kBlock, V - first);
      char* at = out.room(15 * n);
      for (std::size_t i = 0; i < n; ++i, at += 15) {
        for (std::size_t k = 0; k < 3; ++k)
          store_little_endian(at + 4 * k, static_cast<float>(positions[3 * (first + i) + k]));
        for (int k = 0; k < 3; ++k) at[12 + k] = static_cast<char>(colour_byte(colors, first + i, k));
      }
      out.filled();
    }
  } else {
    for (std::uint32_t v = 0; v < V; ++v) {
      write_point(out, stored_point(positions, v));
      if (!colors.empty()) write_colour(out, colors, v);
      out.character('\n');
    }
  }
  std::size_t f = 0;
  if (binary && byte_counts) {
    // The longest run of triangles from the start (all of them for a TriangleFaces).
    std::size_t triangles = 0;
    while (triangles < faces.count() && faces.size(triangles) == 3) ++triangles;
    for (; f < triangles; f += kBlock) {
      const std::size_t n = std::min(kBlock, triangles - f);
      char* at = out.room(13 * n);
      for (std::size_t i = 0; i < n; ++i, at += 13) {
        const std::uint32_t* corners = faces.corners(f + i);
        at[0] = 3;
        for (int c = 0; c < 3; ++c) store_little_endian(at + 1 + 4 * c, static_cast<std::int32_t>(corners[c]));
      }
      out.filled();
    }
    f = triangles;
  }
  for (; f < faces.count(); ++f) {
    const std::size_t n = faces.size(f);
    const std::uint32_t* corners = faces.corners(f);
    if (binary) {
      if (byte_counts)
        out.little_endian(static_cast<std::uint8_t>(n));
      else
        out.little_endian(static_cast<std::int32_t>(n));
      for (std::size_t c = 0; c < n; ++c) out.little_endian(static_cast<std::int32_t>(corners[c]));
    } else {
      out.integer(n);
      for (std::size_t c = 0; c < n; ++c) {
        out.character(' ');
        out.integer(corners[c]);
      }
      out.character('\n');
    }
  }
}

/// STL: each triangle with its unit normal from its stored corners (zero if it has no area).
template <class Faces>
void write_stl(Output& out, const std::vector<double>& positions, const Faces& faces, bool binary) {
  if (binary) {
    // An 80-byte header that does not start with "solid" (readers take that for ascii).
    std::string header = "binary STL written by meshlift";
    header.resize(80, ' ');
    out.text(header);
    out.little_endian(static_cast<std::uint32_t>(faces.count()));
  } else {
    out.text("solid meshlift\n");
  }
  for (std::size_t f = 0; f < faces.count(); ++f) {
    const std::uint32_t* corners = faces.corners(f);
    const std::array<float, 3> p[3] = {stored_point(positions, corners[0]), stored_point(positions, corners[1]),
                                       stored_point(positions, corners[2])};
    const double u[3] = {double{p[1][0]} - p[0][0], double{p[1][1]} - p[0][1], double{p[1][2]} - p[0][2]};
    const double w[3] = {double{p[2][0]} - p[0][0], double{p[2][1]} - p[0][1], double{p[2][2]} - p[0][2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& x : n) x = length > 0 ? x / length : 0.0;
    const std::array<float, 3> normal = {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])};
    if (binary) {  // one 50-byte record: the normal, the corners, a zero attribute count
      char* at = out.room(50);
      for (int k = 0; k < 12; ++k) {
        const std::size_t i = static_cast<std::size_t>(k);
        store_little_endian(at + 4 * k, k < 3 ? normal[i] : p[i / 3 - 1][i % 3]);
      }
      store_little_endian(at + 48, std::uint16_t{0});
      out.filled();
    } else {
      out.text("facet normal ");
      write_point(out, normal);
      out.text("\n  outer loop\n");
      for (const auto& corner : p) {
        out.text("    vertex ");
        write_point(out, corner);
        out.character('\n');
      }
      out.text("  endloop\nendfacet\n");
    }
  }
  if (!binary) out.text("endsolid meshlift\n");
}

template <class Faces>
void write_faces(const std::string& path, const std::vector<double>& positions, const Faces& faces, bool binary,
                 std::span<const double> colors) {
  const std::string ext = extension_of(path);
  if (!is_supported_extension(ext))
    fail(path, "unknown mesh file extension '" + ext + "' (supported: obj, off, ply, stl)");
  if (positions.size() % 3 != 0) fail(path, "positions array length is not a multiple of 3");
  const std::size_t vertex_count = positions.size() / 3;
  if (!colors.empty() && colors.size() != positions.size())
    fail(path, "colours array length is not 3 per vertex");
  // The files store 32-bit floats: a coordinate outside their range would be written as "inf"
  // (or a binary infinity), a file no reader accepts back.
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(static_cast<float>(positions[i]))) {
      std::ostringstream value;
      value << positions[i];
      fail(path, "vertex " + std::to_string(i / 3) + " has coordinate " + value.str() +
                     ", outside the 32-bit float range of mesh files (scale the mesh down)");
    }
  for (std::size_t f = 0; f < faces.count(); ++f) {
    const std::size_t n = faces.size(f);
    if (ext == "stl" && n != 3)
      fail(path, "face " + std::to_string(f) + " has " + std::to_string(n) + " corners: STL stores triangles only");
    if (n < 3) fail(path, "face " + std::to_string(f) + " has " + std::to_string(n) + " corners");
    const std::uint32_t* corners = faces.corners(f);
    for (std::size_t c = 0; c < n; ++c)
      if (corners[c] >= vertex_count)
        fail(path, "face " + std::to_string(f) + " references vertex " + std::to_string(corners[c]) + " of " +
                       std::to_string(vertex_count));
    // A face through one vertex twice has no well-defined surface: refused, not dropped. (Sorted
    // corners for a large polygon: pairs would take quadratic time.)
    std::uint32_t repeated = kNone;
    if (n <= 16) {
      for (std::size_t c = 0; c < n && repeated == kNone; ++c)
        for (std::size_t d = 0; d < c; ++d)
          if (corners[d] == corners[c]) repeated = corners[c];
    } else {
      std::vector<std::uint32_t> sorted(corners, corners + n);
      std::sort(sorted.begin(), sorted.end());
      if (const auto twin = std::adjacent_find(sorted.begin(), sorted.end()); twin != sorted.end()) repeated = *twin;
    }
    if (repeated != kNone) fail(path, "face " + std::to_string(f) + " repeats vertex " + std::to_string(repeated));
  }

  const fs::path target(path);
  const std::string temporary = path + ".tmp-" + random_suffix();
  bool written = false;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out.is_open()) fail(path, "cannot create temporary file " + temporary);
    {
      Output o(out);
      if (ext == "off")
        write_off(o, positions, faces, colors);
      else if (ext == "obj")
        write_obj(o, positions, faces, colors);
      else if (ext == "ply")
        write_ply(o, positions, faces, binary, colors);
      else
        write_stl(o, positions, faces, binary);  // STL has no vertex colours
    }
    out.flush();
    written = out.good();
  }
  std::error_code ec;
  if (!written) {
    fs::remove(temporary, ec);
    fail(path, "cannot write " + temporary + " (disk full?)");
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    fail(path, "cannot rename temporary file into place: " + ec.message());
  }
}

}  // namespace

void write_mesh(const std::string& path, const PolygonMesh& mesh, bool binary) {
  if (mesh.face_offsets.empty() || mesh.face_offsets.front() != 0 || mesh.face_offsets.back() != mesh.face_indices.size())
    fail(path, "face_offsets does not span face_indices");
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    if (mesh.face_offsets[f + 1] < mesh.face_offsets[f]) fail(path, "face_offsets is not increasing");
  write_faces(path, mesh.positions, PolygonFaces{mesh}, binary, mesh.colors);
}

void write_mesh(const std::string& path, const TriangleMesh& mesh, bool binary, std::span<const double> colors) {
  if (mesh.triangles.size() % 3 != 0) fail(path, "triangles array length is not a multiple of 3");
  write_faces(path, mesh.positions, TriangleFaces{mesh.triangles}, binary, colors);
}

}  // namespace meshlift
