#include "parsers/svg/xml_syntax.h"

#include <cctype>
#include <set>
#include <vector>

namespace mpvg::svg::detail {

namespace {

bool space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Characters that end a name (XML 1.0 §2.3's NameChar excludes them all).
bool name_end(char c) {
  return space(c) || c == '/' || c == '>' || c == '<' || c == '=' || c == '"' || c == '\'' || c == '&' || c == ';' ||
         c == '!' || c == '?';
}

bool name_start(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  return u >= 0x80 || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':';
}

class Scanner {
 public:
  explicit Scanner(std::string_view t) : t_(t) {}

  std::optional<XmlFault> run() {
    if (t_.substr(0, 3) == "\xef\xbb\xbf") p_ = 3;
    bool root_seen = false;
    while (p_ < t_.size()) {
      if (stack_.empty()) {
        // The prolog or what follows the root: markup and white space only.
        if (space(t_[p_])) {
          p_++;
          continue;
        }
        if (t_[p_] != '<') return fault(p_, root_seen ? "text after the end of the root element" : "text before the root element");
        if (t_.compare(p_, 2, "<?") == 0) {
          if (!skip_past(p_ + 2, "?>")) return fault(p_, "a processing instruction (<?...) is not closed with ?>");
        } else if (t_.compare(p_, 4, "<!--") == 0) {
          if (auto f = comment()) return f;
        } else if (t_.compare(p_, 9, "<!DOCTYPE") == 0) {
          if (root_seen) return fault(p_, "a DOCTYPE after the root element");
          if (auto f = doctype()) return f;
        } else if (t_.compare(p_, 2, "</") == 0) {
          return fault(p_, "an end tag without a start tag");
        } else {
          if (root_seen) return fault(p_, "a second root element (a document has one)");
          root_seen = true;
          if (auto f = start_tag()) return f;
        }
        continue;
      }
      // Content.
      const char c = t_[p_];
      if (c == '&') {
        if (auto f = reference()) return f;
      } else if (c != '<') {
        p_++;
      } else if (t_.compare(p_, 4, "<!--") == 0) {
        if (auto f = comment()) return f;
      } else if (t_.compare(p_, 9, "<![CDATA[") == 0) {
        if (!skip_past(p_ + 9, "]]>")) return fault(p_, "a CDATA section is not closed with ]]>");
      } else if (t_.compare(p_, 2, "<?") == 0) {
        if (!skip_past(p_ + 2, "?>")) return fault(p_, "a processing instruction (<?...) is not closed with ?>");
      } else if (t_.compare(p_, 2, "</") == 0) {
        if (auto f = end_tag()) return f;
      } else {
        if (auto f = start_tag()) return f;
      }
    }
    if (!stack_.empty()) {
      const Open& o = stack_.back();
      return fault(t_.size(), "the document ends inside <" + o.name + "> (opened at " + where(o.at) + ")");
    }
    if (!root_seen) return fault(t_.size(), "no element: the document is empty or holds no XML");
    return std::nullopt;
  }

 private:
  struct Open {
    std::string name;
    size_t at;
  };

  XmlFault position(size_t at) const {
    XmlFault f;
    for (size_t i = 0; i < at && i < t_.size(); i++) {
      if (t_[i] == '\n') {
        f.line++;
        f.column = 1;
      } else if ((static_cast<unsigned char>(t_[i]) & 0xC0) != 0x80) {
        f.column++;
      }
    }
    return f;
  }
  std::string where(size_t at) const {
    const XmlFault f = position(at);
    return "line " + std::to_string(f.line) + ", column " + std::to_string(f.column);
  }
  std::optional<XmlFault> fault(size_t at, std::string what) const {
    XmlFault f = position(at);
    f.what = std::move(what);
    return f;
  }

  // Moves p_ past the next `end` after `from`; false when there is none.
  bool skip_past(size_t from, std::string_view end) {
    const size_t e = t_.find(end, from);
    if (e == std::string_view::npos) return false;
    p_ = e + end.size();
    return true;
  }

  std::optional<XmlFault> comment() {
    const size_t at = p_;
    if (!skip_past(p_ + 4, "-->")) return fault(at, "a comment is not closed with -->");
    return std::nullopt;
  }

  // <!DOCTYPE name ... [internal subset] >: quoted literals and the
  // subset's declarations, comments and literals skipped.
  std::optional<XmlFault> doctype() {
    const size_t at = p_;
    p_ += 9;
    int brackets = 0;
    while (p_ < t_.size()) {
      const char c = t_[p_];
      if (c == '"' || c == '\'') {
        const size_t e = t_.find(c, p_ + 1);
        if (e == std::string_view::npos) break;
        p_ = e + 1;
      } else if (t_.compare(p_, 4, "<!--") == 0) {
        if (auto f = comment()) return f;
      } else if (c == '[') {
        brackets++;
        p_++;
      } else if (c == ']') {
        brackets--;
        p_++;
      } else if (c == '>' && brackets <= 0) {
        p_++;
        return std::nullopt;
      } else {
        p_++;
      }
    }
    return fault(at, "the DOCTYPE declaration is not closed with >");
  }

  // &name; &#N; &#xH;
  std::optional<XmlFault> reference() {
    const size_t at = p_;
    size_t i = p_ + 1;
    if (i < t_.size() && t_[i] == '#') {
      i++;
      const bool hex = i < t_.size() && t_[i] == 'x';
      if (hex) i++;
      const size_t digits = i;
      while (i < t_.size() && (std::isdigit(static_cast<unsigned char>(t_[i])) ||
                               (hex && std::isxdigit(static_cast<unsigned char>(t_[i])))))
        i++;
      if (i == digits || i >= t_.size() || t_[i] != ';')
        return fault(at, "a malformed character reference (&#N; or &#xH;)");
    } else {
      if (i >= t_.size() || !name_start(t_[i])) return fault(at, "'&' must start an entity reference (write &amp; for an '&')");
      while (i < t_.size() && !name_end(t_[i])) i++;
      if (i >= t_.size() || t_[i] != ';') return fault(at, "an entity reference is not closed with ';' (write &amp; for an '&')");
    }
    p_ = i + 1;
    return std::nullopt;
  }

  std::string name_at(size_t& i) const {
    const size_t b = i;
    while (i < t_.size() && !name_end(t_[i])) i++;
    return std::string(t_.substr(b, i - b));
  }

  std::optional<XmlFault> start_tag() {
    const size_t at = p_;
    size_t i = p_ + 1;
    if (i >= t_.size() || !name_start(t_[i])) return fault(at, "'<' must start a tag (write &lt; for a '<' in text)");
    const std::string name = name_at(i);
    std::set<std::string> seen;
    for (;;) {
      const size_t before = i;
      while (i < t_.size() && space(t_[i])) i++;
      if (i >= t_.size()) return fault(at, "the <" + name + "> tag is not closed with >");
      if (t_[i] == '>') {
        stack_.push_back({name, at});
        p_ = i + 1;
        return std::nullopt;
      }
      if (t_.compare(i, 2, "/>") == 0) {
        p_ = i + 2;
        return std::nullopt;
      }
      if (!name_start(t_[i]))
        return fault(i, "unexpected '" + std::string(1, t_[i]) + "' in the <" + name + "> tag");
      if (i == before) return fault(i, "attributes of <" + name + "> must be separated by white space");
      const size_t attr_at = i;
      const std::string attr = name_at(i);
      while (i < t_.size() && space(t_[i])) i++;
      if (i >= t_.size() || t_[i] != '=') return fault(attr_at, "the attribute '" + attr + "' of <" + name + "> has no value (write " + attr + "=\"...\")");
      i++;
      while (i < t_.size() && space(t_[i])) i++;
      if (i >= t_.size() || (t_[i] != '"' && t_[i] != '\''))
        return fault(i, "the value of the attribute '" + attr + "' of <" + name + "> must be in quotes");
      const char q = t_[i];
      const size_t value_at = i;
      const size_t e = t_.find(q, i + 1);
      if (e == std::string_view::npos) return fault(value_at, "the value of the attribute '" + attr + "' is not closed");
      const size_t lt = t_.find('<', i + 1);
      if (lt < e) return fault(lt, "'<' in the value of the attribute '" + attr + "' (write &lt;)");
      if (!seen.insert(attr).second) return fault(attr_at, "the attribute '" + attr + "' appears twice in <" + name + ">");
      i = e + 1;
    }
  }

  std::optional<XmlFault> end_tag() {
    const size_t at = p_;
    size_t i = p_ + 2;
    const std::string name = name_at(i);
    while (i < t_.size() && space(t_[i])) i++;
    if (i >= t_.size() || t_[i] != '>') return fault(at, "the end tag </" + name + "> is not closed with >");
    const Open& o = stack_.back();
    if (o.name != name)
      return fault(at, "</" + name + "> does not close <" + o.name + "> (opened at " + where(o.at) + ")");
    stack_.pop_back();
    p_ = i + 1;
    return std::nullopt;
  }

  std::string_view t_;
  size_t p_ = 0;
  std::vector<Open> stack_;
};

}  // namespace

std::optional<XmlFault> find_xml_fault(std::string_view text) { return Scanner(text).run(); }

}  // namespace mpvg::svg::detail
