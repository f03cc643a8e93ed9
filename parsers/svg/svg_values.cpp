#include "parsers/svg/svg_values.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <string>

namespace mpvg::svg::detail {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
float clamp01(double v) { return static_cast<float>(std::clamp(v, 0.0, 1.0)); }

}  // namespace

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_ws(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_ws(s.back())) s.remove_suffix(1);
  return s;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); i++)
    if (ascii_lower(a[i]) != ascii_lower(b[i])) return false;
  return true;
}

// ---------------------------------------------------------------- Scanner

bool Scanner::consume_word(std::string_view w) {
  if (s_.size() - pos_ < w.size() || !iequals(s_.substr(pos_, w.size()), w)) return false;
  pos_ += w.size();
  return true;
}

namespace {

// Clinger's fast path (W. D. Clinger, "How to read floating point numbers
// accurately", PLDI 1990): a decimal significand w below 2^53 and a power
// of ten 10^e with |e| <= 22 are both exact doubles, so w * 10^e or
// w / 10^-e is one correctly rounded operation: the double from_chars
// gives, bit for bit. Path data's numbers are nearly all of this kind; the
// rest go through from_chars.
constexpr double kExactPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
constexpr uint64_t kExactSignificand = uint64_t(1) << 53;

}  // namespace

std::optional<double> Scanner::number() {
  size_t i = pos_;
  const size_t n = s_.size();
  if (i < n && (s_[i] == '+' || s_[i] == '-')) i++;
  const size_t mantissa = i;
  size_t int_digits = 0, frac_digits = 0;
  // The significand's digits as an integer while it stays exact (19
  // digits fit 64 bits; `exact` ends at the first that would not).
  uint64_t w = 0;
  bool exact = true;
  auto digit = [&](char c) {
    if (w > (UINT64_MAX - 9) / 10) exact = false;
    else w = w * 10 + uint64_t(c - '0');
  };
  while (i < n && is_digit(s_[i])) digit(s_[i]), i++, int_digits++;
  if (i < n && s_[i] == '.') {
    size_t j = i + 1;
    while (j < n && is_digit(s_[j])) digit(s_[j]), j++, frac_digits++;
    // "1." is a number in SVG 2 path data; a lone "." is not.
    if (int_digits > 0 || frac_digits > 0) i = j;
  }
  if (int_digits == 0 && frac_digits == 0) return std::nullopt;
  long e10 = -static_cast<long>(frac_digits);
  if (i < n && (s_[i] == 'e' || s_[i] == 'E')) {
    size_t j = i + 1;
    bool negative = false;
    if (j < n && (s_[j] == '+' || s_[j] == '-')) negative = s_[j] == '-', j++;
    if (j < n && is_digit(s_[j])) {
      long e = 0;
      while (j < n && is_digit(s_[j])) {
        if (e < 100000) e = e * 10 + (s_[j] - '0');
        j++;
      }
      e10 += negative ? -e : e;
      i = j;
    }
  }
  double v = 0;
  if (exact && w <= kExactSignificand && e10 >= -22 && e10 <= 22) {
    v = e10 < 0 ? double(w) / kExactPow10[-e10] : double(w) * kExactPow10[e10];
  } else {
    // from_chars takes no leading '+'; the sign is applied below.
    const char* first = s_.data() + mantissa;
    const char* last = s_.data() + i;
    const auto r = std::from_chars(first, last, v, std::chars_format::general);
    if (r.ec != std::errc() || r.ptr != last || !std::isfinite(v)) return std::nullopt;
  }
  if (mantissa > pos_ && s_[pos_] == '-') v = -v;
  if (std::fabs(v) > max_) return std::nullopt;
  pos_ = i;
  return v;
}

std::string_view Scanner::word() {
  const size_t start = pos_;
  while (!at_end() && (is_alpha(s_[pos_]) || is_digit(s_[pos_]) || s_[pos_] == '-')) pos_++;
  return s_.substr(start, pos_ - start);
}

std::optional<double> parse_number(std::string_view text) {
  Scanner s(trim(text));
  const auto v = s.number();
  if (!v || !s.at_end()) return std::nullopt;
  return v;
}

// ---------------------------------------------------------------- lengths

namespace {

// A length unit's name (ASCII case-insensitive), '%' aside.
std::optional<Unit> length_unit(std::string_view name) {
  static const struct {
    const char* name;
    Unit unit;
  } units[] = {{"px", Unit::Px}, {"pt", Unit::Pt}, {"pc", Unit::Pc}, {"mm", Unit::Mm}, {"cm", Unit::Cm},
               {"in", Unit::In}, {"em", Unit::Em}, {"ex", Unit::Ex}, {"rem", Unit::Rem}};
  for (const auto& e : units)
    if (iequals(name, e.name)) return e.unit;
  return std::nullopt;
}

// A dimension at the cursor: a number with an optional unit or '%'.
std::optional<Length> dimension(Scanner& s) {
  const auto v = s.number();
  if (!v) return std::nullopt;
  Length l{*v, Unit::None};
  if (s.consume('%')) {
    l.unit = Unit::Percent;
    return l;
  }
  Scanner probe(s.rest());
  const std::string_view u = probe.word();
  if (u.empty()) return l;
  const auto unit = length_unit(u);
  if (!unit) return std::nullopt;
  l.unit = *unit;
  s.consume_word(u);
  return l;
}

// calc() (CSS Values 4 §10): a value is a plain number or a sum of
// length terms; `number` says which.
struct CalcValue {
  bool number = true;
  double n = 0;                          // number
  double px = 0, pct = 0, em = 0, ex = 0, rem = 0;  // length terms
};

CalcValue calc_of(const Length& l) {
  CalcValue v;
  if (l.unit == Unit::None) {
    v.n = l.value;
    return v;
  }
  v.number = false;
  switch (l.unit) {
    case Unit::Percent: v.pct = l.value; break;
    case Unit::Em: v.em = l.value; break;
    case Unit::Ex: v.ex = l.value; break;
    case Unit::Rem: v.rem = l.value; break;
    default: v.px = length_to_px(l, 0); break;
  }
  return v;
}

CalcValue scaled(CalcValue v, double k) {
  v.n *= k;
  v.px *= k;
  v.pct *= k;
  v.em *= k;
  v.ex *= k;
  v.rem *= k;
  return v;
}

constexpr int kMaxCalcDepth = 32;

std::optional<CalcValue> calc_sum(Scanner& s, int depth);

// A value: a dimension, or a parenthesised or calc() sum.
std::optional<CalcValue> calc_value(Scanner& s, int depth) {
  s.skip_ws();
  if (depth > kMaxCalcDepth) return std::nullopt;
  const bool call = s.consume_word("calc(");
  if (call || s.consume('(')) {
    const auto v = calc_sum(s, depth + 1);
    s.skip_ws();
    if (!v || !s.consume(')')) return std::nullopt;
    return v;
  }
  const auto d = dimension(s);
  if (!d) return std::nullopt;
  return calc_of(*d);
}

std::optional<CalcValue> calc_product(Scanner& s, int depth) {
  auto v = calc_value(s, depth);
  if (!v) return std::nullopt;
  for (;;) {
    Scanner look = s;
    look.skip_ws();
    const bool mul = look.consume('*');
    if (!mul && !look.consume('/')) return v;
    s = look;
    const auto r = calc_value(s, depth);
    if (!r) return std::nullopt;
    if (mul) {
      if (!v->number && !r->number) return std::nullopt;  // length * length
      v = v->number ? scaled(*r, v->n) : scaled(*v, r->n);
    } else {
      if (!r->number || r->n == 0) return std::nullopt;  // by a length, or by zero
      v = scaled(*v, 1 / r->n);
    }
  }
}

std::optional<CalcValue> calc_sum(Scanner& s, int depth) {
  auto v = calc_product(s, depth);
  if (!v) return std::nullopt;
  for (;;) {
    // '+' and '-' need white space on both sides ("1px -2px" is no sum).
    Scanner look = s;
    const size_t before = look.pos();
    look.skip_ws();
    if (look.pos() == before) return v;
    const bool plus = look.consume('+');
    if (!plus && !look.consume('-')) return v;
    const size_t op = look.pos();
    look.skip_ws();
    if (look.pos() == op) return std::nullopt;
    s = look;
    auto r = calc_product(s, depth);
    if (!r || r->number != v->number) return std::nullopt;  // number + length
    if (!plus) r = scaled(*r, -1);
    v->n += r->n;
    v->px += r->px;
    v->pct += r->pct;
    v->em += r->em;
    v->ex += r->ex;
    v->rem += r->rem;
  }
}

}  // namespace

std::optional<Length> parse_length(std::string_view text, CalcOk calc, double max_magnitude) {
  Scanner s(trim(text), max_magnitude);
  if (calc == CalcOk::Yes && s.consume_word("calc(")) {
    const auto v = calc_sum(s, 0);
    s.skip_ws();
    if (!v || !s.consume(')') || !s.at_end() || v->number) return std::nullopt;
    for (double t : {v->px, v->pct, v->em, v->ex, v->rem})
      if (!std::isfinite(t) || std::fabs(t) > max_magnitude) return std::nullopt;
    Length l{v->px, Unit::Calc};
    l.percent = v->pct;
    l.em = v->em;
    l.ex = v->ex;
    l.rem = v->rem;
    return l;
  }
  const auto l = dimension(s);
  if (!l || !s.at_end()) return std::nullopt;
  return l;
}

namespace {
thread_local double px_per_inch = 96;
}  // namespace

AbsoluteUnitsScope::AbsoluteUnitsScope(double dpi) : saved_(px_per_inch) { px_per_inch = dpi; }
AbsoluteUnitsScope::~AbsoluteUnitsScope() { px_per_inch = saved_; }

double length_to_px(const Length& l, double percent_base) {
  // CSS Values 3 absolute lengths: 1in = 96px = 2.54cm = 72pt = 6pc (96:
  // px_per_inch, unless --dpi says otherwise).
  const double in = px_per_inch;
  switch (l.unit) {
    case Unit::None:
    case Unit::Px: return l.value;
    case Unit::Pt: return l.value * (in / 72.0);
    case Unit::Pc: return l.value * (in / 6.0);
    case Unit::Mm: return l.value * (in / 25.4);
    case Unit::Cm: return l.value * (in / 2.54);
    case Unit::In: return l.value * in;
    case Unit::Em:
    case Unit::Rem: return l.value * 16.0;
    case Unit::Ex: return l.value * 8.0;
    case Unit::Percent: return l.value * percent_base / 100.0;
    case Unit::Calc: return l.value + l.percent * percent_base / 100.0 + (l.em + l.rem) * 16.0 + l.ex * 8.0;
  }
  return l.value;
}

double resolve_length(const Length& l, double percent_base, double em, double rem) {
  switch (l.unit) {
    case Unit::Em: return l.value * em;
    case Unit::Rem: return l.value * rem;
    case Unit::Ex: return l.value * em / 2;
    case Unit::Calc: return l.value + l.percent / 100 * percent_base + l.em * em + l.ex * em / 2 + l.rem * rem;
    default: return length_to_px(l, percent_base);
  }
}

// ---------------------------------------------------------------- transforms

void sincos_snapped(double radians, double& s, double& c) {
  s = std::sin(radians);
  c = std::cos(radians);
  constexpr double eps = 1e-15;
  if (std::fabs(s) < eps) {
    s = 0;
    c = c < 0 ? -1 : 1;
  } else if (std::fabs(c) < eps) {
    c = 0;
    s = s < 0 ? -1 : 1;
  }
}

namespace {

// A transform argument in degrees: a number, or a CSS angle (deg, grad,
// rad, turn).
std::optional<double> transform_angle(double v, std::string_view unit) {
  if (unit.empty() || iequals(unit, "deg")) return v;
  if (iequals(unit, "grad")) return v * 0.9;
  if (iequals(unit, "rad")) return v * (180.0 / M_PI);
  if (iequals(unit, "turn")) return v * 360.0;
  return std::nullopt;
}

// A transform argument in user units: a number, or a CSS absolute length.
std::optional<double> transform_length(double v, std::string_view unit) {
  if (unit.empty()) return v;
  const auto u = length_unit(unit);
  if (!u || *u == Unit::Em || *u == Unit::Ex || *u == Unit::Rem) return std::nullopt;
  return length_to_px(Length{v, *u}, 0);
}

}  // namespace

std::optional<Affine> parse_transform(std::string_view text) {
  Scanner s(text);
  Affine result;
  s.skip_ws();
  if (s.consume_word("none")) {
    s.skip_ws();
    return s.at_end() ? std::optional<Affine>(result) : std::nullopt;
  }
  while (!s.at_end()) {
    const std::string_view name = s.word();
    s.skip_ws();
    if (!s.consume('(')) return std::nullopt;
    s.skip_ws();
    double a[6];
    std::string_view unit[6];
    int n = 0;
    while (n < 6) {
      const auto v = s.number();
      if (!v) break;
      // A CSS unit (rotate(45deg), translate(10px, 5px)): letters right
      // after the number ("10-20" stays two numbers).
      const std::string_view rest = s.rest();
      size_t letters = 0;
      while (letters < rest.size() && is_alpha(rest[letters])) letters++;
      unit[n] = rest.substr(0, letters);
      s.consume_word(unit[n]);
      a[n++] = *v;
      s.skip_comma_ws();
    }
    if (!s.consume(')')) return std::nullopt;

    auto angle = [&](int k) { return transform_angle(a[k], unit[k]); };
    auto length = [&](int k) { return transform_length(a[k], unit[k]); };
    auto plain = [&](int from, int to) {
      for (int k = from; k < to; k++)
        if (!unit[k].empty()) return false;
      return true;
    };
    Affine t;
    if (name == "matrix" && n == 6 && plain(0, 6)) {
      t = {a[0], a[1], a[2], a[3], a[4], a[5]};
    } else if (name == "translate" && (n == 1 || n == 2)) {
      const auto x = length(0), y = n == 2 ? length(1) : std::optional<double>(0);
      if (!x || !y) return std::nullopt;
      t = Affine::translate(*x, *y);
    } else if ((name == "translateX" || name == "translateY") && n == 1) {
      const auto d = length(0);
      if (!d) return std::nullopt;
      t = name == "translateX" ? Affine::translate(*d, 0) : Affine::translate(0, *d);
    } else if (name == "scale" && (n == 1 || n == 2) && plain(0, n)) {
      t = Affine::scale(a[0], n == 2 ? a[1] : a[0]);
    } else if ((name == "scaleX" || name == "scaleY") && n == 1 && plain(0, 1)) {
      t = name == "scaleX" ? Affine::scale(a[0], 1) : Affine::scale(1, a[0]);
    } else if (name == "rotate" && (n == 1 || n == 3)) {
      const auto deg = angle(0);
      std::optional<double> cx = 0, cy = 0;
      if (n == 3) cx = length(1), cy = length(2);
      if (!deg || !cx || !cy) return std::nullopt;
      double sn, cs;
      sincos_snapped(std::fmod(*deg, 360.0) * (M_PI / 180.0), sn, cs);
      t = {cs, sn, -sn, cs, 0, 0};
      // rotate(a cx cy) = translate(cx cy) rotate(a) translate(-cx -cy).
      if (n == 3) t = Affine::translate(*cx, *cy) * t * Affine::translate(-*cx, -*cy);
    } else if ((name == "skewX" || name == "skewY") && n == 1) {
      const auto deg = angle(0);
      if (!deg) return std::nullopt;
      t = name == "skewX" ? Affine::skew_x_degrees(*deg) : Affine::skew_y_degrees(*deg);
    } else if (name == "skew" && (n == 1 || n == 2)) {
      // CSS skew(ax, ay): x' = x + tan(ax) y, y' = tan(ay) x + y.
      const auto ax = angle(0), ay = n == 2 ? angle(1) : std::optional<double>(0);
      if (!ax || !ay) return std::nullopt;
      t = {1, std::tan(*ay * (M_PI / 180.0)), std::tan(*ax * (M_PI / 180.0)), 1, 0, 0};
    } else {
      return std::nullopt;
    }
    // The list applies right to left: "A B" maps p to A(B(p)).
    result = result * t;
    s.skip_comma_ws();
  }
  const double m[6] = {result.a, result.b, result.c, result.d, result.e, result.f};
  for (double v : m)
    if (!std::isfinite(v)) return std::nullopt;
  return result;
}

// ---------------------------------------------------------------- colours

namespace {

// Hue in degrees, saturation and lightness in [0, 1] (CSS Color 3 §4.2.4).
RGBA hsl_to_rgb(double h, double sat, double light) {
  h = std::fmod(h, 360.0);
  if (h < 0) h += 360.0;
  h /= 360.0;
  const double m2 = light <= 0.5 ? light * (sat + 1) : light + sat - light * sat;
  const double m1 = light * 2 - m2;
  auto hue = [&](double t) {
    if (t < 0) t += 1;
    if (t > 1) t -= 1;
    if (t * 6 < 1) return m1 + (m2 - m1) * t * 6;
    if (t * 2 < 1) return m2;
    if (t * 3 < 2) return m1 + (m2 - m1) * (2.0 / 3.0 - t) * 6;
    return m1;
  };
  return {clamp01(hue(h + 1.0 / 3.0)), clamp01(hue(h)), clamp01(hue(h - 1.0 / 3.0)), 1};
}

// rgb()/rgba()/hsl()/hsla() after the name: "(" args ")". Accepts the comma
// syntax of CSS Color 3 and the space syntax with "/ alpha" of CSS Color 4.
std::optional<RGBA> parse_color_function(Scanner& s, bool hsl) {
  if (!s.consume('(')) return std::nullopt;
  s.skip_ws();
  double v[3];
  bool pct[3];
  for (int i = 0; i < 3; i++) {
    if (i > 0) s.skip_comma_ws();
    const auto n = s.number();
    if (!n) return std::nullopt;
    v[i] = *n;
    pct[i] = s.consume('%');
    if (hsl && i == 0 && !pct[0]) s.consume_word("deg");
  }
  double alpha = 1;
  s.skip_ws();
  if (s.consume(',') || s.consume('/')) {
    s.skip_ws();
    const auto a = s.number();
    if (!a) return std::nullopt;
    alpha = s.consume('%') ? *a / 100.0 : *a;
    s.skip_ws();
  }
  if (!s.consume(')')) return std::nullopt;
  RGBA c;
  if (hsl) {
    // Saturation and lightness are percentages; bare numbers are read as
    // percentages too (CSS Color 4 modern syntax).
    c = hsl_to_rgb(v[0], std::clamp(v[1] / 100.0, 0.0, 1.0), std::clamp(v[2] / 100.0, 0.0, 1.0));
  } else {
    c.r = clamp01(pct[0] ? v[0] / 100.0 : v[0] / 255.0);
    c.g = clamp01(pct[1] ? v[1] / 100.0 : v[1] / 255.0);
    c.b = clamp01(pct[2] ? v[2] / 100.0 : v[2] / 255.0);
  }
  c.a = clamp01(alpha);
  return c;
}

}  // namespace

std::optional<RGBA> parse_color(Scanner& s) {
  if (s.consume('#')) {
    int d[8];
    int n = 0;
    while (!s.at_end() && hex_value(s.peek()) >= 0) {
      if (n == 8) return std::nullopt;  // more than 8 digits
      d[n++] = hex_value(s.peek());
      s.consume(s.peek());
    }
    RGBA c;
    if (n == 3 || n == 4) {
      c = {d[0] * 17 / 255.0f, d[1] * 17 / 255.0f, d[2] * 17 / 255.0f, n == 4 ? d[3] * 17 / 255.0f : 1.0f};
    } else if (n == 6 || n == 8) {
      c = {(d[0] * 16 + d[1]) / 255.0f, (d[2] * 16 + d[3]) / 255.0f, (d[4] * 16 + d[5]) / 255.0f,
           n == 8 ? (d[6] * 16 + d[7]) / 255.0f : 1.0f};
    } else {
      return std::nullopt;
    }
    return c;
  }
  const std::string_view name = s.word();
  if (name.empty()) return std::nullopt;
  s.skip_ws();
  if (s.peek() == '(') {
    if (iequals(name, "rgb") || iequals(name, "rgba")) return parse_color_function(s, false);
    if (iequals(name, "hsl") || iequals(name, "hsla")) return parse_color_function(s, true);
    return std::nullopt;
  }
  return named_color(name);
}

std::optional<RGBA> parse_color(std::string_view text) {
  Scanner s(trim(text));
  auto c = parse_color(s);
  if (!c) return std::nullopt;
  s.skip_ws();
  // SVG 1.1 §11.2: "<color> [<icccolor>]"; ICC colours are not managed.
  if (s.consume_word("icc-color(")) return c;
  if (!s.at_end()) return std::nullopt;
  return c;
}

// ---------------------------------------------------------------- paint and IRIs

std::optional<std::string> parse_func_iri(Scanner& s, bool* external) {
  if (!s.consume_word("url(")) return std::nullopt;
  s.skip_ws();
  char quote = 0;
  if (s.peek() == '\'' || s.peek() == '"') {
    quote = s.peek();
    s.consume(quote);
  }
  std::string iri;
  while (!s.at_end()) {
    const char c = s.peek();
    if (quote ? c == quote : (c == ')' || is_ws(c))) break;
    iri += c;
    s.consume(c);
  }
  if (quote && !s.consume(quote)) return std::nullopt;
  s.skip_ws();
  if (!s.consume(')')) return std::nullopt;
  const size_t hash = iri.find('#');
  if (external) *external = hash != 0;
  if (hash == std::string::npos) return std::string();
  return iri.substr(hash + 1);
}

std::optional<std::string> parse_iri_fragment(std::string_view text) {
  text = trim(text);
  if (text.size() < 2 || text[0] != '#') return std::nullopt;
  return std::string(text.substr(1));
}

std::optional<PaintValue> parse_paint(std::string_view text) {
  Scanner s(trim(text));
  PaintValue p;
  if (s.peek() == 'u' || s.peek() == 'U') {
    bool external = false;
    const auto id = parse_func_iri(s, &external);
    if (!id) return std::nullopt;
    p.kind = PaintValue::Kind::Url;
    p.url = *id;
    p.url_external = external;
    const std::string_view fallback = trim(s.rest());
    if (fallback.empty()) return p;
    if (iequals(fallback, "none")) {
      p.fallback = PaintValue::Fallback::None;
    } else if (iequals(fallback, "currentColor")) {
      p.fallback = PaintValue::Fallback::CurrentColor;
    } else {
      const auto color = parse_color(fallback);
      if (!color) return std::nullopt;
      p.fallback = PaintValue::Fallback::Color;
      p.fallback_color = *color;
    }
    return p;
  }
  const std::string_view all = trim(text);
  if (iequals(all, "none")) return p;
  if (iequals(all, "currentColor")) {
    p.kind = PaintValue::Kind::CurrentColor;
    return p;
  }
  if (iequals(all, "context-fill") || iequals(all, "context-stroke")) {
    p.kind = PaintValue::Kind::Context;
    p.context_stroke = iequals(all, "context-stroke");
    return p;
  }
  const auto color = parse_color(all);
  if (!color) return std::nullopt;
  p.kind = PaintValue::Kind::Color;
  p.color = *color;
  return p;
}

// <blend-mode> (Compositing and Blending 1 §7, and plus-lighter of level
// 2, which Chromium takes); core's Porter-Duff operators past it are not
// CSS blend modes.
std::optional<BlendMode> parse_blend_mode(std::string_view s) {
  for (int i = 0; i <= static_cast<int>(BlendMode::PlusLighter); i++)
    if (iequals(trim(s), blend_mode_name(static_cast<BlendMode>(i)))) return static_cast<BlendMode>(i);
  return std::nullopt;
}

std::optional<double> parse_alpha(std::string_view text) {
  Scanner s(trim(text));
  const auto v = s.number();
  if (!v) return std::nullopt;
  double a = *v;
  if (s.consume('%')) a /= 100.0;
  if (!s.at_end()) return std::nullopt;
  return std::clamp(a, 0.0, 1.0);
}

// ---------------------------------------------------------------- font shorthand

std::optional<std::vector<std::pair<std::string, std::string>>> split_font_shorthand(std::string_view v) {
  using Longhands = std::vector<std::pair<std::string, std::string>>;
  static const char* const names[] = {"font-style",  "font-variant", "font-weight",      "font-stretch", "font-size",
                                      "line-height", "font-family",  "font-size-adjust", "font-kerning"};
  v = trim(v);
  for (const char* keyword : {"inherit", "initial", "unset", "revert", "revert-layer"})
    if (iequals(v, keyword)) {
      Longhands out;
      for (const char* n : names) out.emplace_back(n, std::string(v));
      return out;
    }
  auto lower = [](std::string_view w) {
    std::string k(w);
    for (char& c : k) c = ascii_lower(c);
    return k;
  };
  auto one_of = [](const std::string& k, std::initializer_list<const char*> list) {
    for (const char* x : list)
      if (k == x) return true;
    return false;
  };
  // The next word from `pos`: up to white space or '/', parentheses kept whole (calc()).
  auto next_word = [&](size_t& pos) -> std::string_view {
    while (pos < v.size() && is_ws(v[pos])) pos++;
    const size_t b = pos;
    int depth = 0;
    while (pos < v.size() && (depth > 0 || !(is_ws(v[pos]) || v[pos] == '/'))) {
      if (v[pos] == '(') depth++;
      if (v[pos] == ')') depth--;
      pos++;
    }
    return v.substr(b, pos - b);
  };
  std::string style, variant, weight, stretch;
  int words = 0;
  for (size_t pos = 0;;) {
    const std::string_view word = next_word(pos);
    if (word.empty() || ++words > 5) return std::nullopt;  // no size, or more than four words before it
    const std::string k = lower(word);
    const auto length = parse_length(word, CalcOk::Yes);
    const bool size_keyword = one_of(k, {"xx-small", "x-small", "small", "medium", "large", "x-large", "xx-large",
                                         "xxx-large", "larger", "smaller"});
    const bool unitless = length && length->unit == Unit::None;
    if (size_keyword || (length && (!unitless || length->value == 0) && length->value >= 0)) {
      std::string line_height = "normal";
      size_t at = pos;
      while (at < v.size() && is_ws(v[at])) at++;
      if (at < v.size() && v[at] == '/') {
        pos = at + 1;
        const std::string_view lh = next_word(pos);
        if (lh.empty()) return std::nullopt;
        line_height = std::string(lh);
      }
      const std::string_view family = trim(v.substr(pos));
      // A family is required; quotes must close.
      if (family.empty() || family.front() == ',' || family.back() == ',') return std::nullopt;
      for (size_t i = 0; i < family.size(); i++)
        if (family[i] == '"' || family[i] == '\'') {
          const size_t close = family.find(family[i], i + 1);
          if (close == std::string_view::npos) return std::nullopt;
          i = close;
        }
      const std::string values[] = {style.empty() ? "normal" : style,     variant.empty() ? "normal" : variant,
                                    weight.empty() ? "normal" : weight,   stretch.empty() ? "normal" : stretch,
                                    std::string(word),                    line_height,
                                    std::string(family),                  "none",
                                    "auto"};
      Longhands out;
      for (size_t i = 0; i < std::size(names); i++) out.emplace_back(names[i], values[i]);
      return out;
    }
    if (k == "normal") continue;
    if (style.empty() && (k == "italic" || k == "oblique")) {
      style = k;
      // oblique <angle>
      size_t at = pos;
      const std::string_view angle = next_word(at);
      Scanner sc(angle);
      if (k == "oblique" && sc.number() && !sc.at_end()) {
        const std::string unit = lower(angle.substr(sc.pos()));
        if (one_of(unit, {"deg", "grad", "rad", "turn"})) {
          style += " " + std::string(angle);
          pos = at;
        }
      }
    } else if (variant.empty() && k == "small-caps") {
      variant = k;
    } else if (weight.empty() && (one_of(k, {"bold", "bolder", "lighter"}) ||
                                  (unitless && length->value >= 1 && length->value <= 1000))) {
      weight = k;
    } else if (stretch.empty() && one_of(k, {"ultra-condensed", "extra-condensed", "condensed", "semi-condensed",
                                             "semi-expanded", "expanded", "extra-expanded", "ultra-expanded"})) {
      stretch = k;
    } else {
      return std::nullopt;
    }
  }
}

// ---------------------------------------------------------------- viewports

std::optional<ViewBox> parse_view_box(std::string_view text) {
  Scanner s(text);
  s.skip_ws();
  double v[4];
  for (int i = 0; i < 4; i++) {
    if (i > 0) s.skip_comma_ws();
    const auto n = s.number();
    if (!n) return std::nullopt;
    v[i] = *n;
  }
  s.skip_ws();
  if (!s.at_end() || v[2] < 0 || v[3] < 0) return std::nullopt;
  return ViewBox{v[0], v[1], v[2], v[3]};
}

std::optional<AspectRatio> parse_aspect_ratio(std::string_view text) {
  Scanner s(text);
  s.skip_ws();
  std::string_view w = s.word();
  if (w == "defer") {
    s.skip_ws();
    w = s.word();
  }
  AspectRatio ar;
  if (w == "none") {
    ar.x = ar.y = AspectRatio::Align::None;
  } else {
    if (w.size() != 8 || w[0] != 'x' || w[4] != 'Y') return std::nullopt;
    auto align = [](std::string_view a) -> std::optional<AspectRatio::Align> {
      if (a == "Min") return AspectRatio::Align::Min;
      if (a == "Mid") return AspectRatio::Align::Mid;
      if (a == "Max") return AspectRatio::Align::Max;
      return std::nullopt;
    };
    const auto ax = align(w.substr(1, 3)), ay = align(w.substr(5, 3));
    if (!ax || !ay) return std::nullopt;
    ar.x = *ax;
    ar.y = *ay;
  }
  s.skip_ws();
  const std::string_view mode = s.word();
  if (mode == "slice") {
    ar.slice = true;
  } else if (!mode.empty() && mode != "meet") {
    return std::nullopt;
  }
  s.skip_ws();
  if (!s.at_end()) return std::nullopt;
  return ar;
}

Affine view_box_transform(const ViewBox& vb, const AspectRatio& ar, double width, double height) {
  double sx = width / vb.w, sy = height / vb.h;
  if (ar.x != AspectRatio::Align::None) {
    sx = sy = ar.slice ? std::max(sx, sy) : std::min(sx, sy);
  }
  double tx = -vb.x * sx, ty = -vb.y * sy;
  const double free_x = width - vb.w * sx, free_y = height - vb.h * sy;
  if (ar.x == AspectRatio::Align::Mid) tx += free_x / 2;
  if (ar.x == AspectRatio::Align::Max) tx += free_x;
  if (ar.y == AspectRatio::Align::Mid) ty += free_y / 2;
  if (ar.y == AspectRatio::Align::Max) ty += free_y;
  return {sx, 0, 0, sy, tx, ty};
}

}  // namespace mpvg::svg::detail
