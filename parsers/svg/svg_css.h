// CSS style sheets for SVG (SVG 2 styling.html, CSS Cascade 4, Selectors 4):
// the rules of <style> elements parsed into selectors and declarations, and
// applied to the element tree as each element's cascaded declarations.
//
// Selectors: type, universal, #id, .class, attribute ([a], =, ~=, |=, ^=,
// $=, *=), the structural pseudo-classes :first-child, :last-child,
// :only-child, :nth-child(), :nth-last-child(), :first-of-type,
// :last-of-type, :root, :not() of a compound; descendant, child (>), next
// sibling (+) and subsequent sibling (~) combinators. A selector with
// anything else (an unknown pseudo-class, a pseudo-element) matches
// nothing; other @-rules are skipped (@media, @font-face). @import and
// <?xml-stylesheet?> read local files only, through the caller's loader
// (the document's read policy; never the network).
//
// Internal to the SVG frontend.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "parsers/svg/svg_dom.h"

namespace mpvg::svg::detail {

// Applies every style sheet of the document (the text of its <style>
// elements whose type is absent or text/css) to each element: its
// declarations become, in increasing precedence, the matching rules'
// normal declarations (by specificity, then document order), its style
// attribute's normal ones, the rules' !important ones, the style
// attribute's !important ones. Presentation attributes stay below all of
// them (Element::declarations is read first).
// With `load`, the sheets of <?xml-stylesheet?> come first (in document
// order, before the <style> elements) and @import rules at a sheet's start
// bring in the sheets they name (four levels deep at most).
void apply_style_sheets(Document& doc,
                        const std::function<std::optional<std::string>(std::string_view)>& load = nullptr);

// An SVG document's element tree (build_document, svg_dom.h) with its CSS
// sheets applied (apply_style_sheets): <style>, and with `load`
// <?xml-stylesheet?> and @import of the files it gives (href to CSS text,
// nullopt when refused). Throws as build_document does.
Document parse_document(std::string_view text,
                        const std::function<std::optional<std::string>(std::string_view)>& load = nullptr);

}  // namespace mpvg::svg::detail
