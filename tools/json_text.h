// JSON text for the commands that print or write JSON (compare, rd).
#pragma once

#include <string>

namespace meshlift::cli {

/// `text` as a JSON string literal: quotes, backslashes and control characters escaped.
std::string json_string(const std::string& text);

}  // namespace meshlift::cli
