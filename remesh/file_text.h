// What the mesh file readers (OFF, PLY, OBJ, STL) share: their error, their white space and
// words, a token quoted for a message, and the numbers of the text formats as they take them.
// Internal to remesh/.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace meshlift::file_text {

/// Throws MeshIOError "path: problem".
[[noreturn]] void fail(const std::string& path, const std::string& problem);

/// White space as isspace() has it in the C locale, without a call per byte.
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/// The word of `text` that starts at or after `at` (past white space), moving `at` past it;
/// empty at the end of the text.
std::string_view next_word(std::string_view text, std::size_t& at);

/// `text` without a leading UTF-8 byte-order mark.
std::string_view without_byte_order_mark(std::string_view text);

/// A token quoted for a one-line message: cut at 40 bytes, bytes outside printable ASCII as \xHH.
std::string quoted(std::string_view text);

/// The whole word as a decimal integer: an optional sign (one leading '+' is dropped, as
/// operator>> accepted it) and digits. Values beyond long long saturate (so that every range
/// check refuses them); anything else that is not an integer (`1.5`, `+-5`, `x`) gives nullopt.
std::optional<long long> parse_integer(std::string_view word);

/// The whole word as a finite float or double, correctly rounded (std::from_chars, locale-free,
/// as strtof and strtod round). A value too small for the type becomes a signed zero (a
/// subnormal where one holds it); NaN, infinities, hexadecimal and values beyond the type's
/// range, however far (`1e5000`), give nullopt.
template <class T>
std::optional<T> parse_decimal(std::string_view word);

extern template std::optional<float> parse_decimal<float>(std::string_view);
extern template std::optional<double> parse_decimal<double>(std::string_view);

}  // namespace meshlift::file_text
