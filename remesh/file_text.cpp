// See file_text.h.
#include "file_text.h"

#include "meshlift/mesh_io.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

namespace meshlift::file_text {
namespace {

/// Drops one leading '+' (which operator>> accepted and std::from_chars does not), unless a sign
/// follows it.
std::string_view without_plus(std::string_view word) {
  if (word.size() > 1 && word[0] == '+' && word[1] != '+' && word[1] != '-') word.remove_prefix(1);
  return word;
}

}  // namespace

void fail(const std::string& path, const std::string& problem) { throw MeshIOError(path + ": " + problem); }

std::string_view next_word(std::string_view text, std::size_t& at) {
  while (at < text.size() && is_space(text[at])) ++at;
  const std::size_t start = at;
  while (at < text.size() && !is_space(text[at])) ++at;
  return text.substr(start, at - start);
}

std::string_view without_byte_order_mark(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

std::string quoted(std::string_view text) {
  // Appended piece by piece: GCC 12 reports a false -Wrestrict for "'" + std::string(...) (GCC bug 105651).
  std::string result(1, '\'');
  for (const char c : text.substr(0, 40)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      result.push_back(c);
    } else {
      const char* const hex = "0123456789abcdef";
      result.append({'\\', 'x', hex[byte >> 4], hex[byte & 15]});
    }
  }
  result.append(text.size() > 40 ? "...'" : "'");
  return result;
}

std::optional<long long> parse_integer(std::string_view word) {
  word = without_plus(word);
  long long value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (end != word.data() + word.size() || word.empty()) return std::nullopt;
  if (error == std::errc::result_out_of_range)
    return word[0] == '-' ? std::numeric_limits<long long>::min() : std::numeric_limits<long long>::max();
  if (error != std::errc()) return std::nullopt;
  return value;
}

template <class T>
std::optional<T> parse_decimal(std::string_view word) {
  word = without_plus(word);
  const char* const first = word.data();
  const char* const last = first + word.size();
  T value = 0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (end != last || word.empty()) return std::nullopt;
  if (error == std::errc::result_out_of_range) {
    // Underflow or overflow? A long double holds the answer for any |exponent| < 4932; beyond
    // that either way the word is refused.
    long double wide = 0;
    const auto [wide_end, wide_error] = std::from_chars(first, last, wide);
    if (wide_end != last || wide_error != std::errc() || std::abs(wide) >= 1) return std::nullopt;
    return std::copysign(T{0}, static_cast<T>(wide));
  }
  if (error != std::errc() || !std::isfinite(value)) return std::nullopt;
  return value;
}

template std::optional<float> parse_decimal<float>(std::string_view);
template std::optional<double> parse_decimal<double>(std::string_view);

}  // namespace meshlift::file_text
