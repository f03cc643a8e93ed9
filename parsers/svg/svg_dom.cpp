#include "parsers/svg/svg_dom.h"

#include "parsers/svg/svg_declarations.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "parsers/svg/svg_values.h"
#include "parsers/svg/xml_encoding.h"
#include "parsers/svg/xml_syntax.h"

namespace mpvg::svg::detail {

std::string unmark_white_space(const char* text);

namespace {

constexpr std::string_view kSvgNs = "http://www.w3.org/2000/svg";
constexpr std::string_view kXlinkNs = "http://www.w3.org/1999/xlink";

// In-scope namespace declarations (Namespaces in XML 1.0 §6, "Applying Namespaces"): a stack of
// (prefix, uri); "" is the default namespace. Later entries shadow earlier.
class NamespaceScope {
 public:
  // The namespace of `prefix`, or nullptr when undeclared.
  const std::string* lookup(std::string_view prefix) const {
    for (auto it = decls_.rbegin(); it != decls_.rend(); ++it)
      if (it->first == prefix) return &it->second;
    return nullptr;
  }
  size_t mark() const { return decls_.size(); }
  void release(size_t mark) { decls_.resize(mark); }
  void declare(std::string prefix, std::string uri) {
    decls_.emplace_back(std::move(prefix), std::move(uri));
  }

 private:
  std::vector<std::pair<std::string, std::string>> decls_;
};

std::pair<std::string_view, std::string_view> split_qname(std::string_view q) {
  const size_t colon = q.find(':');
  if (colon == std::string_view::npos) return {{}, q};
  return {q.substr(0, colon), q.substr(colon + 1)};
}

// Whether an element name is in the SVG namespace. In a document that does
// not use namespaces at all (an unprefixed root without xmlns, as
// hand-written files often are), unprefixed names without a default
// namespace are taken as SVG: nothing else could be meant.
bool in_svg_namespace(std::string_view prefix, const NamespaceScope& ns, bool no_namespaces) {
  const std::string* uri = ns.lookup(prefix);
  if (!uri) return no_namespaces && prefix.empty();
  return *uri == kSvgNs;
}

// What tinyxml2's error kinds mean, for a document in which
// find_xml_fault finds no fault (the two disagree on a detail).
const char* error_sentence(tinyxml2::XMLError e) {
  switch (e) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: return "no element: the document is empty or holds no XML";
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: return "a malformed tag";
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: return "a malformed attribute";
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: return "an end tag that does not match its start tag";
    case tinyxml2::XML_ERROR_PARSING_TEXT: return "malformed text";
    case tinyxml2::XML_ERROR_PARSING_CDATA: return "a malformed CDATA section";
    case tinyxml2::XML_ERROR_PARSING_COMMENT: return "a comment that is not closed";
    case tinyxml2::XML_ERROR_PARSING_DECLARATION: return "a malformed <?...?> declaration";
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN: return "a malformed <!...> declaration";
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED: return "elements nested too deep";
    default: return "not well-formed XML";
  }
}

// The one-line message of a document tinyxml2 refuses: the first fault
// find_xml_fault finds in the document's text `utf8`, with its line and
// column; else tinyxml2's line (counted from first_line, a piece's start
// in the text, split_deep_xml) and its error kind in words.
ParseError xml_error(const tinyxml2::XMLDocument& xml, int first_line, std::string_view raw) {
  std::optional<XmlFault> f;
  try {
    f = find_xml_fault(xml_to_utf8(raw));
  } catch (const Error&) {
  }
  if (f)
    return ParseError("XML parse error at line " + std::to_string(f->line) + ", column " + std::to_string(f->column) +
                      ": " + f->what);
  return ParseError("XML parse error at line " + std::to_string(first_line - 1 + std::max(1, xml.ErrorLineNum())) +
                    ": " + error_sentence(xml.ErrorID()));
}

constexpr std::string_view kPieceMark = "\xef\xb7\x90";  // U+FDD0, as mark_white_space_text uses it

class TreeBuilder {
 public:
  TreeBuilder(Document& doc, const XmlPieces& pieces, std::string_view raw) : doc_(doc), pieces_(pieces), raw_(raw) {}

  // Converts x and its subtree; nullptr when x is not an SVG element (its
  // subtree is then dropped too: SVG content inside foreign elements is not
  // rendered).
  std::unique_ptr<Element> build(const tinyxml2::XMLElement* x, const Element* parent) {
    const size_t mark = ns_.mark();
    for (const tinyxml2::XMLAttribute* a = x->FirstAttribute(); a; a = a->Next()) {
      const std::string_view name = a->Name();
      if (name == "xmlns")
        ns_.declare("", a->Value());
      else if (name.substr(0, 6) == "xmlns:")
        ns_.declare(std::string(name.substr(6)), a->Value());
    }
    const auto [prefix, local] = split_qname(x->Name());
    if (!parent) no_namespaces_ = prefix.empty() && !ns_.lookup("");
    std::unique_ptr<Element> e;
    if (in_svg_namespace(prefix, ns_, no_namespaces_)) {
      e = std::make_unique<Element>();
      e->name = std::string(local);
      e->parent = parent;
      copy_attributes(x, *e);
      // Character data is kept inside text content elements only, as
      // children named "#text" (svg_text.cpp lays them out).
      const bool text_content = in_text_ || e->name == "text";
      const bool was_in_text = in_text_;
      in_text_ = text_content;
      for (const tinyxml2::XMLNode* c = x->FirstChild(); c; c = c->NextSibling()) {
        if (const tinyxml2::XMLElement* ce = c->ToElement()) {
          if (std::string_view(ce->Name()).substr(0, kPieceMark.size()) == kPieceMark) {
            if (auto child = build_piece(ce, e.get())) e->children.push_back(std::move(child));
          } else if (auto child = build(ce, e.get())) {
            e->children.push_back(std::move(child));
          }
        } else if (const tinyxml2::XMLText* t = c->ToText(); t && e->name == "style") {
          e->text += unmark_white_space(t->Value());  // CSS text, CDATA sections included
        } else if (const tinyxml2::XMLText* t = c->ToText(); t && text_content) {
          auto node = std::make_unique<Element>();
          node->name = "#text";
          node->text = unmark_white_space(t->Value());
          node->parent = e.get();
          e->children.push_back(std::move(node));
        }
      }
      in_text_ = was_in_text;
    }
    ns_.release(mark);
    return e;
  }

 private:
  // The tree of the piece a placeholder stands for (split_deep_xml),
  // parsed now and dropped once converted.
  std::unique_ptr<Element> build_piece(const tinyxml2::XMLElement* placeholder, const Element* parent) {
    const size_t k = std::strtoul(placeholder->Name() + kPieceMark.size(), nullptr, 10);
    if (k == 0 || k >= pieces_.pieces.size()) return nullptr;
    const std::string& text = pieces_.pieces[k];
    tinyxml2::XMLDocument xml;
    if (xml.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) throw xml_error(xml, pieces_.first_line[k], raw_);
    const tinyxml2::XMLElement* root = xml.RootElement();
    return root ? build(root, parent) : nullptr;
  }

  void copy_attributes(const tinyxml2::XMLElement* x, Element& e) {
    size_t count = 0;
    for (const tinyxml2::XMLAttribute* a = x->FirstAttribute(); a; a = a->Next()) count++;
    e.attributes.reserve(count);  // grown one at a time, the vector moved its strings again and again
    for (const tinyxml2::XMLAttribute* a = x->FirstAttribute(); a; a = a->Next()) {
      const std::string_view qname = a->Name();
      if (qname == "xmlns" || qname.substr(0, 6) == "xmlns:") continue;
      const auto [prefix, local] = split_qname(qname);
      std::string name;
      if (prefix.empty()) {
        name = std::string(local);
      } else {
        const std::string* uri = ns_.lookup(prefix);
        // An undeclared "xlink" prefix is a common slip; honour it.
        if ((uri && *uri == kXlinkNs) || (!uri && prefix == "xlink"))
          name = "xlink:" + std::string(local);
        else if (prefix == "xml")  // bound to the XML namespace by definition (xml:space)
          name = "xml:" + std::string(local);
        else if (uri && *uri == kSvgNs)
          name = std::string(local);
        else
          continue;
      }
      const std::string_view value = a->Value();  // one strlen, not one per use
      if (name == "style") {
        e.declarations = parse_style_attribute(value);
        e.style_attribute = value;
        continue;
      }
      if (name == "id" && !value.empty()) doc_.ids.emplace(value, &e);
      e.attributes.emplace_back(std::move(name), value);
    }
  }

  Document& doc_;
  const XmlPieces& pieces_;
  std::string_view raw_;  // the document as read, for error messages
  NamespaceScope ns_;
  bool no_namespaces_ = false;
  bool in_text_ = false;  // inside a <text>
};

}  // namespace

const std::string* Element::attribute(std::string_view n) const {
  for (const auto& [k, v] : attributes)
    if (k == n) return &v;
  return nullptr;
}

std::string expand_internal_entities(std::string_view text) {
  std::string storage;
  const std::string_view out = expand_internal_entities(text, storage);
  if (out.data() == storage.data()) return storage;
  return std::string(out);
}

std::string_view expand_internal_entities(std::string_view text, std::string& storage) {
  const size_t doctype = text.find("<!DOCTYPE");
  if (doctype == std::string_view::npos) return text;
  const size_t open = text.find('[', doctype);
  const size_t first_gt = text.find('>', doctype);
  if (open == std::string_view::npos || open > first_gt) return text;
  // The subset ends at the first ']' outside quoted literals and comments.
  size_t close = open + 1;
  while (close < text.size() && text[close] != ']') {
    const char c = text[close];
    size_t next = close + 1;
    if (c == '"' || c == '\'') {
      next = text.find(c, close + 1);
      next = next == std::string_view::npos ? text.size() : next + 1;
    } else if (text.substr(close, 4) == "<!--") {
      next = text.find("-->", close + 4);
      next = next == std::string_view::npos ? text.size() : next + 3;
    }
    close = next;
  }
  const size_t end = text.find('>', close);
  if (end == std::string_view::npos) return text;

  // <!ENTITY name "value"> and <!ENTITY name 'value'>; parameter entities
  // ('%') and external entities (SYSTEM/PUBLIC) are not expanded.
  std::vector<std::pair<std::string, std::string>> entities;
  const std::string_view subset = text.substr(open + 1, close - open - 1);
  for (size_t p = subset.find("<!ENTITY"); p != std::string_view::npos; p = subset.find("<!ENTITY", p + 1)) {
    Scanner s(subset.substr(p + 8));
    s.skip_ws();
    if (s.peek() == '%') continue;
    std::string name;
    while (!s.at_end() && !is_ws(s.peek()) && s.peek() != '"' && s.peek() != '\'') {
      name += s.peek();
      s.consume(s.peek());
    }
    s.skip_ws();
    const char q = s.peek();
    if (name.empty() || (q != '"' && q != '\'')) continue;
    s.consume(q);
    const std::string_view rest = s.rest();
    const size_t qend = rest.find(q);
    if (qend == std::string_view::npos) continue;
    entities.emplace_back(std::move(name), std::string(rest.substr(0, qend)));
  }

  // tinyxml2 splits a DOCTYPE at every '>', so markup inside entity values
  // would leak out as elements: blank the whole declaration, keeping its
  // newlines so that error line numbers stay right.
  std::string& out = storage;
  out.assign(text.substr(0, doctype));
  for (size_t i = doctype; i <= end; i++) out += text[i] == '\n' ? '\n' : ' ';
  const size_t limit = std::max<size_t>(text.size() * 4, size_t(1) << 20);
  // The text a run at a time, from one '&' to the next.
  size_t i = end + 1;
  while (i < text.size()) {
    const size_t amp = entities.empty() ? text.size() : std::min(text.find('&', i), text.size());
    out.append(text, i, amp - i);
    i = amp;
    if (i == text.size()) break;
    if (out.size() < limit) {
      const size_t semi = text.find(';', i + 1);
      if (semi != std::string_view::npos && semi - i <= 64) {
        const std::string_view name = text.substr(i + 1, semi - i - 1);
        const auto it =
            std::find_if(entities.begin(), entities.end(), [&](const auto& e) { return e.first == name; });
        if (it != entities.end()) {
          out += it->second;
          i = semi + 1;
          continue;
        }
      }
    }
    out += '&';
    i++;
  }
  return out;
}

// tinyxml2 (9.x, Debian 12's) drops text nodes made only of white space,
// which text layout needs ("<tspan>a</tspan> <tspan>b</tspan>" has a space
// between the words). Inside the root element, such runs between two tags
// get the Unicode noncharacter U+FDD0 in front (never interchanged, so no
// document has it), which makes tinyxml2 keep them (with their newlines, so
// error line numbers stay right); the tree builder removes it again.
std::string mark_white_space_text(std::string_view xml) {
  // The root element's start: the first '<' followed by a name character.
  size_t root = 0;
  for (;;) {
    root = xml.find('<', root);
    if (root == std::string::npos || root + 1 >= xml.size()) return std::string(xml);
    const char c = xml[root + 1];
    if (c != '?' && c != '!') break;
    root++;
  }
  std::string out;
  out.reserve(xml.size() + xml.size() / 8);
  // From '>' to '>', copied a run at a time.
  for (size_t i = 0; i < xml.size();) {
    const size_t gt = xml.find('>', i);
    if (gt == std::string::npos) {
      out.append(xml, i, std::string::npos);
      break;
    }
    out.append(xml, i, gt + 1 - i);
    i = gt + 1;
    if (i <= root) continue;
    // After a tag's '>' (not the end of a comment, CDATA section or
    // processing instruction): white space up to the next '<'.
    if (i >= 3 && (xml.compare(i - 3, 3, "-->") == 0 || xml.compare(i - 3, 3, "]]>") == 0)) continue;
    if (i >= 2 && xml[i - 2] == '?') continue;
    size_t j = i;
    while (j < xml.size() && (xml[j] == ' ' || xml[j] == '\t' || xml[j] == '\n' || xml[j] == '\r')) j++;
    if (j > i && j < xml.size() && xml[j] == '<') out += "\xef\xb7\x90";  // U+FDD0
  }
  return out;
}

// The text without mark_white_space_text's marks.
std::string unmark_white_space(const char* text) {
  std::string out = text;
  for (size_t at; (at = out.find("\xef\xb7\x90")) != std::string::npos;) out.erase(at, 3);
  return out;
}

namespace {

// One construct of XML text from a '<' at i: its kind and where it ends
// (npos: unterminated). Comments, CDATA sections, processing instructions
// and declarations (a DOCTYPE's internal subset in brackets) are Other.
enum class XmlToken { Start, Empty, End, Other };
std::pair<XmlToken, size_t> xml_token(const std::string& t, size_t i) {
  auto after = [&](std::string_view end, size_t from) {
    const size_t at = t.find(end, from);
    return at == std::string::npos ? at : at + end.size();
  };
  if (t.compare(i, 4, "<!--") == 0) return {XmlToken::Other, after("-->", i + 4)};
  if (t.compare(i, 9, "<![CDATA[") == 0) return {XmlToken::Other, after("]]>", i + 9)};
  if (t.compare(i, 2, "<?") == 0) return {XmlToken::Other, after("?>", i + 2)};
  const bool declaration = t.compare(i, 2, "<!") == 0, end_tag = t.compare(i, 2, "</") == 0;
  int brackets = 0;
  char quote = 0;
  for (size_t k = i + 1; k < t.size(); k++) {
    const char c = t[k];
    if (quote) {
      // to the closing quote at once: attribute values (path data) are
      // most of a document's bytes
      const void* at = std::memchr(t.data() + k, quote, t.size() - k);
      if (!at) break;
      k = static_cast<size_t>(static_cast<const char*>(at) - t.data());
      quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (declaration && c == '[') {
      brackets++;
    } else if (declaration && c == ']') {
      brackets--;
    } else if (c == '>' && brackets <= 0) {
      if (declaration) return {XmlToken::Other, k + 1};
      if (end_tag) return {XmlToken::End, k + 1};
      return {t[k - 1] == '/' ? XmlToken::Empty : XmlToken::Start, k + 1};
    }
  }
  return {XmlToken::Other, std::string::npos};
}

}  // namespace

XmlPieces split_deep_xml(const std::string& text, int piece_depth, int max_depth) {
  // First only the depth: most documents need no piece.
  int depth = 0, deepest = 0;
  for (size_t i = text.find('<'); i != std::string::npos; i = text.find('<', i)) {
    const auto [kind, end] = xml_token(text, i);
    if (end == std::string::npos) break;
    if (kind == XmlToken::Start) deepest = std::max(deepest, ++depth);
    if (kind == XmlToken::Empty) deepest = std::max(deepest, depth + 1);
    if (kind == XmlToken::End) depth--;
    i = end;
  }
  XmlPieces out;
  if (deepest <= piece_depth && deepest <= max_depth) return out;
  struct Open {
    size_t piece;
    int depth;  // elements open in it
  };
  std::vector<Open> open{{0, 0}};
  out.pieces.emplace_back();
  out.first_line.push_back(1);
  int total = 0, skip = 0, line = 1;  // skip > 0: inside an element left out, this deep in it
  auto lines = [&](size_t from, size_t to) { return int(std::count(text.begin() + from, text.begin() + to, '\n')); };
  auto emit = [&](size_t from, size_t to) {
    if (!skip) out.pieces[open.back().piece].append(text, from, to - from);
  };
  // The piece ends at line `last`: its placeholder closes in the parent,
  // with as many newlines as the piece spans.
  auto close_piece = [&](int last) {
    const size_t done = open.back().piece;
    open.pop_back();
    out.pieces[open.back().piece] += std::string(size_t(last - out.first_line[done]), '\n') + "/>";
  };
  size_t i = 0;
  while (i < text.size()) {
    const size_t lt = std::min(text.find('<', i), text.size());
    emit(i, lt);
    line += lines(i, lt);
    if (lt == text.size()) break;
    const auto [kind, end] = xml_token(text, lt);
    if (end == std::string::npos) {  // tinyxml2 says what is wrong
      emit(lt, text.size());
      break;
    }
    const int tag_lines = lines(lt, end);
    if ((kind == XmlToken::Start || kind == XmlToken::Empty) && !skip && total + 1 > max_depth) {
      out.dropped = true;
      if (kind == XmlToken::Start) skip = 1;
    } else if (kind == XmlToken::Start && skip) {
      skip++;
    } else if (kind == XmlToken::End && skip) {
      skip--;
    } else if (kind == XmlToken::Start && open.back().depth == piece_depth) {
      // A piece of its own; the placeholder keeps the parent's lines where
      // they are (its newlines stand for the piece's).
      const size_t k = out.pieces.size();
      out.pieces[open.back().piece] += "<" + std::string(kPieceMark) + std::to_string(k);
      open.push_back({k, 1});
      out.pieces.emplace_back();
      out.first_line.push_back(line);
      out.pieces[k].append(text, lt, end - lt);
      total++;
    } else {
      emit(lt, end);
      if (kind == XmlToken::Start) {
        open.back().depth++;
        total++;
      } else if (kind == XmlToken::End && open.back().depth > 0) {
        open.back().depth--;
        total--;
        if (open.back().depth == 0 && open.size() > 1) {
          // The piece ends: its placeholder closes in the parent, with as
          // many newlines as the piece spans.
          close_piece(line + tag_lines);
        }
      }
    }
    line += tag_lines;
    i = end;
  }
  // Pieces left open (the document ends inside them: their own parse says
  // so) still close in their parents.
  while (open.size() > 1) close_piece(line);
  return out;
}

Document build_document(std::string_view raw) {
  // The encoding and entity steps copy the text only when they change it:
  // a UTF-8 document without an internal subset is copied once, marked,
  // before tinyxml2 takes its own copy (whole copies of a large document
  // were a tenth of its parse, page faults included).
  std::string text;
  {
    std::string converted, expanded;
    text = mark_white_space_text(expand_internal_entities(xml_to_utf8(raw, converted), expanded));
  }
  XmlPieces pieces = split_deep_xml(text);
  if (!pieces.pieces.empty()) text = std::move(pieces.pieces[0]);
  tinyxml2::XMLDocument xml;
  if (xml.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) throw xml_error(xml, 1, raw);
  const tinyxml2::XMLElement* root = xml.RootElement();
  if (!root) throw Error("not an SVG document: no root element");

  Document doc;
  // <?xml-stylesheet href="..." type="text/css"?> before the root.
  for (const tinyxml2::XMLNode* n = xml.FirstChild(); n && n != root; n = n->NextSibling()) {
    const tinyxml2::XMLDeclaration* d = n->ToDeclaration();
    if (!d || !d->Value()) continue;
    const std::string_view v = d->Value();
    if (v.substr(0, 14) != "xml-stylesheet") continue;
    auto pseudo_attr = [&](std::string_view name) -> std::optional<std::string> {
      const size_t at = v.find(std::string(name) + "=");
      if (at == std::string_view::npos || at + name.size() + 1 >= v.size()) return std::nullopt;
      const char q = v[at + name.size() + 1];
      if (q != '"' && q != '\'') return std::nullopt;
      const size_t end = v.find(q, at + name.size() + 2);
      if (end == std::string_view::npos) return std::nullopt;
      return std::string(v.substr(at + name.size() + 2, end - at - name.size() - 2));
    };
    const auto type = pseudo_attr("type");
    const auto href = pseudo_attr("href");
    if (href && (!type || *type == "text/css")) doc.stylesheet_hrefs.push_back(*href);
  }
  if (pieces.dropped)
    doc.warnings.push_back("elements nested deeper than " + std::to_string(kMaxXmlDepth) +
                           " levels: left out with their content");
  TreeBuilder builder(doc, pieces, raw);
  doc.root = builder.build(root, nullptr);
  if (!doc.root || doc.root->name != "svg") {
    const auto [prefix, local] = split_qname(root->Name());
    if (local == "svg") {
      const std::string attr = prefix.empty() ? "xmlns" : "xmlns:" + std::string(prefix);
      const char* ns = root->Attribute(attr.c_str());
      throw Error(std::string("not an SVG document: the root <") + root->Name() + "> is in namespace '" +
                  (ns ? ns : "(undeclared)") + "', not " + std::string(kSvgNs));
    }
    throw Error(std::string("not an SVG document: the root element is <") + root->Name() + ">, not <svg>");
  }
  return doc;
}

}  // namespace mpvg::svg::detail
