// Helpers of the SVG frontend's tests: documents built around a body, and
// scene dumps (mpvg::dump) cut down to the lines a case is about.
#pragma once
#include <algorithm>
#include <string>
#include <string_view>

namespace svg_test {

// `body` inside an <svg> root that declares the SVG and XLink namespaces
// and carries the attributes `root`.
inline std::string document(const std::string& body, const std::string& root = "viewBox=\"0 0 100 100\"") {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" " + root + ">" +
         body + "</svg>";
}

// The lines of `dump` (each with its newline) for which keep(text, indent)
// holds: text is the line after its leading spaces, indent their number
// (pattern tiles are dumped indented inside their pattern; geometry lines
// two spaces deeper than their path).
template <class Keep>
std::string dump_lines(const std::string& dump, Keep keep) {
  std::string out;
  for (size_t pos = 0; pos < dump.size();) {
    const size_t end = dump.find('\n', pos);
    const std::string_view line = std::string_view(dump).substr(pos, end == std::string::npos ? end : end - pos + 1);
    const size_t indent = std::min(line.find_first_not_of(' '), line.size());
    if (keep(line.substr(indent), indent)) out += line;
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  return out;
}

// The dump without geometry lines at the top level (paths, paints and the
// stream only).
inline std::string without_geometry(const std::string& dump) {
  return dump_lines(dump, [](std::string_view, size_t indent) { return indent < 2; });
}

}  // namespace svg_test
