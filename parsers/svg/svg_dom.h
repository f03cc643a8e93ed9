// The SVG element tree: XML parsed by tinyxml2, reduced to the elements of
// the SVG namespace, with namespaced attribute names resolved and the style
// attribute split into declarations.
//
// Internal to the SVG frontend.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace mpvg::svg::detail {

struct Element {
  std::string name;  // local name; the element is in the SVG namespace
  // Attributes without a namespace (or in the SVG namespace) under their
  // local name; XLink attributes as "xlink:NAME"; others are dropped.
  std::vector<std::pair<std::string, std::string>> attributes;
  // Declarations of the style attribute in document order: lower-case
  // property names, trimmed values, "!important" removed.
  std::vector<std::pair<std::string, std::string>> declarations;
  // The style attribute as written (svg_css.cpp re-cascades it with the
  // style sheets' rules).
  std::string style_attribute;
  const Element* parent = nullptr;
  std::vector<std::unique_ptr<Element>> children;
  // Character data, for the children named "#text" that text content
  // elements (text and what it holds) keep, and a <style> element's sheet.
  std::string text;

  const std::string* attribute(std::string_view name) const;
};

struct Document {
  std::unique_ptr<Element> root;
  // The hrefs of <?xml-stylesheet?> processing instructions (type absent
  // or text/css), in document order.
  std::vector<std::string> stylesheet_hrefs;
  // The first element carrying each id.
  std::unordered_map<std::string, const Element*> ids;
  // What the user should hear of (elements nested too deep, left out).
  std::vector<std::string> warnings;
};

// XML nested deeper than tinyxml2 parses (TINYXML2_MAX_ELEMENT_DEPTH, 100
// in 9.x) is parsed in pieces: an element that would open at depth
// kXmlPieceDepth inside its piece starts a piece of its own, which its
// parent holds as a placeholder element (named U+FDD0 and the piece's
// number: no document has that name) that the tree builder replaces by
// the piece's tree. Elements nested deeper than kMaxXmlDepth in all are
// left out with their content, with a warning: the converter would
// ignore them (kMaxDepth), and the DOM's recursions stay bounded.
constexpr int kXmlPieceDepth = 64;
constexpr int kMaxXmlDepth = 257;
struct XmlPieces {
  std::vector<std::string> pieces;  // pieces[0] is the document; empty: no piece needed
  std::vector<int> first_line;      // the text's line where each piece starts
  bool dropped = false;             // elements past max_depth were left out
};
XmlPieces split_deep_xml(const std::string& text, int piece_depth = kXmlPieceDepth, int max_depth = kMaxXmlDepth);

// Parses XML text into the element tree, style attributes read as
// declarations (svg_declarations.h); style sheets are applied by
// parse_document (svg_css.h). Throws mpvg::Error on malformed XML ("XML
// parse error at line N: ...") and when the root element is not an SVG
// <svg>.
Document build_document(std::string_view text);

// Expands the general entities declared in the document's internal DTD
// subset (<!DOCTYPE svg [ <!ENTITY name "value"> ]>), which tinyxml2 does not
// do; drawing tools write the SVG namespace itself through one. A DOCTYPE
// with an internal subset is blanked out (tinyxml2 mis-splits it). Expansion
// is one level deep and the output size is bounded.
std::string expand_internal_entities(std::string_view text);
// The same, copied only when something changes: a document without an
// internal subset comes back as `text` itself; otherwise the result is put
// in `storage` and viewed there.
std::string_view expand_internal_entities(std::string_view text, std::string& storage);

}  // namespace mpvg::svg::detail
