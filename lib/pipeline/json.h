// JSON text for the programs' machine-readable outputs (svg2png --query,
// --report, mpvg-compare --json): a string literal with RFC 8259's escapes.
#pragma once
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace mpvg::json {

// `s` as a JSON string, quotes included. Bytes are passed through (UTF-8
// stays UTF-8); quotes, backslashes and control characters are escaped.
inline std::string quote(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"') out += "\\\"";
    else if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else
      out += ch;
  }
  return out + "\"";
}

// A number as JSON writes it: finite, shortest round trip of %.17g not
// needed here: `digits` decimals, trailing zeros kept (0.1 ms, 1 px).
inline std::string number(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v == v ? v : 0.0);
  return buf;
}

inline std::string string_array(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); i++) out += (i ? ", " : "") + quote(items[i]);
  return out + "]";
}

}  // namespace mpvg::json
