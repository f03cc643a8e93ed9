// CSS style sheets (parsers/svg/svg_css.cpp): each case's scene dump equals
// the dump of the same document styled by presentation attributes alone,
// i.e. the cascade picked the declarations the comment says.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "parsers/svg/svg_css.h"
#include "parsers/svg/svg_declarations.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_values.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"
#include "frame/scene_info.h"

namespace {

std::string headers_of(const std::string& body) {
  return svg_test::without_geometry(mpvg::dump(mpvg::svg::parse_svg_string(svg_test::document(body)).scene));
}

// The whole dump (geometry included).
std::string dump_of(const std::string& body) {
  return mpvg::dump(mpvg::svg::parse_svg_string(svg_test::document(body)).scene);
}

std::vector<std::string> warnings_of(const std::string& body) {
  return mpvg::svg::parse_svg_string(svg_test::document(body)).warnings;
}

const std::string kRect = R"(width="10" height="10")";

std::string rect(const std::string& attrs) { return "<rect " + kRect + " " + attrs + "/>"; }

}  // namespace

TEST_CASE("css: type, class, id, universal and attribute selectors", "[svg][css]") {
  CHECK(headers_of("<style>rect { fill: red }</style>" + rect("")) == headers_of(rect(R"(fill="red")")));
  CHECK(headers_of("<style>.a { fill: green }</style>" + rect(R"(class="b a")") + rect(R"(class="ab")")) ==
        headers_of(rect(R"(fill="green")") + rect("")));
  CHECK(headers_of("<style>#r1 { fill: blue }</style>" + rect(R"(id="r1")") + rect(R"(id="r2")")) ==
        headers_of(rect(R"(id="r1" fill="blue")") + rect(R"(id="r2")")));
  CHECK(headers_of("<style>* { fill: yellow }</style>" + rect("")) == headers_of(rect(R"(fill="yellow")")));
  // [a], [a=v], [a~=v], [a|=v], [a^=v], [a$=v], [a*=v]
  CHECK(headers_of("<style>[data-x] { fill: red } [data-y=\"b c\"] { fill: green } [data-z~=q] { fill: blue }"
                   "[lang|=en] { fill: yellow } [data-p^=ab] { fill: cyan } [data-s$=yz] { fill: magenta }"
                   "[data-m*=mid] { fill: gray }</style>" +
                   rect(R"(data-x="")") + rect(R"(data-y="b c")") + rect(R"(data-z="p q r")") +
                   rect(R"(lang="en-GB")") + rect(R"(data-p="abc")") + rect(R"(data-s="xyz")") +
                   rect(R"(data-m="amidst")") + rect(R"(lang="english")")) ==
        headers_of(rect(R"(fill="red")") + rect(R"(fill="green")") + rect(R"(fill="blue")") +
                   rect(R"(fill="yellow")") + rect(R"(fill="cyan")") + rect(R"(fill="magenta")") +
                   rect(R"(fill="gray")") + rect("")));
}

TEST_CASE("css: combinators and structural pseudo-classes", "[svg][css]") {
  // g rect (descendant), g > rect (child), rect + rect, rect ~ rect
  CHECK(headers_of("<style>g rect { fill: red } g > rect { stroke: blue } circle + rect { fill: green }"
                   "circle ~ rect { opacity: 0.5 }</style>"
                   "<g><g>" + rect("") + "</g>" + rect("") + "</g><circle r=\"1\"/>" + rect("") + rect("")) ==
        headers_of("<g><g>" + rect(R"(fill="red" stroke="blue")") + "</g>" + rect(R"(fill="red" stroke="blue")") +
                   "</g><circle r=\"1\"/>" + rect(R"(fill="green" opacity="0.5")") + rect(R"(opacity="0.5")")));
  CHECK(headers_of("<style>rect:first-child { fill: red } rect:last-child { fill: blue }"
                   "rect:nth-child(2n+3) { stroke: green } g > :not(rect) { fill: yellow }</style>"
                   "<g>" + rect("") + rect("") + rect("") + rect("") + "<circle r=\"1\"/></g>") ==
        headers_of("<g>" + rect(R"(fill="red")") + rect("") + rect(R"(stroke="green")") + rect("") +
                   "<circle r=\"1\" fill=\"yellow\"/></g>"));
  // An unknown pseudo-class or a pseudo-element makes its rule match nothing.
  CHECK(headers_of("<style>rect:hover, rect { fill: red } rect::before { fill: blue }</style>" + rect("")) ==
        headers_of(rect("")));
}

TEST_CASE("css: the cascade: specificity, order, style attribute, !important, attributes", "[svg][css]") {
  // More specific wins whatever the order; equal specificity: the later.
  CHECK(headers_of("<style>#a { fill: red } rect.c { fill: blue } rect { fill: green }</style>" +
                   rect(R"(id="a" class="c")")) == headers_of(rect(R"(id="a" fill="red")")));
  CHECK(headers_of("<style>.c { fill: red } .c { fill: blue }</style>" + rect(R"(class="c")")) ==
        headers_of(rect(R"(fill="blue")")));
  // Sheet rules beat presentation attributes; the style attribute beats
  // sheet rules; !important in a sheet beats the style attribute, an
  // important style attribute beats that.
  CHECK(headers_of("<style>rect { fill: red }</style>" + rect(R"(fill="blue")")) == headers_of(rect(R"(fill="red")")));
  CHECK(headers_of("<style>rect { fill: red }</style>" + rect(R"(style="fill: blue")")) ==
        headers_of(rect(R"(fill="blue")")));
  CHECK(headers_of("<style>rect { fill: red !important }</style>" + rect(R"(style="fill: blue")")) ==
        headers_of(rect(R"(fill="red")")));
  CHECK(headers_of("<style>rect { fill: red !important }</style>" + rect(R"(style="fill: blue !important")")) ==
        headers_of(rect(R"(fill="blue")")));
  // A sheet after the element it styles, in CDATA, with comments and
  // @-rules skipped; a sheet of another type is not CSS.
  CHECK(headers_of(rect("") + "<style><![CDATA[ /* c */ @media print { rect { fill: blue } } rect { fill: red } ]]></style>") ==
        headers_of(rect(R"(fill="red")")));
  CHECK(headers_of("<style type=\"text/other\">rect { fill: red }</style>" + rect("")) == headers_of(rect("")));
}

TEST_CASE("css: <?xml-stylesheet?> and @import read local sheets under the read policy", "[svg][css]") {
  // linked.svg links sheet.css, which imports imported.css, and
  // /etc/passwd, which lies outside the document's folder: a warning.
  const std::string dir = std::string(MPVG_SOURCE_DIR) + "/testdata/css/";
  const auto linked = mpvg::svg::parse_svg_file(dir + "linked.svg");
  CHECK(mpvg::dump(linked.scene) == mpvg::dump(mpvg::svg::parse_svg_file(dir + "linked-expected.svg").scene));
  REQUIRE(linked.warnings.size() == 1);
  CHECK(linked.warnings[0] == "style sheet not loaded: '/etc/passwd' lies outside the folders the document may read");
  // From a string without a folder the same sheet is not read.
  CHECK(mpvg::svg::parse_svg_string("<?xml-stylesheet href='https://example.org/x.css'?>"
                                    "<svg xmlns='http://www.w3.org/2000/svg' width='1' height='1'/>")
            .warnings.size() == 1);
}

TEST_CASE("css: initial resets an inherited property; inherit takes the parent's", "[svg][css]") {
  CHECK(headers_of("<g fill='red' stroke='blue'>" + rect("fill='initial'") + "</g>") ==
        headers_of("<g stroke='blue'>" + rect("") + "</g>"));
  CHECK(headers_of("<g fill='red'>" + rect("style='fill: green; fill: initial'") + "</g>") ==
        headers_of(rect("")));
  CHECK(headers_of("<g fill='red'>" + rect("style='fill: initial; fill: green'") + "</g>") ==
        headers_of(rect("fill='green'")));
  // A non-inherited property: initial is its default.
  CHECK(headers_of(rect("opacity='initial'")) == headers_of(rect("")));
}

TEST_CASE("css: !important inside one style attribute beats the block's later declarations", "[svg][css]") {
  CHECK(headers_of(rect("style='fill: red !important; fill: blue'")) == headers_of(rect("fill='red'")));
  CHECK(headers_of(rect("style='fill: red; fill: blue'")) == headers_of(rect("fill='blue'")));
}

TEST_CASE("css: marker and font declarations become their longhands in place", "[svg][css]") {
  using mpvg::svg::detail::parse_declarations;
  const auto d = parse_declarations(
      "marker-start: url(#a); marker: none !important; font: italic bold 12px/1.5 'A B', serif");
  std::vector<std::string> got;
  for (const auto& x : d) got.push_back(x.name + "=" + x.value + (x.important ? "!" : ""));
  CHECK(got == std::vector<std::string>{"marker-start=url(#a)", "marker-start=none!", "marker-mid=none!",
                                        "marker-end=none!", "font-style=italic", "font-variant=normal",
                                        "font-weight=bold", "font-stretch=normal", "font-size=12px",
                                        "line-height=1.5", "font-family='A B', serif", "font-size-adjust=none",
                                        "font-kerning=auto"});
  // An invalid shorthand sets nothing; a CSS-wide keyword goes to every longhand.
  CHECK(parse_declarations("font: 12px; font: bold bold 12px serif; font: caption; font: 12px 'open").empty());
  const auto inherit = parse_declarations("font: inherit");
  REQUIRE(inherit.size() == 9);
  for (const auto& x : inherit) CHECK(x.value == "inherit");
}

TEST_CASE("css: the font shorthand's grammar", "[svg][css]") {
  using mpvg::svg::detail::split_font_shorthand;
  auto size_and_family = [](const char* v) -> std::string {
    const auto l = split_font_shorthand(v);
    if (!l) return "invalid";
    std::string out;
    for (const auto& [n, x] : *l)
      if (n != "font-size-adjust" && n != "font-kerning" && x != "normal") out += n + ":" + x + " ";
    return out;
  };
  CHECK(size_and_family("12px serif") == "font-size:12px font-family:serif ");
  CHECK(size_and_family("700 small-caps condensed oblique 10deg calc(1em + 2px) / 20px A, \"B C\"") ==
        "font-style:oblique 10deg font-variant:small-caps font-weight:700 font-stretch:condensed "
        "font-size:calc(1em + 2px) line-height:20px font-family:A, \"B C\" ");
  CHECK(size_and_family("normal normal 0 serif") == "font-size:0 font-family:serif ");  // 0 is a size, not a weight
  CHECK(size_and_family("larger serif") == "font-size:larger font-family:serif ");
  CHECK(size_and_family("12px/ serif") == "invalid");
  CHECK(size_and_family("12px ,serif") == "invalid");
  CHECK(size_and_family("normal normal normal normal normal 12px serif") == "invalid");
  CHECK(size_and_family("italic italic 12px serif") == "invalid");
  CHECK(size_and_family("-2px serif") == "invalid");
}

TEST_CASE("css: longhands and shorthands in cascade order", "[svg][css]") {
  // A sheet's font beats the font-size attribute; in one block the later
  // of shorthand and longhand wins. Sizes show as a 1em wide rect.
  CHECK(dump_of("<style>.f { font: 40px serif }</style><rect class='f' font-size='10' width='1em' height='1'/>") ==
        dump_of("<rect width='40' height='1'/>"));
  CHECK(dump_of("<rect style='font-size: 10px; font: 30px serif' width='1em' height='1'/>") ==
        dump_of("<rect width='30' height='1'/>"));
  CHECK(dump_of("<rect style='font: 30px serif; font-size: 10px' width='1em' height='1'/>") ==
        dump_of("<rect width='10' height='1'/>"));
  CHECK(dump_of("<g font-size='20'><rect style='font: initial' font-size='10' width='1em' height='1'/></g>") ==
        dump_of("<rect width='16' height='1'/>"));
  // The marker shorthand from a sheet beats a marker-start attribute; a
  // later shorthand beats an earlier longhand in one block.
  const std::string m =
      "<marker id='m' markerWidth='1' markerHeight='1' overflow='visible'><rect width='1' height='1'/></marker>";
  CHECK(headers_of(m + "<style>.n { marker: none }</style><path d='M 0 0 H 5' marker-start='url(#m)' class='n'/>") ==
        headers_of(m + "<path d='M 0 0 H 5'/>"));
  CHECK(headers_of(m + "<path d='M 0 0 H 5' style='marker-start: url(#m); marker: none'/>") ==
        headers_of(m + "<path d='M 0 0 H 5'/>"));
}

TEST_CASE("css: unset and revert: inherited properties inherit, the others take their initial value",
          "[svg][css]") {
  CHECK(headers_of("<g fill='red'>" + rect("fill='blue' style='fill: unset'") + "</g>") ==
        headers_of("<g fill='red'>" + rect("") + "</g>"));
  CHECK(headers_of("<g fill='red'>" + rect("style='fill: blue; fill: revert'") + "</g>") ==
        headers_of("<g fill='red'>" + rect("") + "</g>"));
  CHECK(headers_of(rect("opacity='0.5' style='opacity: unset'") + rect("")) == headers_of(rect("") + rect("")));
  // inherit on a property that is not inherited takes the parent's value.
  CHECK(dump_of("<g transform='translate(5 0)'>" + rect("style='transform: inherit'") + "</g>") ==
        dump_of("<g transform='translate(5 0)'>" + rect("transform='translate(5 0)'") + "</g>"));
}

TEST_CASE("css: attributes of properties that are no presentation attributes are ignored", "[svg][css]") {
  CHECK(headers_of("<g isolation='isolate'>" + rect("style='mix-blend-mode: screen'") + "</g>") ==
        headers_of("<g>" + rect("style='mix-blend-mode: screen'") + "</g>"));
  CHECK(dump_of(rect("transform='scale(2)' transform-origin='center' transform-box='fill-box'")) ==
        dump_of(rect("transform='scale(2)' transform-origin='center'")));
  CHECK(dump_of(rect("transform='scale(2)' transform-origin='center' style='transform-box: fill-box'")) !=
        dump_of(rect("transform='scale(2)' transform-origin='center'")));
  CHECK(warnings_of(rect("mask-image='url(#m)' inline-size='10' shape-inside='url(#r)'")).empty());
}

TEST_CASE("css: invalid values are dropped and the cascade falls back", "[svg][css]") {
  // A display, mask, overflow, mask-type or size that is no valid value
  // leaves the one below it in force.
  CHECK(headers_of(rect("display='none' style='display: nonsense'")) == headers_of(rect("display='none'")));
  CHECK(headers_of("<mask id='m'><rect width='5' height='5' fill='white'/></mask>" +
                   rect("mask='url(#m)' style='mask: nonsense'")) ==
        headers_of("<mask id='m'><rect width='5' height='5' fill='white'/></mask>" + rect("mask='url(#m)'")));
  CHECK(headers_of("<svg width='5' height='5' overflow='visible' style='overflow: nonsense'>" + rect("") + "</svg>") ==
        headers_of("<svg width='5' height='5' overflow='visible'>" + rect("") + "</svg>"));
  CHECK(headers_of("<mask id='m' mask-type='alpha' style='mask-type: opacity'/>" + rect("mask='url(#m)'")) ==
        headers_of("<mask id='m' mask-type='alpha'/>" + rect("mask='url(#m)'")));
  CHECK(dump_of("<rect width='10' height='10' style='width: -5px'/>") == dump_of(rect("")));
  CHECK(dump_of(rect("transform-origin='5 5' transform='scale(2)' style='transform-origin: left nonsense'")) ==
        dump_of(rect("transform-origin='5 5' transform='scale(2)'")));
}

TEST_CASE("css: one warning per unsupported property, wherever it is declared", "[svg][css]") {
  // Attribute, style attribute and sheet, on several elements: one
  // warning, naming the property.
  CHECK(warnings_of("<style>.s { direction: rtl; shape-inside: url(#r) }</style>"
                    "<g direction='rtl'>" + rect("class='s'") + rect("style='direction: rtl; shape-inside: auto'") +
                    "</g>") ==
        std::vector<std::string>{"property 'direction' is not supported: ignored",
                                 "property 'shape-inside' is not supported: ignored"});
  // Values that change nothing, properties without effect on a static
  // drawing or without shape-inside or mask images, CSS-wide keywords,
  // and the supported values of a partly supported property: silent.
  CHECK(warnings_of(rect("direction='ltr' unicode-bidi='normal' clip='auto' glyph-orientation-vertical='auto' "
                         "cursor='pointer' pointer-events='none' color-rendering='optimizeSpeed' "
                         "vector-effect='non-scaling-stroke' writing-mode='tb' white-space='pre' "
                         "text-overflow='ellipsis' font-variant='small-caps' text-decoration='underline' "
                         "style='inline-size: 0; shape-inside: auto; line-height: 2; shape-margin: 4px; "
                         "shape-subtract: url(#x); mask-image: none; mask-mode: match-source; mask-size: 10px; "
                         "mask-border: none; font-variant-ligatures: normal; text-decoration-line: none; "
                         "text-decoration-style: solid; text-decoration-color: red; direction: inherit'"))
            .empty());
  // A partly supported property names the value.
  CHECK(warnings_of(rect("vector-effect='non-scaling-stroke non-rotation'") +
                    rect("style='vector-effect: non-rotation'")) ==
        std::vector<std::string>{"property 'vector-effect' value 'non-rotation' is not supported: ignored"});
  CHECK(warnings_of(rect("style='mask-image: url(#m); mask-mode: alpha; text-decoration-line: underline'")) ==
        std::vector<std::string>{"property 'mask-image' is not supported: ignored",
                                 "property 'mask-mode' is not supported: ignored",
                                 "property 'text-decoration-line' is not supported: ignored"});
}

namespace {

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu";

// The dump of text drawn with DejaVu Sans 20px (or its other faces).
std::string text_dump(const std::string& body, std::vector<std::string>* warnings = nullptr) {
  mpvg::svg::ParseOptions o;
  o.font_dirs = {kDejaVu};
  o.system_fonts = false;
  const auto r = mpvg::svg::parse_svg_string(
      svg_test::document(body, "width='200' height='100' font-family='DejaVu Sans' font-size='20'"), ".", o);
  if (warnings) *warnings = r.warnings;
  return mpvg::dump(r.scene);
}

}  // namespace

TEST_CASE("css: text properties from attributes, style attributes and sheets", "[svg][css][text]") {
  if (!std::filesystem::exists(std::string(kDejaVu) + "/DejaVuSans.ttf")) {
    WARN("skipped: DejaVu Sans is not installed (Debian package fonts-dejavu-core)");
    return;
  }
  // font-variant is left out: small-caps uses the font's smcp feature,
  // which DejaVu Sans has not.
  struct Case {
    const char* name;
    const char* value;
    const char* initial;  // the initial value, spelt out
    const char* text;
    bool presentation;  // a presentation attribute
    // A parent's value alone draws the child as its own would: inherited
    // properties, text-decoration (drawn across the descendants) and
    // alignment-baseline (mpvg aligns a span by its parent's too).
    bool like_own;
    bool on_text;  // applies to text elements, not spans (chunks, layout)
  };
  const Case cases[] = {
      {"font-family", "DejaVu Serif", "serif", "Hg", true, true, false},
      {"font-weight", "bold", "normal", "Hg", true, true, false},
      {"font-style", "italic", "normal", "Hg", true, true, false},
      {"font-stretch", "condensed", "normal", "Hg", true, true, false},
      {"font-size-adjust", "0.7", "none", "x", true, true, false},
      {"font-kerning", "none", "auto", "AVAV", false, true, false},
      {"font-feature-settings", "\"liga\" 0", "normal", "fi ffl", false, true, false},
      {"letter-spacing", "5", "normal", "ab", true, true, false},
      {"word-spacing", "10", "normal", "a b", true, true, false},
      {"text-anchor", "middle", "start", "ab", true, true, true},
      {"dominant-baseline", "hanging", "auto", "ab", true, true, false},
      {"writing-mode", "vertical-rl", "horizontal-tb", "ab", true, true, true},
      {"text-rendering", "optimizeSpeed", "auto", "ab", true, true, false},
      {"white-space", "pre", "normal", "a  b", true, true, false},
      {"text-decoration", "underline", "none", "ab", true, true, false},
      {"baseline-shift", "super", "baseline", "ab", true, false, false},
      {"alignment-baseline", "hanging", "auto", "ab", true, true, false},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    const std::string n = c.name, v = c.value;
    // The property is tried on the inner tspan of a text "H<tspan
    // outer><tspan class='t' inner>T</tspan></tspan>" (on_text: on the text
    // in "<g outer><text class='t' inner>T</text></g>"); the sheet's rule
    // is .t { n: sheet }.
    auto doc = [&](const std::string& inner, const std::string& outer = "", const std::string& sheet = "") {
      const std::string rule = sheet.empty() ? "" : "<style>.t { " + n + ": " + sheet + " }</style>";
      if (c.on_text)
        return rule + "<g " + outer + "><text x='100' y='50' class='t' " + inner + ">" + c.text + "</text></g>";
      return rule + "<text x='10' y='50'>H<tspan " + outer + "><tspan class='t' " + inner + ">" + c.text +
             "</tspan></tspan></text>";
    };
    auto style = [&](const std::string& value) { return "style='" + n + ": " + value + "'"; };
    std::vector<std::string> w;
    const std::string plain = text_dump(doc("")), own = text_dump(doc(style(v)), &w);
    CHECK(w.empty());
    CHECK(own != plain);  // the value shows
    CHECK(text_dump(doc("", "", v)) == own);                                          // a sheet
    CHECK(text_dump(doc(n + "='" + v + "'")) == (c.presentation ? own : plain));     // the attribute
    CHECK(text_dump(doc(style("initial"), "", v + " !important")) == own);            // !important over style
    CHECK(text_dump(doc(style("initial"), "", v)) == text_dump(doc(style(c.initial))));  // style over sheet
    CHECK(text_dump(doc("style='" + n + ": " + v + "; " + n + ": 1 2 3 nonsense'")) == own);  // invalid: dropped
    // Inheritance: none of its own, inherit and unset under a parent with the value.
    const std::string both = text_dump(doc(style(v), style(v))), parent_only = text_dump(doc("", style(v)));
    CHECK((parent_only == both) == c.like_own);
    CHECK(text_dump(doc(style("inherit"), style(v))) == both);
    CHECK(text_dump(doc(style("unset"), style(v))) == parent_only);
  }
}
