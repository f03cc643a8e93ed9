// The character encoding of an XML document (XML 1.0 §4.3.3 and Appendix
// F): tinyxml2 reads UTF-8 only, so documents in UTF-16 (which every XML
// processor must read), ISO-8859-1, US-ASCII or windows-1252 are turned
// into UTF-8 before it sees them.
//
// Internal to the SVG frontend.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace mpvg::svg::detail {

// The document as UTF-8, without a byte-order mark. The encoding is found
// from the byte-order mark or the first bytes ("<?" in UTF-16), then from
// the encoding declaration. Throws mpvg::Error for UTF-32 and for other
// declared encodings whose bytes are not valid UTF-8 ("the document's
// encoding 'Shift_JIS' is not supported").
std::string xml_to_utf8(std::string_view bytes);
// The same, copied only when converted: UTF-8 bytes come back as a view of
// `bytes` (after the byte-order mark); converted text is put in `storage`
// and viewed there.
std::string_view xml_to_utf8(std::string_view bytes, std::string& storage);

// Appends code point c in UTF-8 (1 to 4 bytes).
void append_utf8(std::string& out, uint32_t c);

}  // namespace mpvg::svg::detail
