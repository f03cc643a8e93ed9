#include "parsers/svg/svg_declarations.h"

#include <algorithm>
#include <cctype>
#include <iterator>

#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

std::string strip_comments(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); i++) {
    if (s[i] == '/' && i + 1 < s.size() && s[i + 1] == '*') {
      const size_t end = s.find("*/", i + 2);
      if (end == std::string_view::npos) break;
      i = end + 1;
      continue;
    }
    out += s[i];
  }
  return out;
}

std::vector<CssDeclaration> parse_declarations(std::string_view block) {
  const std::string text = strip_comments(block);
  std::vector<CssDeclaration> out;
  auto declaration = [&](std::string_view d) {
    const size_t colon = d.find(':');
    if (colon == std::string_view::npos) return;
    std::string name(trim(d.substr(0, colon)));
    std::transform(name.begin(), name.end(), name.begin(), [](char c) { return char(std::tolower(c)); });
    std::string_view value = trim(d.substr(colon + 1));
    bool important = false;
    const size_t bang = value.rfind('!');
    if (bang != std::string_view::npos && iequals(trim(value.substr(bang + 1)), "important")) {
      value = trim(value.substr(0, bang));
      important = true;
    }
    if (name.empty() || value.empty()) return;
    // Shorthands become their longhands where they stand, so that the
    // cascade orders each longhand among the others' declarations (CSS
    // Cascade 4 §1.2): marker sets marker-start, -mid and -end; font its
    // font-* longhands (an invalid font is dropped whole).
    if (name == "marker") {
      for (const char* m : {"marker-start", "marker-mid", "marker-end"})
        out.push_back({m, std::string(value), important});
      return;
    }
    if (name == "font") {
      if (const auto longhands = split_font_shorthand(value))
        for (const auto& [n, v] : *longhands) out.push_back({n, v, important});
      return;
    }
    out.push_back({std::move(name), std::string(value), important});
  };
  size_t start = 0;
  int depth = 0;
  char quote = 0;
  for (size_t i = 0; i <= text.size(); i++) {
    const char c = i < text.size() ? text[i] : ';';
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') quote = c;
    else if (c == '(') depth++;
    else if (c == ')') depth--;
    else if (c == ';' && depth <= 0) {
      declaration(std::string_view(text).substr(start, i - start));
      start = i + 1;
    }
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> parse_style_attribute(std::string_view style) {
  // The block's declarations (svg_css.cpp), the !important ones after the
  // others: later entries win, and an important declaration beats any
  // normal one of the block.
  std::vector<std::pair<std::string, std::string>> out, important;
  for (CssDeclaration& d : parse_declarations(style))
    (d.important ? important : out).emplace_back(std::move(d.name), std::move(d.value));
  out.insert(out.end(), std::make_move_iterator(important.begin()), std::make_move_iterator(important.end()));
  return out;
}

}  // namespace mpvg::svg::detail
