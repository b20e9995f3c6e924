// PLY, ascii and binary. See ply_reader.h.
#include "ply_reader.h"

#include "file_text.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <system_error>
#include <type_traits>
#include <vector>

namespace meshlift {
namespace {

enum class Type : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Type> type_named(std::string_view name) {
  static constexpr std::pair<std::string_view, Type> kNames[] = {
      {"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},    {"uint8", Type::u8},
      {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16},  {"uint16", Type::u16},
      {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},    {"uint32", Type::u32},
      {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64},  {"float64", Type::f64}};
  for (const auto& [text, type] : kNames)
    if (name == text) return type;
  return std::nullopt;
}

std::size_t size_of(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 0;
}

bool is_float(Type t) { return t == Type::f32 || t == Type::f64; }

/// What the reader does with a property's values.
enum class Role : std::uint8_t { skip, x, y, z, corners, red, green, blue };

struct Property {
  std::string name;
  Type type = Type::u8;
  std::optional<Type> count_type;  // a list
  Role role = Role::skip;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

using file_text::fail;
using file_text::quoted;

/// The header's words, line by line, and where the body starts.
struct Header {
  bool ascii = true, big_endian = false;
  std::vector<Element> elements;
  std::size_t body = 0;
};

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  for (std::string_view w = file_text::next_word(line, at); !w.empty(); w = file_text::next_word(line, at)) words.push_back(w);
  return words;
}

Header parse_header(const std::string& path, std::string_view bytes) {
  Header h;
  std::size_t at = 0;
  // The next line, without its LF or CRLF; nullopt at the end of the bytes.
  auto next_line = [&]() -> std::optional<std::string_view> {
    if (at >= bytes.size()) return std::nullopt;
    const std::size_t end = bytes.find('\n', at);
    std::string_view line = bytes.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at);
    at = end == std::string_view::npos ? bytes.size() : end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
  };
  const auto first = next_line();
  if (!first || *first != "ply") fail(path, "not a PLY file (first line is not 'ply')");
  bool has_format = false;
  for (;;) {
    const auto line = next_line();
    if (!line) fail(path, "PLY header has no end_header line");
    const std::vector<std::string_view> w = words_of(*line);
    const auto malformed = [&] { fail(path, "malformed PLY header line " + quoted(*line)); };
    if (w.empty()) malformed();
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0") malformed();
      if (w[1] == "ascii")
        h.ascii = true;
      else if (w[1] == "binary_little_endian" || w[1] == "binary_big_endian")
        h.ascii = false, h.big_endian = w[1] == "binary_big_endian";
      else
        malformed();
      has_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) malformed();
      Element e;
      e.name = w[1];
      const std::string_view count = w[2];
      const auto r = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (count.empty() || count.find_first_not_of("0123456789") != std::string_view::npos)
        fail(path, "PLY element line " + quoted(*line) + " has no valid count");
      if (r.ec != std::errc() || e.count > bytes.size())
        fail(path, "PLY header claims " + std::string(count.substr(0, 20)) + " " + e.name +
                       " elements, more than the file's " + std::to_string(bytes.size()) + " bytes");
      h.elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail(path, "PLY property before any element");
      Property p;
      const bool list = w.size() > 1 && w[1] == "list";
      if (w.size() != (list ? 5u : 3u)) malformed();
      const auto type = type_named(w[list ? 3 : 1]);
      const auto count_type = list ? type_named(w[2]) : std::nullopt;
      if (!type || (list && !count_type))
        fail(path, "PLY property line " + quoted(*line) + " has an unknown type");
      if (list && is_float(*count_type))
        fail(path, "PLY property line " + quoted(*line) + ": a list's count must be an integer type");
      p.type = *type;
      p.count_type = count_type;
      p.name = w[list ? 4 : 2];
      h.elements.back().properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      if (w.size() != 1) malformed();
      break;
    } else {
      malformed();
    }
  }
  if (!has_format) fail(path, "PLY header has no format line");
  h.body = at;
  return h;
}

/// Binary values, in the file's byte order.
class BinaryBody {
 public:
  BinaryBody(std::string_view bytes, bool big_endian) : bytes_(bytes), big_endian_(big_endian) {}
  std::size_t left() const { return bytes_.size() - at_; }
  /// Whether the values are stored as this machine holds them (then read_bulk() applies).
  bool native_order() const { return big_endian_ == (std::endian::native == std::endian::big); }
  /// The bytes not read yet, and skipping n of them (\pre n <= left()).
  const char* next() const { return bytes_.data() + at_; }
  void skip(std::size_t n) { at_ += n; }
  /// The next value of type t; false at the end of the bytes.
  bool integer(Type t, std::int64_t& out) {
    std::uint64_t u;
    if (!raw(t, u)) return false;
    switch (t) {
      case Type::i8: out = static_cast<std::int8_t>(u); break;
      case Type::i16: out = static_cast<std::int16_t>(u); break;
      case Type::i32: out = static_cast<std::int32_t>(u); break;
      case Type::f32: out = std::llround(std::clamp<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)), -1e18, 1e18)); break;
      case Type::f64: out = std::llround(std::clamp(std::bit_cast<double>(u), -1e18, 1e18)); break;
      default: out = static_cast<std::int64_t>(u); break;
    }
    return true;
  }
  bool number(Type t, double& out) {
    std::uint64_t u;
    if (!raw(t, u)) return false;
    switch (t) {
      case Type::f32: out = std::bit_cast<float>(static_cast<std::uint32_t>(u)); break;
      case Type::f64: out = std::bit_cast<double>(u); break;
      case Type::i8: out = static_cast<std::int8_t>(u); break;
      case Type::i16: out = static_cast<std::int16_t>(u); break;
      case Type::i32: out = static_cast<std::int32_t>(u); break;
      default: out = static_cast<double>(u); break;
    }
    return true;
  }

 private:
  bool raw(Type t, std::uint64_t& u) {
    const std::size_t n = size_of(t);
    if (left() < n) return false;
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + at_, n);
    at_ += n;
    u = 0;
    for (std::size_t i = 0; i < n; ++i) u |= std::uint64_t{b[big_endian_ ? n - 1 - i : i]} << (8 * i);
    return true;
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
  bool big_endian_;
};

/// Ascii values: words separated by white space.
class AsciiBody {
 public:
  AsciiBody(const std::string& path, std::string_view bytes) : path_(path), bytes_(bytes) {}
  std::size_t left() const { return bytes_.size() - at_; }
  bool integer(Type t, std::int64_t& out) {
    const std::string_view w = word();
    if (w.empty()) return false;
    if (is_float(t)) {
      double x;
      parse_decimal(w, x);
      out = std::llround(std::clamp(x, -1e18, 1e18));
    } else {
      parse_integer(w, out);
    }
    return true;
  }
  bool number(Type t, double& out) {
    const std::string_view w = word();
    if (w.empty()) return false;
    if (t == Type::f32) {
      float f;
      parse_decimal(w, f);
      out = f;
    } else if (t == Type::f64) {
      parse_decimal(w, out);
    } else {
      std::int64_t i;
      parse_integer(w, i);
      out = static_cast<double>(i);
    }
    return true;
  }
  /// Where the values being read are, for messages: element `element`'s item `index`.
  const std::string* element = nullptr;
  std::uint64_t index = 0;

 private:
  std::string_view word() { return file_text::next_word(bytes_, at_); }
  void parse_integer(std::string_view w, std::int64_t& out) {
    const std::optional<long long> value = file_text::parse_integer(w);
    if (!value) bad(w);
    out = *value;
  }
  template <class T>
  void parse_decimal(std::string_view w, T& out) {
    const std::optional<T> value = file_text::parse_decimal<T>(w);
    if (!value) bad(w);
    out = *value;
  }
  [[noreturn]] void bad(std::string_view w) {
    fail(path_, "PLY " + (element != nullptr ? *element : std::string("body")) + " " + std::to_string(index) + ": " +
                    quoted(w) + " is not a valid number");
  }
  const std::string& path_;
  std::string_view bytes_;
  std::size_t at_ = 0;
};

/// The items of element `e` the common binary layouts allow to read in bulk, in the file's order,
/// into `mesh` (the positions of a vertex element whose properties are all scalars, x, y and z
/// floats or doubles; the corners of a face element whose one property is a list of uchar count
/// and int or uint corners), each item as read_body() takes it; returns how many. It stops before
/// an item it cannot take whole (a list of no corners, or longer than the bytes left), for
/// read_body() to go on from there and name the problem. The meshes written by meshlift and most
/// tools have these layouts: the body of a 3.3 M-vertex, 6.6 M-face PLY (float coordinates, int
/// corners) is read in 116-123 ms instead of 237 (one value at a time through BinaryBody).
std::uint64_t read_bulk(const Element& e, BinaryBody& body, PolygonMesh& mesh) {
  if (!body.native_order()) return 0;
  const auto read_as_double = [](Type t, const char* at) {
    if (t == Type::f64) {
      double x;
      std::memcpy(&x, at, sizeof x);
      return x;
    }
    float x;
    std::memcpy(&x, at, sizeof x);
    return static_cast<double>(x);
  };
  if (e.name == "vertex") {
    std::size_t stride = 0, offset[3] = {};
    Type type[3] = {Type::f64, Type::f64, Type::f64};
    bool found[3] = {false, false, false};
    for (const Property& p : e.properties) {
      if (p.count_type || p.role >= Role::red) return 0;  // colours go the general way
      if (p.role == Role::x || p.role == Role::y || p.role == Role::z) {
        if (!is_float(p.type)) return 0;
        const int k = static_cast<int>(p.role) - 1;
        offset[k] = stride;
        type[k] = p.type;
        found[k] = true;
      }
      stride += size_of(p.type);
    }
    // An element that lacks a coordinate (a second vertex element, say) goes the general way.
    if (!(found[0] && found[1] && found[2]) || stride == 0) return 0;
    const std::uint64_t count = std::min<std::uint64_t>(e.count, body.left() / stride);
    for (std::uint64_t item = 0; item < count; ++item) {
      const char* at = body.next();
      for (int k = 0; k < 3; ++k) mesh.positions.push_back(read_as_double(type[k], at + offset[k]));
      body.skip(stride);
    }
    return count;
  }
  if (e.name == "face" && e.properties.size() == 1 && e.properties[0].role == Role::corners &&
      e.properties[0].count_type == Type::u8 && (e.properties[0].type == Type::i32 || e.properties[0].type == Type::u32)) {
    const bool is_signed = e.properties[0].type == Type::i32;
    std::uint64_t item = 0;
    for (; item < e.count && body.left() >= 1; ++item) {
      const char* at = body.next();
      const std::size_t corners = static_cast<unsigned char>(at[0]);
      if (corners == 0 || 1 + 4 * corners > body.left()) break;
      for (std::size_t k = 0; k < corners; ++k) {
        std::uint32_t u;
        std::memcpy(&u, at + 1 + 4 * k, sizeof u);
        // As read_body() takes it: a negative int, or kNone itself, names no vertex.
        mesh.face_indices.push_back(is_signed && static_cast<std::int32_t>(u) < 0 ? kNone : u);
      }
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
      body.skip(1 + 4 * corners);
    }
    return item;
  }
  return 0;
}

/// A colour property's value in [0, 1]: an integer type's value over its largest (uchar 255,
/// ushort 65535, ...: 2^bits - 1, or 2^(bits - 1) - 1 signed), a float's as it is, each clamped
/// to [0, 1].
double colour_value(Type t, double value) {
  const bool is_signed = t == Type::i8 || t == Type::i16 || t == Type::i32;
  const double largest = is_float(t) ? 1.0 : std::ldexp(1.0, 8 * static_cast<int>(size_of(t)) - (is_signed ? 1 : 0)) - 1;
  return std::clamp(value / largest, 0.0, 1.0);
}

/// Reads every element of the body into `mesh`.
template <class Body>
void read_body(const std::string& path, const Header& h, Body& body, PolygonMesh& mesh) {
  const auto ended = [&](const Element& e, std::uint64_t item) {
    fail(path, "PLY file ends inside " + e.name + " " + std::to_string(item) + " (of " + std::to_string(e.count) + ")");
  };
  for (const Element& e : h.elements) {
    // The bytes an item takes at least: its scalars' and list counts' (binary), or one (ascii).
    std::size_t least = 0;
    for (const Property& p : e.properties) least += size_of(p.count_type.value_or(p.type));
    if constexpr (std::is_same_v<Body, AsciiBody>) least = e.properties.size();  // a value takes a byte at least
    if (least == 0) continue;  // items of no properties take no bytes: nothing to read
    if (e.count > body.left() / least)
      fail(path, "PLY header claims " + std::to_string(e.count) + " " + e.name + " elements, more than the " +
                     std::to_string(body.left()) + " bytes left hold");
    // Reserved within the bytes left (each kept value is read from one byte at least).
    const bool vertices = e.name == "vertex", faces = e.name == "face";
    const bool colours = vertices && std::any_of(e.properties.begin(), e.properties.end(),
                                                 [](const Property& p) { return p.role >= Role::red; });
    if (vertices) mesh.positions.reserve(mesh.positions.size() + std::min<std::uint64_t>(3 * e.count, body.left()));
    if (colours) mesh.colors.reserve(mesh.colors.size() + std::min<std::uint64_t>(3 * e.count, body.left()));
    if (faces) {
      mesh.face_offsets.reserve(mesh.face_offsets.size() + e.count);
      mesh.face_indices.reserve(mesh.face_indices.size() + std::min<std::uint64_t>(3 * e.count, body.left()));
    }
    std::uint64_t first = 0;
    if constexpr (std::is_same_v<Body, BinaryBody>) first = read_bulk(e, body, mesh);
    for (std::uint64_t item = first; item < e.count; ++item) {
      if constexpr (std::is_same_v<Body, AsciiBody>) body.element = &e.name, body.index = item;
      double xyz[3] = {0, 0, 0}, rgb[3] = {0, 0, 0};
      for (const Property& p : e.properties) {
        if (!p.count_type) {
          double value;
          if (!body.number(p.type, value)) ended(e, item);
          if (p.role == Role::x || p.role == Role::y || p.role == Role::z) xyz[static_cast<int>(p.role) - 1] = value;
          if (p.role >= Role::red) {
            // A binary float may hold NaN or an infinity (the ascii parser refuses them).
            if (!std::isfinite(value))
              fail(path, "PLY vertex " + std::to_string(item) + ": a colour component is NaN or infinite");
            rgb[static_cast<int>(p.role) - static_cast<int>(Role::red)] = colour_value(p.type, value);
          }
          continue;
        }
        std::int64_t count;
        if (!body.integer(*p.count_type, count)) ended(e, item);
        if (count < 0 || static_cast<std::uint64_t>(count) > body.left())
          fail(path, "PLY " + e.name + " " + std::to_string(item) + ": a list claims " + std::to_string(count) +
                         " entries, more than the " + std::to_string(body.left()) + " bytes left in the file");
        if (p.role == Role::corners && count == 0) fail(path, "face " + std::to_string(mesh.face_count()) + " has no corners");
        for (std::int64_t k = 0; k < count; ++k) {
          std::int64_t value;
          if (!body.integer(p.type, value)) ended(e, item);
          if (p.role == Role::corners)
            mesh.face_indices.push_back(value < 0 || value >= std::int64_t{kNone} ? kNone : static_cast<std::uint32_t>(value));
        }
        if (p.role == Role::corners) mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
      }
      if (vertices) mesh.positions.insert(mesh.positions.end(), xyz, xyz + 3);
      if (colours) mesh.colors.insert(mesh.colors.end(), rgb, rgb + 3);
    }
  }
}

}  // namespace

PolygonMesh read_ply(const std::string& path, std::string_view bytes) {
  Header h = parse_header(path, bytes);
  bool has_x = false, has_y = false, has_z = false;
  for (Element& e : h.elements) {
    bool corners = false;
    unsigned colour_seen = 0, colour_properties = 0;  // which of red, green, blue; how many properties
    for (Property& p : e.properties) {
      if (e.name == "vertex" && !p.count_type && (p.name == "x" || p.name == "y" || p.name == "z")) {
        p.role = p.name == "x" ? Role::x : p.name == "y" ? Role::y : Role::z;
        (p.name == "x" ? has_x : p.name == "y" ? has_y : has_z) = true;
      }
      // Vertex colours: red, green, blue (or diffuse_red, ... as some scanners write them).
      if (e.name == "vertex" && !p.count_type) {
        const std::string_view n = std::string_view(p.name).substr(p.name.rfind("diffuse_", 0) == 0 ? 8 : 0);
        if (n == "red" || n == "green" || n == "blue") {
          p.role = n == "red" ? Role::red : n == "green" ? Role::green : Role::blue;
          colour_seen |= 1u << (static_cast<int>(p.role) - static_cast<int>(Role::red));
          ++colour_properties;
        }
      }
      if (e.name == "face" && p.count_type && !corners && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (is_float(p.type)) fail(path, "PLY face corners (" + quoted(p.name) + ") must be of an integer type");
        p.role = Role::corners;
        corners = true;
      }
    }
    if (e.name == "face" && e.count > 0 && !corners)
      fail(path, "PLY face element has no 'vertex_indices' list");
    // Colours only where all three are there, once each: else read past.
    if (colour_seen != 7 || colour_properties != 3)
      for (Property& p : e.properties)
        if (p.role >= Role::red) p.role = Role::skip;
  }
  const bool any_vertex = std::any_of(h.elements.begin(), h.elements.end(), [](const Element& e) { return e.name == "vertex"; });
  if (any_vertex && !(has_x && has_y && has_z)) fail(path, "PLY vertex element lacks an x, y or z property");
  PolygonMesh mesh;
  if (h.ascii) {
    AsciiBody body(path, bytes.substr(h.body));
    read_body(path, h, body, mesh);
  } else {
    BinaryBody body(bytes.substr(h.body), h.big_endian);
    read_body(path, h, body, mesh);
  }
  // Colours on one vertex element of several: not one per vertex, so none.
  if (mesh.colors.size() != mesh.positions.size()) mesh.colors = {};
  // What was read past: other properties of the vertices and faces, other elements (their names
  // quoted, as the file's words are in messages, and at most kListed of each kind).
  constexpr std::size_t kListed = 8;
  std::size_t other_elements = 0;
  for (const Element& e : h.elements) {
    if (e.count == 0) continue;
    if (e.name != "vertex" && e.name != "face") {
      if (++other_elements <= kListed)
        mesh.not_read.push_back("PLY element " + quoted(e.name) + " (" + std::to_string(e.count) + ")");
      continue;
    }
    std::string names;
    std::size_t skipped = 0;
    for (const Property& p : e.properties)
      if (p.role == Role::skip && ++skipped <= kListed) names += (names.empty() ? "" : ", ") + quoted(p.name);
    if (skipped > kListed) names += " and " + std::to_string(skipped - kListed) + " more";
    if (skipped > 0) mesh.not_read.push_back("PLY " + e.name + " properties " + names);
  }
  if (other_elements > kListed)
    mesh.not_read.push_back(std::to_string(other_elements - kListed) + " more PLY elements");
  return mesh;
}

}  // namespace meshlift
