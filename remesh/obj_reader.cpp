// Wavefront OBJ geometry. See obj_reader.h.
#include "obj_reader.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <system_error>

namespace meshlift {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) { throw MeshIOError(path + ": " + problem); }

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

/// The words of one line, one at a time.
class Words {
 public:
  explicit Words(std::string_view line) : line_(line) {}
  /// The next word; empty at the end of the line.
  std::string_view next() {
    while (at_ < line_.size() && is_blank(line_[at_])) ++at_;
    const std::size_t start = at_;
    while (at_ < line_.size() && !is_blank(line_[at_])) ++at_;
    return line_.substr(start, at_ - start);
  }

 private:
  std::string_view line_;
  std::size_t at_ = 0;
};

/// A coordinate: a finite float, rounded as strtof rounds (subnormal or zero below the range).
bool parse_coordinate(std::string_view word, float& out) {
  if (word.empty()) return false;
  if (word[0] == '+') word.remove_prefix(1);
  if (word.empty() || word.find_first_not_of("0123456789+-.eE") != std::string_view::npos) return false;
  const auto r = std::from_chars(word.data(), word.data() + word.size(), out);
  if (r.ptr != word.data() + word.size()) return false;
  if (r.ec == std::errc::result_out_of_range) {
    long double v = 0;
    std::from_chars(word.data(), word.data() + word.size(), v);
    if (!(std::abs(v) <= 1)) return false;  // beyond the float range
    out = static_cast<float>(v);
    return true;
  }
  return r.ec == std::errc() && std::isfinite(out);
}

}  // namespace

PolygonMesh read_obj(const std::string& path, std::string_view text) {
  PolygonMesh mesh;
  std::size_t at = 0, line_number = 0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") at = 3;  // a UTF-8 byte-order mark
  while (at < text.size()) {
    // The next line, ended by LF, CRLF or CR, without its comment.
    std::size_t end = at;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    std::string_view line = text.substr(at, end - at);
    at = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const auto where = [&] { return "OBJ line " + std::to_string(line_number); };
    Words words(line);
    const std::string_view keyword = words.next();
    if (keyword == "v") {
      float xyz[3];
      for (float& x : xyz)
        if (!parse_coordinate(words.next(), x)) fail(path, where() + ": a vertex coordinate is missing or not a finite number");
      mesh.positions.insert(mesh.positions.end(), {xyz[0], xyz[1], xyz[2]});
    } else if (keyword == "f") {
      const std::size_t first = mesh.face_indices.size();
      const auto vertices = static_cast<std::int64_t>(mesh.vertex_count());
      for (std::string_view corner = words.next(); !corner.empty(); corner = words.next()) {
        const std::string_view index = corner.substr(0, corner.find('/'));
        if (index.empty()) fail(path, where() + " has a face corner without a vertex index");
        const std::string_view digits = index[0] == '+' ? index.substr(1) : index;
        std::int64_t i = 0;
        const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), i);
        if (digits.empty() || r.ptr != digits.data() + digits.size() ||
            (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
          fail(path, where() + ": face corner '" + std::string(corner.substr(0, 40)) + "' has no integer vertex index");
        if (r.ec == std::errc::result_out_of_range) i = 0;  // out of range either way
        // 1-based; negative: back from the last vertex so far. 0 and beyond: no vertex.
        const std::int64_t v = i > 0 ? i - 1 : i < 0 ? vertices + i : -1;
        mesh.face_indices.push_back(v >= 0 && v < std::int64_t{kNone} ? static_cast<std::uint32_t>(v) : kNone);
      }
      if (mesh.face_indices.size() == first) fail(path, "face " + std::to_string(mesh.face_count()) + " has no corners");
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
    }
  }
  return mesh;
}

}  // namespace meshlift
