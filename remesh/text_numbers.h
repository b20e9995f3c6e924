// The numbers of the text mesh formats (OFF, OBJ, ascii PLY and STL), one word at a time, as
// their readers take them. Internal to remesh/.
#pragma once

#include <optional>
#include <string_view>

namespace meshlift::text_numbers {

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

}  // namespace meshlift::text_numbers
