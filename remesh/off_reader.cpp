#include "off_reader.h"

#include "file_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <system_error>

namespace meshlift {
namespace {

/// One whitespace-separated word of the file and the line it starts on (1-based); an empty
/// text means the end of the file.
struct Token {
  std::string_view text;
  std::size_t line = 0;
};

/// The file as tokens: the only reading of it. A record's tail ("the rest of the line") is
/// defined on the same tokens, by their line numbers.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text) : text_(file_text::without_byte_order_mark(text)) {}

  Token next() {
    skip_blanks();
    const std::size_t start = position_;
    while (position_ < text_.size() && !is_delimiter(text_[position_])) ++position_;
    return {text_.substr(start, position_ - start), line_};
  }

  Token peek() {
    const std::size_t saved_position = position_, saved_line = line_;
    const Token token = next();
    position_ = saved_position;
    line_ = saved_line;
    return token;
  }

  /// Consumes the tokens left on `line` and returns how many there were; the first `keep` of
  /// them are written to `kept`.
  std::size_t skip_rest_of_line(std::size_t line, std::string_view* kept = nullptr, std::size_t keep = 0) {
    std::size_t count = 0;
    for (skip_blanks(); position_ < text_.size() && line_ == line; skip_blanks()) {
      const Token token = next();
      if (count < keep) kept[count] = token.text;
      ++count;
    }
    return count;
  }

  std::size_t remaining_bytes() const { return text_.size() - position_; }

 private:
  static bool is_delimiter(char c) { return file_text::is_space(c) || c == '#'; }

  /// Moves to the start of the next token, over white space, line ends and comments.
  void skip_blanks() {
    while (position_ < text_.size()) {
      const char c = text_[position_];
      if (c == '#') {
        while (position_ < text_.size() && text_[position_] != '\n' && text_[position_] != '\r') ++position_;
      } else if (c == '\n' || (c == '\r' && (position_ + 1 == text_.size() || text_[position_ + 1] != '\n'))) {
        ++line_;
        ++position_;
      } else if (file_text::is_space(c)) {
        ++position_;  // including the CR of a CRLF, whose LF counts the line
      } else {
        break;
      }
    }
  }

  std::string_view text_;
  std::size_t position_ = 0;
  std::size_t line_ = 1;
};

/// What the header keyword [ST][C][N][4][n]OFF declares.
struct Layout {
  std::string keyword = "(none)";
  bool texture = false, colour = false, normal = false, homogeneous = false, dimension_follows = false;

  std::size_t coordinates() const { return homogeneous ? 4 : 3; }
  /// Fewest numbers a vertex line carries after its coordinates.
  std::size_t minimum_extras() const { return (normal ? 3 : 0) + (colour ? 3 : 0) + (texture ? 2 : 0); }
};

std::optional<Layout> parse_keyword(std::string_view word) {
  Layout layout;
  layout.keyword = std::string(word);
  const auto take = [&word](std::string_view prefix) {
    if (word.substr(0, prefix.size()) != prefix) return false;
    word.remove_prefix(prefix.size());
    return true;
  };
  layout.texture = take("ST");
  layout.colour = take("C");
  layout.normal = take("N");
  layout.homogeneous = take("4");
  layout.dimension_follows = take("n");
  if (word != "OFF") return std::nullopt;
  return layout;
}

/// Throws the reader's MeshIOError: "path: problem (line L)".
class Failure {
 public:
  explicit Failure(const std::string& path) : path_(path) {}
  [[noreturn]] void operator()(const std::string& problem, std::size_t line) const {
    throw MeshIOError(path_ + ": " + problem + " (line " + std::to_string(line) + ")");
  }

 private:
  const std::string& path_;
};

}  // namespace

PolygonMesh read_off(const std::string& path, std::string_view text) {
  const Failure fail(path);
  Tokenizer tokens(text);

  // Header keyword (optional), BINARY, the nOFF dimension.
  Layout layout;
  if (const Token first = tokens.peek(); !first.text.empty() && !file_text::parse_integer(first.text)) {
    const std::optional<Layout> declared = parse_keyword(first.text);
    if (!declared) fail("unknown OFF header keyword " + file_text::quoted(first.text) + " (expected [ST][C][N][4][n]OFF)", first.line);
    layout = *declared;
    tokens.next();
    if (const Token binary = tokens.peek(); binary.line == first.line && binary.text == "BINARY")
      fail("binary OFF is not supported (only ascii OFF is read)", first.line);
    if (layout.dimension_follows) {
      const Token dimension = tokens.next();
      if (file_text::parse_integer(dimension.text) != 3)
        fail(layout.keyword + " vertex dimension " + file_text::quoted(dimension.text) + " is not supported (only 3)", dimension.line);
    }
  }

  // Counts "V F [E]"; E and the rest of F's line are ignored.
  const Token vertex_token = tokens.next();
  const Token face_token = tokens.next();
  const std::optional<long long> vertex_count = file_text::parse_integer(vertex_token.text);
  const std::optional<long long> face_count = file_text::parse_integer(face_token.text);
  if (!vertex_count || !face_count) fail("OFF header has no vertex and face counts", vertex_token.line);
  if (*vertex_count < 0 || *face_count < 0)
    fail("OFF header has a negative count (" + std::string(vertex_token.text) + " vertices, " +
             std::string(face_token.text) + " faces)",
         face_token.line);
  tokens.skip_rest_of_line(face_token.line);
  if (*vertex_count == 0) fail("file has no vertices", face_token.line);

  // Each token takes at least one character and one separator (the last one none), so V vertices
  // and F faces need 2 (V coordinates + F) - 1 bytes: a vertex is counted by its coordinates (its
  // extras are checked as it is read, with a clearer message), a face by its corner count (its
  // corners are held to the bytes left when it is read).
  const std::uintmax_t budget = std::uintmax_t{tokens.remaining_bytes()} + 1;
  const std::uintmax_t vertex_tokens = layout.coordinates();
  const auto claims = [&] {
    return "OFF header claims " + std::string(vertex_token.text) + " vertices and " + std::string(face_token.text) +
           " faces, more than the remaining " + std::to_string(tokens.remaining_bytes()) + " bytes of the file hold";
  };
  if (std::uintmax_t(*vertex_count) > budget / (2 * vertex_tokens) || std::uintmax_t(*face_count) > budget / 2 ||
      2 * (vertex_tokens * std::uintmax_t(*vertex_count) + std::uintmax_t(*face_count)) > budget)
    fail(claims(), face_token.line);
  // Indices and offsets are 32-bit; kNone is no vertex.
  if (*vertex_count >= kNone || *face_count >= kNone) fail(claims() + " (at most 2^32 - 2 each)", face_token.line);
  const auto vertices = static_cast<std::size_t>(*vertex_count);
  const auto faces = static_cast<std::size_t>(*face_count);

  PolygonMesh mesh;
  mesh.positions.reserve(3 * vertices);
  mesh.face_offsets.reserve(faces + 1);
  mesh.face_indices.reserve(3 * faces);

  for (std::size_t v = 0; v < vertices; ++v) {
    float coordinate[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    Token token;
    for (std::size_t k = 0; k < layout.coordinates(); ++k) {
      token = tokens.next();
      const std::optional<float> value = file_text::parse_decimal<float>(token.text);
      if (!value)
        fail("vertex " + std::to_string(v) + " has a coordinate that is missing or not a finite number: " +
                 (token.text.empty() ? std::string("end of file") : file_text::quoted(token.text)),
             token.line);
      coordinate[k] = *value;
    }
    if (layout.homogeneous) {
      // 4OFF: homogeneous coordinates (x, y, z, w) stand for the point (x/w, y/w, z/w).
      for (int k = 0; k < 3; ++k) {
        const float value = static_cast<float>(double(coordinate[k]) / double(coordinate[3]));
        if (!std::isfinite(value))
          fail("vertex " + std::to_string(v) + " has a coordinate that is missing or not a finite number: w = " +
                   file_text::quoted(token.text),
               token.line);
        coordinate[k] = value;
      }
    }
    mesh.positions.insert(mesh.positions.end(), {double(coordinate[0]), double(coordinate[1]), double(coordinate[2])});
    std::string_view extra[6];  // a normal's 3, then a colour's first 3
    const std::size_t extras = tokens.skip_rest_of_line(token.line, extra, 6);
    if (extras < layout.minimum_extras())
      fail("vertex " + std::to_string(v) + " has " + std::to_string(extras) + " numbers after its coordinates, but the " +
               layout.keyword + " header declares at least " + std::to_string(layout.minimum_extras()) +
               " (normal: 3, colour: 3 or 4, texture coordinates: 2)",
           token.line);
    if (layout.colour) {
      // Red, green, blue after the normal, if any: three integers are 0-255, else decimals 0-1
      // (Geomview's two forms).
      const std::string_view* rgb = extra + (layout.normal ? 3 : 0);
      bool bytes = true;
      for (std::size_t k = 0; k < 3; ++k) bytes &= file_text::parse_integer(rgb[k]).has_value();
      for (std::size_t k = 0; k < 3; ++k) {
        const std::optional<double> value = file_text::parse_decimal<double>(rgb[k]);
        if (!value)
          fail("vertex " + std::to_string(v) + " has a colour component that is not a number: " + file_text::quoted(rgb[k]),
               token.line);
        mesh.colors.push_back(std::clamp(bytes ? *value / 255.0 : *value, 0.0, 1.0));
      }
    }
  }

  for (std::size_t f = 0; f < faces; ++f) {
    const std::string face = "face " + std::to_string(f);
    const Token size_token = tokens.next();
    if (size_token.text.empty()) fail("file ends before " + face + " of " + std::to_string(faces), size_token.line);
    const std::optional<long long> corners = file_text::parse_integer(size_token.text);
    if (!corners) fail(face + " has corner count " + file_text::quoted(size_token.text) + ", not an integer", size_token.line);
    if (*corners == 0) fail(face + " has no corners", size_token.line);
    if (*corners < 3) fail(face + " has " + std::string(size_token.text) + " corners, fewer than 3", size_token.line);
    if (std::uintmax_t(*corners) > vertices)
      fail(face + " claims " + std::string(size_token.text) + " corners, more than the file's " + std::to_string(vertices) +
               " vertices",
           size_token.line);
    if (std::uintmax_t(*corners) > (std::uintmax_t{tokens.remaining_bytes()} + 1) / 2)
      fail(face + " claims " + std::string(size_token.text) + " corners, more than the remaining " +
               std::to_string(tokens.remaining_bytes()) + " bytes of the file hold",
           size_token.line);
    if (mesh.face_indices.size() + std::size_t(*corners) >= kNone)
      fail(face + " takes the corner count past 2^32 - 1, beyond 32-bit face offsets", size_token.line);
    Token token = size_token;
    for (long long c = 0; c < *corners; ++c) {
      token = tokens.next();
      if (token.text.empty()) fail("file ends in " + face + " of " + std::to_string(faces), token.line);
      const std::optional<long long> index = file_text::parse_integer(token.text);
      if (!index) fail(face + " has corner " + file_text::quoted(token.text) + ", not a vertex index", token.line);
      if (*index < 0 || std::uintmax_t(*index) >= vertices)
        fail(face + " references vertex " + std::string(token.text) + " but the file has " + std::to_string(vertices) +
                 " vertices",
             token.line);
      mesh.face_indices.push_back(static_cast<std::uint32_t>(*index));
    }
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
    tokens.skip_rest_of_line(token.line);  // the face colour, if any
  }
  if (layout.normal) mesh.not_read.push_back("normals (" + layout.keyword + ")");
  if (layout.texture) mesh.not_read.push_back("texture coordinates (" + layout.keyword + ")");
  return mesh;
}

}  // namespace meshlift
