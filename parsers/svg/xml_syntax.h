// Where an XML document stops being well-formed (XML 1.0 §2-§4), said as a
// sentence: tinyxml2 reports an error's kind and line only
// (XML_ERROR_PARSING_ATTRIBUTE at line 3), so when it refuses a document
// this scanner walks the text again and names the first fault it meets
// with its line and column: "line 3, column 13: the value of attribute 'x'
// must be in quotes".
//
// It checks what a well-formedness error is made of: tags and their
// nesting, attributes (names, '=', quoted values without '<', no
// duplicates), comments, CDATA sections, processing instructions, the
// DOCTYPE (its internal subset skipped), entity and character references,
// one root element and nothing but markup and white space around it. Names
// are checked for the characters that end them, not for XML's full name
// classes.
//
// Internal to the SVG frontend.
#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace mpvg::svg::detail {

struct XmlFault {
  int line = 1, column = 1;  // 1-based; columns count characters (UTF-8 code points)
  std::string what;          // a sentence without a full stop
};

// The first well-formedness fault of UTF-8 text; nullopt when none is found.
std::optional<XmlFault> find_xml_fault(std::string_view text);

}  // namespace mpvg::svg::detail
