// fuzz_css: the CSS parser (parsers/svg/svg_css.h). The input is a style
// sheet: it is the text of a <style> element of a small fixed element tree
// to which every sheet is applied (selector matching, specificity, the
// cascade with style attributes), with @import answered by a fixed loader
// (one sheet for "a.css", refusal otherwise); it is also parsed as a
// declaration block and as a style attribute.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "parsers/svg/svg_css.h"
#include "parsers/svg/svg_dom.h"
#include "parsers/svg/svg_declarations.h"

namespace {

using mpvg::svg::detail::Element;

Element* add(Element& parent, const char* name,
             std::initializer_list<std::pair<std::string, std::string>> attributes = {}) {
  auto e = std::make_unique<Element>();
  e->name = name;
  e->attributes = attributes;
  for (const auto& [k, v] : e->attributes)
    if (k == "style") e->style_attribute = v;
  e->parent = &parent;
  Element* raw = e.get();
  parent.children.push_back(std::move(e));
  return raw;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mpvg::svg::detail;
  const std::string_view sheet(reinterpret_cast<const char*>(data), size);
  Document doc;
  doc.root = std::make_unique<Element>();
  Element& root = *doc.root;
  root.name = "svg";
  root.attributes = {{"id", "root"}, {"width", "10"}, {"height", "10"}};
  Element* style = add(root, "style", {{"type", "text/css"}});
  style->text = std::string(sheet);
  Element* g = add(root, "g", {{"id", "g1"}, {"class", "a b"}, {"lang", "en-US"}, {"style", "fill:red"}});
  add(*g, "rect", {{"class", "b"}, {"x", "1"}, {"style", "stroke: blue !important; fill: green"}});
  add(*g, "circle", {{"id", "c"}, {"r", "2"}});
  add(*g, "rect", {{"class", "c-d"}, {"data-x", "foo bar"}});
  Element* text = add(root, "text", {{"class", "t"}});
  add(*text, "#text")->text = "hi";
  add(root, "path", {{"d", "M0 0h1"}, {"class", "a"}});
  doc.stylesheet_hrefs = {"a.css"};
  for (const auto& c : root.children) doc.ids.emplace(c->name, c.get());
  apply_style_sheets(doc, [](std::string_view href) -> std::optional<std::string> {
    if (href == "a.css") return std::string("@import 'b.css'; rect { fill: blue } .a > .b { stroke: red }");
    return std::nullopt;
  });
  (void)parse_declarations(sheet);
  (void)parse_style_attribute(sheet);
  return 0;
}
