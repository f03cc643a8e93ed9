// CSS style sheets (svg_css.h).
#include "parsers/svg/svg_css.h"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <optional>

#include "parsers/svg/svg_declarations.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

namespace {

struct Attr {
  std::string name, value;
  char op = 0;  // 0: present; '=', '~', '|', '^', '$', '*'
};

struct Nth {
  int a = 0, b = 0;
  bool matches(int index) const {  // index counts from 1
    if (a == 0) return index == b;
    const int n = index - b;
    return n % a == 0 && n / a >= 0;
  }
};

struct Compound {
  std::string type;  // empty or "*": any
  std::vector<std::string> ids, classes;
  std::vector<Attr> attrs;
  enum class Pseudo { FirstChild, LastChild, OnlyChild, NthChild, NthLastChild, FirstOfType, LastOfType, Root, Not };
  struct P {
    Pseudo kind;
    Nth nth;
    std::vector<Compound> inner;  // :not()
  };
  std::vector<P> pseudos;
};

struct Selector {
  // Compounds right to left: parts[0] is the subject; combinators[i] joins
  // parts[i] to parts[i + 1] (' ', '>', '+', '~').
  std::vector<Compound> parts;
  std::vector<char> combinators;
  int specificity = 0;  // ids * 10000 + classes/attributes/pseudo-classes * 100 + types
};

struct Rule {
  Selector selector;
  std::vector<CssDeclaration> declarations;
  int order = 0;
};

bool ident_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
         static_cast<unsigned char>(c) >= 0x80 || c == '\\';
}

class SelectorParser {
 public:
  explicit SelectorParser(std::string_view s) : s_(s) {}

  std::optional<Selector> parse() {
    Selector sel;
    std::vector<Compound> left_to_right;
    std::vector<char> combs;
    skip_ws();
    while (true) {
      auto c = compound();
      if (!c) return std::nullopt;
      left_to_right.push_back(std::move(*c));
      const bool ws = skip_ws();
      if (at_end()) break;
      char comb = ' ';
      if (peek() == '>' || peek() == '+' || peek() == '~') {
        comb = s_[i_++];
        skip_ws();
      } else if (!ws) {
        return std::nullopt;
      }
      combs.push_back(comb);
    }
    for (const Compound& c : left_to_right) sel.specificity += specificity(c);
    sel.parts.assign(left_to_right.rbegin(), left_to_right.rend());
    sel.combinators.assign(combs.rbegin(), combs.rend());
    return sel;
  }

 private:
  static int specificity(const Compound& c) {
    int s = int(c.ids.size()) * 10000 + int(c.classes.size() + c.attrs.size()) * 100;
    for (const Compound::P& p : c.pseudos) {
      if (p.kind == Compound::Pseudo::Not)
        for (const Compound& in : p.inner) s += specificity(in);
      else
        s += 100;
    }
    if (!c.type.empty() && c.type != "*") s += 1;
    return s;
  }
  bool at_end() const { return i_ >= s_.size(); }
  char peek() const { return at_end() ? 0 : s_[i_]; }
  bool skip_ws() {
    const size_t b = i_;
    while (!at_end() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\f')) i_++;
    return i_ > b;
  }
  std::string ident() {
    std::string out;
    while (!at_end() && ident_char(s_[i_])) {
      if (s_[i_] == '\\' && i_ + 1 < s_.size()) i_++;  // an escaped character stands for itself
      out += s_[i_++];
    }
    return out;
  }
  std::optional<Nth> nth(std::string_view arg) {
    std::string t;
    for (char c : arg)
      if (c != ' ') t += char(std::tolower(static_cast<unsigned char>(c)));
    if (t == "odd") return Nth{2, 1};
    if (t == "even") return Nth{2, 0};
    Nth n;
    const size_t p = t.find('n');
    auto num = [](const std::string& x, int def) -> std::optional<int> {
      if (x.empty() || x == "+") return def;
      if (x == "-") return -def;
      char* end = nullptr;
      const long v = std::strtol(x.c_str(), &end, 10);
      if (!end || *end) return std::nullopt;
      return int(v);
    };
    if (p == std::string::npos) {
      const auto b = num(t, 0);
      if (!b || t.empty()) return std::nullopt;
      n.b = *b;
      return n;
    }
    const auto a = num(t.substr(0, p), 1), b = num(t.substr(p + 1), 0);
    if (!a || !b) return std::nullopt;
    n.a = *a, n.b = *b;
    return n;
  }
  std::optional<Compound> compound() {
    Compound c;
    bool any = false;
    if (peek() == '*') {
      c.type = "*";
      i_++;
      any = true;
    } else if (ident_char(peek())) {
      c.type = ident();
      any = true;
    }
    while (!at_end()) {
      const char k = peek();
      if (k == '#') {
        i_++;
        const std::string id = ident();
        if (id.empty()) return std::nullopt;
        c.ids.push_back(id);
      } else if (k == '.') {
        i_++;
        const std::string cl = ident();
        if (cl.empty()) return std::nullopt;
        c.classes.push_back(cl);
      } else if (k == '[') {
        i_++;
        skip_ws();
        Attr a;
        a.name = ident();
        skip_ws();
        if (a.name.empty()) return std::nullopt;
        if (peek() == '=') {
          a.op = '=';
          i_++;
        } else if (std::string_view("~|^$*").find(peek()) != std::string_view::npos && peek() &&
                   i_ + 1 < s_.size() && s_[i_ + 1] == '=') {
          a.op = s_[i_];
          i_ += 2;
        }
        if (a.op) {
          skip_ws();
          if (peek() == '"' || peek() == '\'') {
            const char q = s_[i_++];
            const size_t end = s_.find(q, i_);
            if (end == std::string_view::npos) return std::nullopt;
            a.value = std::string(s_.substr(i_, end - i_));
            i_ = end + 1;
          } else {
            a.value = ident();
          }
          skip_ws();
        }
        if (peek() != ']') return std::nullopt;
        i_++;
        c.attrs.push_back(std::move(a));
      } else if (k == ':') {
        i_++;
        if (peek() == ':') return std::nullopt;  // pseudo-elements match no element
        std::string name = ident();
        std::transform(name.begin(), name.end(), name.begin(), [](char ch) { return char(std::tolower(ch)); });
        std::string arg;
        if (peek() == '(') {
          const size_t end = s_.find(')', i_);
          if (end == std::string_view::npos) return std::nullopt;
          arg = std::string(s_.substr(i_ + 1, end - i_ - 1));
          i_ = end + 1;
        }
        using K = Compound::Pseudo;
        Compound::P p{K::Root, {}, {}};
        if (name == "first-child") p.kind = K::FirstChild;
        else if (name == "last-child") p.kind = K::LastChild;
        else if (name == "only-child") p.kind = K::OnlyChild;
        else if (name == "first-of-type") p.kind = K::FirstOfType;
        else if (name == "last-of-type") p.kind = K::LastOfType;
        else if (name == "root") p.kind = K::Root;
        else if (name == "nth-child" || name == "nth-last-child") {
          const auto n = nth(arg);
          if (!n) return std::nullopt;
          p.kind = name == "nth-child" ? K::NthChild : K::NthLastChild;
          p.nth = *n;
        } else if (name == "not") {
          SelectorParser inner(arg);
          inner.skip_ws();
          auto ic = inner.compound();
          inner.skip_ws();
          if (!ic || !inner.at_end()) return std::nullopt;
          p.kind = K::Not;
          p.inner.push_back(std::move(*ic));
        } else {
          return std::nullopt;  // :hover, :link, ... never match a static render
        }
        c.pseudos.push_back(std::move(p));
      } else {
        break;
      }
      any = true;
    }
    if (!any) return std::nullopt;
    return c;
  }

  std::string_view s_;
  size_t i_ = 0;
};

// The element children of e's parent (text nodes skipped).
std::vector<const Element*> siblings(const Element& e) {
  std::vector<const Element*> out;
  if (!e.parent) return {&e};
  for (const auto& c : e.parent->children)
    if (c->name != "#text") out.push_back(c.get());
  return out;
}

bool matches(const Compound& c, const Element& e) {
  if (!c.type.empty() && c.type != "*" && c.type != e.name) return false;
  const std::string* id = e.attribute("id");
  for (const std::string& want : c.ids)
    if (!id || *id != want) return false;
  if (!c.classes.empty()) {
    const std::string* cls = e.attribute("class");
    if (!cls) return false;
    for (const std::string& want : c.classes) {
      bool found = false;
      for (size_t pos = 0; pos < cls->size() && !found;) {
        const size_t b = cls->find_first_not_of(" \t\n\r\f", pos);
        if (b == std::string::npos) break;
        size_t end = cls->find_first_of(" \t\n\r\f", b);
        if (end == std::string::npos) end = cls->size();
        found = cls->compare(b, end - b, want) == 0;
        pos = end;
      }
      if (!found) return false;
    }
  }
  for (const Attr& a : c.attrs) {
    const std::string* v = e.attribute(a.name);
    if (!v) return false;
    const std::string& x = *v;
    switch (a.op) {
      case 0: break;
      case '=': if (x != a.value) return false; break;
      case '~': {
        bool found = false;
        for (size_t pos = 0; pos < x.size() && !found;) {
          const size_t b = x.find_first_not_of(" \t\n\r\f", pos);
          if (b == std::string::npos) break;
          size_t end = x.find_first_of(" \t\n\r\f", b);
          if (end == std::string::npos) end = x.size();
          found = x.compare(b, end - b, a.value) == 0;
          pos = end;
        }
        if (!found) return false;
        break;
      }
      case '|': if (!(x == a.value || x.rfind(a.value + "-", 0) == 0)) return false; break;
      case '^': if (a.value.empty() || x.rfind(a.value, 0) != 0) return false; break;
      case '$':
        if (a.value.empty() || x.size() < a.value.size() || x.compare(x.size() - a.value.size(), a.value.size(), a.value) != 0)
          return false;
        break;
      case '*': if (a.value.empty() || x.find(a.value) == std::string::npos) return false; break;
    }
  }
  if (!c.pseudos.empty()) {
    const std::vector<const Element*> sib = siblings(e);
    const int n = int(sib.size());
    const int index = int(std::find(sib.begin(), sib.end(), &e) - sib.begin()) + 1;
    int type_index = 0, type_count = 0;
    for (const Element* s : sib)
      if (s->name == e.name) {
        type_count++;
        if (s == &e) type_index = type_count;
      }
    using K = Compound::Pseudo;
    for (const Compound::P& p : c.pseudos) {
      bool ok = true;
      switch (p.kind) {
        case K::FirstChild: ok = e.parent && index == 1; break;
        case K::LastChild: ok = e.parent && index == n; break;
        case K::OnlyChild: ok = e.parent && n == 1; break;
        case K::NthChild: ok = e.parent && p.nth.matches(index); break;
        case K::NthLastChild: ok = e.parent && p.nth.matches(n - index + 1); break;
        case K::FirstOfType: ok = e.parent && type_index == 1; break;
        case K::LastOfType: ok = e.parent && type_index == type_count; break;
        case K::Root: ok = !e.parent; break;
        case K::Not: ok = !matches(p.inner[0], e); break;
      }
      if (!ok) return false;
    }
  }
  return true;
}

bool matches(const Selector& s, size_t part, const Element& e) {
  if (!matches(s.parts[part], e)) return false;
  if (part + 1 == s.parts.size()) return true;
  const char comb = s.combinators[part];
  if (comb == '>') return e.parent && matches(s, part + 1, *e.parent);
  if (comb == ' ') {
    for (const Element* a = e.parent; a; a = a->parent)
      if (matches(s, part + 1, *a)) return true;
    return false;
  }
  // Siblings before e.
  const std::vector<const Element*> sib = siblings(e);
  const auto at = std::find(sib.begin(), sib.end(), &e);
  if (at == sib.begin() || at == sib.end()) return false;
  if (comb == '+') return matches(s, part + 1, **(at - 1));
  for (auto it = sib.begin(); it != at; ++it)
    if (matches(s, part + 1, **it)) return true;
  return false;
}

using Loader = std::function<std::optional<std::string>(std::string_view)>;

// Rules of one sheet appended to `rules`; @import rules load theirs first
// (with a loader), other @-rules and their blocks are skipped.
void parse_sheet(std::string_view text, std::vector<Rule>& rules, int& order, const Loader& load = nullptr,
                 int depth = 0) {
  const std::string s = strip_comments(text);
  size_t i = 0;
  while (i < s.size()) {
    const size_t b = s.find_first_not_of(" \t\n\r\f", i);
    if (b == std::string::npos) break;
    if (s.compare(b, 4, "<!--") == 0 || s.compare(b, 3, "-->") == 0) {  // CDO / CDC tokens
      i = b + (s[b] == '<' ? 4 : 3);
      continue;
    }
    if (s[b] == '@') {
      // A statement (to ';') or a block (to its matching '}').
      const size_t semi = s.find(';', b), brace = s.find('{', b);
      if (brace == std::string::npos || (semi != std::string::npos && semi < brace)) {
        const size_t end = semi == std::string::npos ? s.size() : semi;
        // @import "file.css"; or @import url(file.css);
        if (load && depth < 4 && s.compare(b, 7, "@import") == 0) {
          std::string_view arg = trim(std::string_view(s).substr(b + 7, end - b - 7));
          if (arg.substr(0, 4) == "url(" && arg.back() == ')') arg = trim(arg.substr(4, arg.size() - 5));
          if (arg.size() >= 2 && (arg[0] == '"' || arg[0] == '\'') && arg.back() == arg[0])
            arg = arg.substr(1, arg.size() - 2);
          if (!arg.empty())
            if (const auto sheet = load(arg)) parse_sheet(*sheet, rules, order, load, depth + 1);
        }
        i = end == s.size() ? s.size() : end + 1;
        continue;
      }
      int depth = 0;
      size_t k = brace;
      for (; k < s.size(); k++) {
        if (s[k] == '{') depth++;
        else if (s[k] == '}' && --depth == 0) break;
      }
      i = k + 1;
      continue;
    }
    const size_t open = s.find('{', b);
    if (open == std::string::npos) break;
    const size_t close = s.find('}', open);
    const std::string_view prelude = std::string_view(s).substr(b, open - b);
    const std::string_view block =
        std::string_view(s).substr(open + 1, (close == std::string::npos ? s.size() : close) - open - 1);
    i = close == std::string::npos ? s.size() : close + 1;
    const std::vector<CssDeclaration> decls = parse_declarations(block);
    // A selector list: one rule per selector; an invalid selector drops the
    // whole rule (Selectors 4 §3).
    std::vector<Selector> sels;
    bool valid = true;
    int depth = 0;
    size_t start = 0;
    for (size_t k = 0; k <= prelude.size() && valid; k++) {
      if (k < prelude.size() && (prelude[k] == '(' || prelude[k] == '[')) depth++;
      if (k < prelude.size() && (prelude[k] == ')' || prelude[k] == ']')) depth--;
      if (k == prelude.size() || (prelude[k] == ',' && depth == 0)) {
        auto sel = SelectorParser(trim(prelude.substr(start, k - start))).parse();
        if (!sel) valid = false;
        else sels.push_back(std::move(*sel));
        start = k + 1;
      }
    }
    if (!valid) continue;
    for (Selector& sel : sels) rules.push_back({std::move(sel), decls, order++});
  }
}

}  // namespace

void apply_style_sheets(Document& doc, const Loader& load) {
  if (!doc.root) return;
  std::vector<Rule> rules;
  int order = 0;
  if (load)
    for (const std::string& href : doc.stylesheet_hrefs)
      if (const auto sheet = load(href)) parse_sheet(*sheet, rules, order, load, 1);
  std::function<void(const Element&)> gather = [&](const Element& e) {
    if (e.name == "style") {
      const std::string* type = e.attribute("type");
      if (!type || trim(*type).empty() || iequals(trim(*type), "text/css")) parse_sheet(e.text, rules, order, load);
    }
    for (const auto& c : e.children) gather(*c);
  };
  gather(*doc.root);
  if (rules.empty()) return;
  std::stable_sort(rules.begin(), rules.end(), [](const Rule& a, const Rule& b) {
    return a.selector.specificity != b.selector.specificity ? a.selector.specificity < b.selector.specificity
                                                            : a.order < b.order;
  });
  std::function<void(Element&)> apply = [&](Element& e) {
    if (e.name != "#text") {
      std::vector<std::pair<std::string, std::string>> normal, important;
      for (const Rule& r : rules)
        if (matches(r.selector, 0, e))
          for (const CssDeclaration& d : r.declarations) (d.important ? important : normal).emplace_back(d.name, d.value);
      if (!normal.empty() || !important.empty()) {
        std::vector<std::pair<std::string, std::string>> inline_important;
        for (const CssDeclaration& d : parse_declarations(e.style_attribute))
          (d.important ? inline_important : normal).emplace_back(d.name, d.value);
        normal.insert(normal.end(), important.begin(), important.end());
        normal.insert(normal.end(), inline_important.begin(), inline_important.end());
        e.declarations = std::move(normal);
      }
    }
    for (auto& c : e.children) apply(*c);
  };
  apply(*doc.root);
}

Document parse_document(std::string_view text,
                        const std::function<std::optional<std::string>(std::string_view)>& load) {
  Document doc = build_document(text);
  apply_style_sheets(doc, load);
  return doc;
}

}  // namespace mpvg::svg::detail
