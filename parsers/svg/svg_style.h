// Properties (SVG 2 styling.html, CSS Cascade 4): a property's value on an
// element from its style declarations and presentation attributes, and the
// computed value of an inherited one; svg_style.cpp holds the property
// table they read and computes an element's style for the converter.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/svg_dom.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

// A property's value on one element.
template <class T>
struct Prop {
  // Initial: the keyword "initial" (CSS Cascade 4 §7.1); compute_style
  // resets inherited properties declared so, callers treat it as unset.
  enum State { Unset, Inherit, Initial, Set } state = Unset;
  T value{};
};

// Whether an attribute `name` is a presentation attribute, read as the
// property of that name (the property table in svg_style.cpp): false for
// the properties that SVG 2 styling.html#PresentationAttributes leaves out
// (font-kerning, transform-box, the mask-* longhands, ...), true for the
// others and for names that are no property of the table.
bool presentation_attribute(std::string_view name);
// False for a value of property `name` that svg_style.cpp knows to be
// invalid before the property's own parser sees it: a word that is none of
// the keywords of a property whose value is one keyword (overflow,
// mask-type), a negative size in a declaration (width, height, r, rx, ry).
bool value_valid(std::string_view name, std::string_view value, bool attribute);

// The value of property `name` on `e`. Declarations of the style attribute
// win over the presentation attribute (SVG 2 styling.html#PresentationAttributes:
// they count as author style sheet rules of specificity 0, before all others); a
// later declaration wins over an earlier one; a declaration or attribute
// whose value does not parse is ignored (CSS Syntax 3: invalid declarations are dropped), so the
// next candidate applies. unset (and revert, which falls back to the
// user agent's values: SVG has none for these) ends the search as Unset:
// no value, so that the property inherits or takes its initial value as
// it would without any declaration (CSS Cascade 4 §7.3.3).
template <class T, class Parse>
Prop<T> property(const Element& e, std::string_view name, Parse parse) {
  Prop<T> p;
  auto accept = [&](const std::string& text, bool attribute) {
    const std::string_view t = trim(text);
    if (iequals(t, "inherit")) {
      p.state = Prop<T>::Inherit;
      return true;
    }
    if (iequals(t, "initial")) {
      p.state = Prop<T>::Initial;
      return true;
    }
    if (iequals(t, "unset") || iequals(t, "revert") || iequals(t, "revert-layer")) return true;
    if (!value_valid(name, t, attribute)) return false;
    std::optional<T> v = parse(text);
    if (!v) return false;
    p.state = Prop<T>::Set;
    p.value = std::move(*v);
    return true;
  };
  for (auto it = e.declarations.rbegin(); it != e.declarations.rend(); ++it)
    if (it->first == name && accept(it->second, false)) return p;
  if (const std::string* a = e.attribute(name); a && presentation_attribute(name)) accept(*a, true);
  return p;
}

// The computed value on e of an inherited property: `initial` at the root,
// then each element's own value from the top down ("initial" restarts
// from `initial`). parse(text, inherited) sees the value inherited from
// the parent.
template <class T, class Parse>
T inherited_property(const Element& e, const char* name, T initial, Parse parse) {
  std::vector<const Element*> chain;
  for (const Element* a = &e; a; a = a->parent) chain.push_back(a);
  T value = initial;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    const auto p = property<T>(**it, name, [&](std::string_view v) { return parse(v, value); });
    if (p.state == Prop<T>::Set) value = p.value;
    if (p.state == Prop<T>::Initial) value = initial;
  }
  return value;
}

// The computed value of `color` on e: currentColor in it means the
// parent's (CSS Color 4 §4.4), initially black.
RGBA computed_color(const Element& e);

// A keyword value, lower-cased; nullopt unless the value is one word.
std::optional<std::string> parse_keyword(std::string_view s);


// image-rendering (CSS Images 3 and SVG 1.1's keywords) as a texture filter.
std::optional<TextureFilter> parse_image_rendering(std::string_view v);

}  // namespace mpvg::svg::detail
