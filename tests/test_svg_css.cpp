// CSS style sheets (parsers/svg/svg_css.cpp): each case's scene dump equals
// the dump of the same document styled by presentation attributes alone,
// i.e. the cascade picked the declarations the comment says.
#include <string>

#include "parsers/svg/svg_parser.h"
#include "tests/catch.h"
#include "tests/svg_test_util.h"

namespace {

std::string headers_of(const std::string& body) {
  return svg_test::without_geometry(mpvg::dump(mpvg::svg::parse_svg_string(svg_test::document(body)).scene));
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
