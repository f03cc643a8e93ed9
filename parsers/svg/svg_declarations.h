// CSS declarations (CSS Syntax 3, simplified): a declaration block
// ("name: value; ...", comments allowed) as names and values with their
// !important flag, as style attributes (svg_dom.cpp) and the rules of
// style sheets (svg_css.cpp) give them.
//
// Internal to the SVG frontend.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mpvg::svg::detail {

// The text without its /* comments */ (an unterminated one runs to the end).
std::string strip_comments(std::string_view s);

// One declaration block's declarations with their !important flag. The
// shorthands marker and font come as the longhands they set, in their
// place (an invalid font shorthand sets none).
struct CssDeclaration {
  std::string name, value;
  bool important = false;
};
std::vector<CssDeclaration> parse_declarations(std::string_view block);

// The declarations of a style attribute, in cascade order: !important
// ones last.
std::vector<std::pair<std::string, std::string>> parse_style_attribute(std::string_view style);

}  // namespace mpvg::svg::detail
