// COLR v1 colour glyphs (text/color_glyph.h) against their paint graphs
// drawn directly: each glyph of testdata/fonts/MpvgTestColrV1.ttf (made by
// scripts/make-test-font.py, colr_v1_font()) is rendered on the CPU from
// color_glyph_scene and from a scene built here with SceneBuilder out of the
// numbers the script writes, following the COLR spec's definitions (the
// linear gradient's projected p3, the colour line's span moved to [0, 1],
// stops interpolated with premultiplied alpha, here by dense sampling).
// Composites are checked against the Porter-Duff and W3C blend formulas,
// region by region.
//
// Debian 12's libfreetype6 (2.12.1+dfsg-5+deb12u3 and later) ships
// FreeType's COLR v1 API disabled: there every test that needs a paint
// graph says SKIPPED and passes without checking; they run against an
// upstream FreeType 2.12.1 built as a shared library, e.g.
//   LD_LIBRARY_PATH=/path/to/freetype-2.12.1/build ./test_color_glyph
//
// Tolerances (8-bit channels): 1 for solid fills and transforms, 2 for
// gradients (float evaluation, the lowering's adaptive premultiplied stops
// against 64 samples a segment here), 2 for composites (blend formulas in
// doubles here, in floats in core).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "frame/frame.h"
#include "core/scene.h"
#include "tests/catch.h"
#include "text/color_glyph.h"
#include "text/text.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

using namespace mpvg;
namespace tx = mpvg::text;

namespace {

const std::string kFontDir = std::string(MPVG_SOURCE_DIR) + "/testdata/fonts/";

// colr_v1_font()'s COLR_PALETTE.
const int kPalette[7][4] = {
    {204, 26, 26, 255}, {255, 200, 0, 255}, {0, 90, 220, 255}, {20, 180, 60, 255},
    {200, 60, 160, 204}, {30, 200, 220, 255}, {120, 60, 20, 128},
};

// Rendering: 100 user units per em (0.1 per font unit) into 160 x 160
// pixels, the pen at (30, 110): font units [-300, 1300] x [-500, 1100] are
// seen, and multiples of 10 units fall on pixel edges.
constexpr double kSize = 100;
constexpr double kK = kSize / 1000;
constexpr int kPixels = 160;
const Affine kView = Affine::translate(30, 110);
const Affine kFont{kK, 0, 0, -kK, 0, 0};  // font units, y up, to user units

RGBA pal(int i, double alpha = 1) {
  const int* c = kPalette[i];
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, static_cast<float>(c[3] / 255.0 * alpha)};
}

std::vector<uint8_t> render(const Scene& s) {
  RenderOptions o;
  o.width = o.height = kPixels;
  o.view = kView;
  o.backend = Backend::Cpu;
  return to_rgba8(render_cpu(s, o), o.gamma);
}

// The largest channel difference, with where it is.
int max_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, std::string* where = nullptr) {
  int d = 0;
  for (size_t i = 0; i < a.size(); i++) {
    const int e = std::abs(int(a[i]) - int(b[i]));
    if (e > d) {
      d = e;
      if (where) {
        const size_t px = i / 4;
        *where = "pixel (" + std::to_string(px % kPixels) + ", " + std::to_string(px / kPixels) + ") channel " +
                 std::to_string(i % 4) + ": " + std::to_string(a[i]) + " vs " + std::to_string(b[i]);
      }
    }
  }
  return d;
}

bool blank(const std::vector<uint8_t>& im) {
  return std::all_of(im.begin(), im.end(), [](uint8_t v) { return v == 0; });
}

struct Font {
  tx::FontDb db;
  int face = 0;
  Font() { REQUIRE(db.add_file(kFontDir + "MpvgTestColrV1.ttf") == 1); }
  uint32_t glyph(char32_t c) const {
    std::string u;  // UTF-8 of a BMP code point
    u += static_cast<char>(0xE0 | (c >> 12));
    u += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    u += static_cast<char>(0x80 | (c & 0x3F));
    if (c < 0x80) u = std::string(1, static_cast<char>(c));
    const std::vector<tx::ShapedGlyph> g = tx::shape(db, face, u, 1);
    REQUIRE(g.size() == 1);
    REQUIRE(g[0].glyph != 0);
    return g[0].glyph;
  }
  // Whether this FreeType's COLR v1 API answers; if not, says SKIPPED.
  bool api() const {
    std::vector<std::string> w;
    if (scene(0xE100, &w)) return true;
    WARN("SKIPPED: this FreeType's COLR v1 API gives no paint graph (Debian 12's libfreetype6 disables it): "
         << (w.empty() ? std::string("no warning") : w[0]));
    return false;
  }
  std::shared_ptr<const Scene> scene(char32_t c, std::vector<std::string>* warnings = nullptr,
                                     RGBA foreground = {0, 0, 0, 1}) const {
    tx::ColorGlyphOptions o;
    o.size = kSize;
    o.foreground = foreground;
    return tx::color_glyph_scene(db, face, glyph(c), o, warnings);
  }
};

// ---------------------------------------------------------- references

Path rect(double x0, double y0, double x1, double y1) { return Path::rectangle(x0, y0, x1, y1); }
Path tri() {  // the script's "tri"
  Path p;
  p.move_to({100, 0});
  p.line_to({500, 800});
  p.line_to({900, 0});
  p.close();
  return p;
}
const Path kStrip[3] = {rect(50, 0, 330, 800), rect(360, 0, 640, 800), rect(670, 0, 950, 800)};
const Path kBox = rect(100, 0, 900, 800), kBar = rect(100, 300, 900, 500), kSq = rect(0, 0, 200, 200);
const Path kRectA = rect(100, 100, 600, 600), kRectB = rect(400, 200, 900, 700);
const Path kEverywhere = rect(-5000, -5000, 5000, 5000);

Paint solid(RGBA c) {
  Paint p;
  p.color = c;
  return p;
}

// A scene in font units: each fill's transform is kFont * m.
struct Ref {
  SceneBuilder b{kSize, kSize};
  void fill(const Path& p, const Paint& paint, const Affine& m = {}, FillRule rule = FillRule::NonZero) {
    b.fill(b.add_geometry(p), kFont * m, rule, paint);
  }
  void clip(const Path& p, const Affine& m = {}) {
    b.push();
    b.clip(b.add_geometry(p), kFont * m, FillRule::NonZero);
    b.activate();
  }
  std::vector<uint8_t> pixels() { return render(b.finish()); }
};

struct Stop {
  double offset;
  int pal;
  double alpha;
};

// A COLR colour line as core stops: offsets from [s0, s1] (their span) to
// [0, 1]; between stops, 64 straight pieces of the premultiplied
// interpolation (exact at their ends).
std::vector<ColorStop> ramp(const std::vector<Stop>& st, double& s0, double& s1) {
  s0 = st.front().offset;
  s1 = st.back().offset;
  std::vector<ColorStop> out;
  for (size_t i = 0; i + 1 < st.size(); i++) {
    const RGBA a = pal(st[i].pal, st[i].alpha), b = pal(st[i + 1].pal, st[i + 1].alpha);
    for (int j = 0; j <= 64; j++) {
      const double s = j / 64.0;
      const double al = a.a + s * (b.a - a.a);
      auto ch = [&](double x, double y) { return float((a.a * x * (1 - s) + b.a * y * s) / al); };
      const double off = st[i].offset + s * (st[i + 1].offset - st[i].offset);
      out.push_back({(off - s0) / (s1 - s0), RGBA{ch(a.r, b.r), ch(a.g, b.g), ch(a.b, b.b), float(al)}});
    }
  }
  return out;
}

Spread spread(const char* e) {
  return std::string(e) == "repeat" ? Spread::Repeat : std::string(e) == "reflect" ? Spread::Reflect : Spread::Pad;
}

// PaintLinearGradient: the colour at q is the colour line's at the t where
// the line through q parallel to p0p2 meets p0p1; as a two-point gradient,
// from p0 to p3 = p0 + the part of p1 - p0 across p0p2.
Paint linear(Ref& r, const Affine& m, const char* extend, const std::vector<Stop>& st, Vec2 p0, Vec2 p1, Vec2 p2) {
  Gradient g;
  double s0, s1;
  g.stops = ramp(st, s0, s1);
  g.spread = spread(extend);
  const Vec2 u = p2 - p0;
  const Vec2 d = p1 - p0;
  const Vec2 along = (dot(d, u) / dot(u, u)) * u;  // the part of d along p0p2, which does not change t
  const Vec2 p3 = p0 + (d - along);
  g.p0 = lerp(p0, p3, s0);
  g.p1 = lerp(p0, p3, s1);
  g.xf = kFont * m;
  Paint p;
  p.type = PaintType::LinearGradient;
  p.index = r.b.add_gradient(g);
  return p;
}

Paint radial(Ref& r, const char* extend, const std::vector<Stop>& st, Vec2 c0, double r0, Vec2 c1, double r1) {
  Gradient g;
  double s0, s1;
  g.stops = ramp(st, s0, s1);
  g.spread = spread(extend);
  g.focal = lerp(c0, c1, s0);
  g.center = lerp(c0, c1, s1);
  g.focal_radius = r0 + s0 * (r1 - r0);
  g.radius = r0 + s1 * (r1 - r0);
  g.xf = kFont;
  Paint p;
  p.type = PaintType::RadialGradient;
  p.index = r.b.add_gradient(g);
  return p;
}

// Angles counter-clockwise from +x in font space (y up): core's sweep
// measures from +x towards +y of gradient space, which is font space.
Paint sweep(Ref& r, const char* extend, const std::vector<Stop>& st, Vec2 c, double start, double end) {
  Gradient g;
  double s0, s1;
  g.stops = ramp(st, s0, s1);
  g.spread = spread(extend);
  g.center = c;
  g.start_angle = start + s0 * (end - start);
  g.end_angle = start + s1 * (end - start);
  g.xf = kFont;
  Paint p;
  p.type = PaintType::SweepGradient;
  p.index = r.b.add_gradient(g);
  return p;
}

void check(const Font& font, char32_t c, Ref& ref, int tolerance, RGBA foreground = {0, 0, 0, 1}) {
  std::vector<std::string> warnings;
  const std::shared_ptr<const Scene> s = font.scene(c, &warnings, foreground);
  REQUIRE(s);
  for (const std::string& w : warnings) UNSCOPED_INFO(w);
  CHECK(warnings.empty());
  const std::vector<uint8_t> got = render(*s), want = ref.pixels();
  REQUIRE(!blank(want));
  std::string where;
  const int d = max_difference(got, want, &where);
  INFO("largest difference at " << where);
  CHECK(d <= tolerance);
}

Affine about(const Affine& t, double cx, double cy) {
  return Affine::translate(cx, cy) * t * Affine::translate(-cx, -cy);
}

// c_solid's drawing, under m.
void draw_c_solid(Ref& r, const Affine& m, RGBA foreground) {
  r.fill(kBox, solid(pal(0)), m);
  foreground.a *= 0.5f;
  r.fill(kBar, solid(foreground), m);
}

// c_clip's drawing: box, tri, a bare solid over everything, in its clip box.
void draw_c_clip(Ref& r) {
  r.clip(rect(200, 100, 800, 600));
  r.fill(kBox, solid(pal(1)));
  r.fill(tri(), solid(pal(2)));
  r.fill(kEverywhere, solid(pal(6)));
  r.b.pop();
}

}  // namespace

TEST_CASE("colr v1: solid paints, palette and foreground", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  for (RGBA fg : {RGBA{0, 0, 0, 1}, RGBA{0.2f, 0.6f, 0.9f, 0.8f}}) {
    Ref r;
    draw_c_solid(r, {}, fg);
    check(font, 0xE100, r, 1, fg);
  }
  // The foreground shows: two colours, two images.
  const std::shared_ptr<const Scene> a = font.scene(0xE100, nullptr, {1, 0, 0, 1});
  const std::shared_ptr<const Scene> b = font.scene(0xE100, nullptr, {0, 0, 1, 1});
  CHECK(max_difference(render(*a), render(*b)) > 100);
  // No clip box: the scene is the outlines' box, 800 x 800 units.
  CHECK(a->width == Approx(80));
  CHECK(a->height == Approx(80));
}

TEST_CASE("colr v1: linear gradients, pad / repeat / reflect", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  r.fill(kStrip[0], linear(r, {}, "pad", {{0, 1, 1}, {1, 2, 1}}, {100, 200}, {280, 600}, {300, 100}));
  r.fill(kStrip[1], linear(r, {}, "repeat", {{0.125, 1, 1}, {0.5, 3, 0.5}, {0.875, 2, 1}}, {400, 300}, {600, 300},
                           {450, 500}));
  r.fill(kStrip[2], linear(r, {}, "reflect", {{0.25, 2, 1}, {0.5, 0, 0.25}}, {700, 100}, {920, 700}, {700, 700}));
  check(font, 0xE101, r, 2);
}

TEST_CASE("colr v1: radial gradients, pad / repeat / reflect", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  r.fill(kStrip[0], radial(r, "pad", {{0, 1, 1}, {1, 2, 1}}, {190, 400}, 20, {190, 400}, 130));
  r.fill(kStrip[1], radial(r, "repeat", {{0, 1, 1}, {0.5, 3, 1}, {1, 2, 0.5}}, {450, 300}, 0, {500, 450}, 100));
  r.fill(kStrip[2], radial(r, "reflect", {{0, 5, 1}, {1, 6, 1}}, {700, 200}, 30, {900, 600}, 80));
  check(font, 0xE102, r, 2);
}

TEST_CASE("colr v1: sweep gradients, pad / repeat / reflect", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  r.fill(kStrip[0], sweep(r, "pad", {{0, 1, 1}, {1, 2, 1}}, {190, 400}, 45, 135));
  r.fill(kStrip[1], sweep(r, "repeat", {{0, 1, 1}, {0.5, 3, 0.5}, {1, 2, 1}}, {500, 400}, 0, 90));
  r.fill(kStrip[2], sweep(r, "reflect", {{0.25, 5, 1}, {0.75, 0, 1}}, {810, 400}, 270, 180));
  check(font, 0xE103, r, 2);
}

TEST_CASE("colr v1: PaintGlyph of a transformed gradient, and clipping layers", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  // The gradient moves with the translation; the outline does not.
  r.fill(tri(), linear(r, Affine::translate(100, 0), "pad", {{0, 1, 1}, {1, 2, 1}}, {0, 0}, {800, 0}, {0, 800}));
  r.clip(kBar);
  r.fill(kEverywhere, solid(pal(3, 0.75)));
  r.fill(kRectA, solid(pal(4)));
  r.b.pop();
  check(font, 0xE104, r, 2);
}

TEST_CASE("colr v1: PaintColrGlyph inline, with the referenced clip box", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  draw_c_solid(r, about(Affine::scale(0.5, 0.75), 500, 400), {0, 0, 0, 1});
  draw_c_clip(r);
  check(font, 0xE105, r, 1);
}

TEST_CASE("colr v1: every transform format", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  const double t225 = std::tan(22.5 * M_PI / 180), t1125 = std::tan(11.25 * M_PI / 180),
               t3375 = std::tan(-33.75 * M_PI / 180);
  // x' = xx x + xy y + dx, y' = yx x + yy y + dy.
  r.fill(kSq, solid(pal(0, 0.75)), Affine{1, 0.25, 0.5, 1, 50, 550});
  r.fill(kSq, solid(pal(1, 0.75)), Affine::translate(300, 550));
  r.fill(kSq, solid(pal(2, 0.75)), Affine::scale(1.5, 0.5));
  r.fill(kSq, solid(pal(3, 0.75)), about(Affine::scale(0.5, 1.25), 600, 100));
  r.fill(kSq, solid(pal(4)), Affine::scale(0.75, 0.75));
  r.fill(kSq, solid(pal(5, 0.75)), about(Affine::scale(1.25, 1.25), 1000, 0));
  // Counter-clockwise in font space.
  const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
  r.fill(kSq, solid(pal(6)), Affine{c, s, -s, c, 0, 0});
  const double c2 = std::cos(-M_PI / 8), s2 = std::sin(-M_PI / 8);
  r.fill(kSq, solid(pal(0, 0.5)), Affine::translate(600, 500) * about(Affine{c2, s2, -s2, c2, 0, 0}, 100, 100));
  // The spec's skew matrix: xy = -tan(x angle), yx = tan(y angle).
  r.fill(kSq, solid(pal(1)), Affine::translate(700, 0) * Affine{1, 0, -t225, 1, 0, 0});
  r.fill(kSq, solid(pal(2, 0.75)), Affine::translate(400, 300) * about(Affine{1, t3375, -t1125, 1, 0, 0}, 100, 100));
  check(font, 0xE106, r, 1);
}

TEST_CASE("colr v1: the clip box clips everything, a bare paint fills it", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  Ref r;
  draw_c_clip(r);
  check(font, 0xE107, r, 1);
  const std::shared_ptr<const Scene> s = font.scene(0xE107);
  CHECK(s->width == Approx(60));
  CHECK(s->height == Approx(50));
}

TEST_CASE("colr v1: a PaintColrGlyph cycle is cut with a warning", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  std::vector<std::string> warnings;
  const std::shared_ptr<const Scene> s = font.scene(0xE108, &warnings);
  REQUIRE(s);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("cycle") != std::string::npos);
  Ref r;
  r.fill(kBox, solid(pal(1)));
  CHECK(max_difference(render(*s), r.pixels()) <= 1);
}

TEST_CASE("colr v1: composites nested past the group limit warn and draw", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  std::vector<std::string> warnings;
  const std::shared_ptr<const Scene> s = font.scene(0xE109, &warnings);
  REQUIRE(s);
  REQUIRE(!warnings.empty());
  CHECK(warnings[0].find("groups") != std::string::npos);
  CHECK(!blank(render(*s)));
  // No group nests deeper than the limit.
  int depth = 0, deepest = 0;
  for (const Element& e : s->stream) {
    if (e.kind == ElementKind::BeginGroup) deepest = std::max(deepest, ++depth);
    if (e.kind == ElementKind::EndGroup) depth--;
  }
  CHECK(deepest <= tx::kMaxColorGlyphGroups);
  CHECK(deepest >= tx::kMaxColorGlyphGroups - 1);  // what fits is drawn
}

TEST_CASE("colr v1: paints FreeType cannot read are skipped with a warning", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  std::vector<std::string> warnings;
  const std::shared_ptr<const Scene> s = font.scene(0xE10A, &warnings);
  REQUIRE(s);
  Ref r;
  r.fill(kBox, solid(pal(1)));
  if (!warnings.empty()) {  // FreeType 2.12: PaintVarSolid (format 3) unsupported
    CHECK(warnings.size() == 1);
    CHECK(warnings[0].find("paint format 3 unsupported") != std::string::npos);
  } else {  // FreeType 2.13 reads it
    r.fill(kBar, solid(pal(2)));
  }
  CHECK(max_difference(render(*s), r.pixels()) <= 1);
}

TEST_CASE("colr v1: no scene for glyphs without a COLR v1 paint", "[text][colr]") {
  Font font;
  tx::ColorGlyphOptions o;
  o.size = kSize;
  // A COLR version 0 glyph (its layers are color_layers's), a plain glyph.
  std::vector<std::string> warnings;
  CHECK(tx::color_glyph_scene(font.db, 0, font.glyph(0xE10B), o, &warnings) == nullptr);
  // Without the API (Debian's FreeType) the miss says why.
  CHECK(warnings.size() == (font.api() ? 0u : 1u));
  CHECK(tx::color_layers(font.db, 0, font.glyph(0xE10B)).size() == 2);
  CHECK(tx::color_glyph_scene(font.db, 0, font.glyph(' '), o) == nullptr);
  // A font without COLR.
  tx::FontDb other;
  REQUIRE(other.add_file(kFontDir + "MpvgTestVF.ttf") == 1);
  CHECK(tx::color_glyph_scene(other, 0, 3, o) == nullptr);
  if (!font.api()) return;
  // Variation settings on a face without axes change nothing.
  o.variations = {{"wght", 700}};
  const std::shared_ptr<const Scene> v = tx::color_glyph_scene(font.db, 0, font.glyph(0xE100), o);
  REQUIRE(v);
  CHECK(max_difference(render(*v), render(*font.scene(0xE100))) == 0);
}

namespace {

// W3C Compositing 1: separable blend functions B(cb, cs) ...
double blend_channel(const std::string& m, double cb, double cs) {
  auto multiply = [](double b, double s) { return b * s; };
  auto screen = [](double b, double s) { return b + s - b * s; };
  auto hard_light = [&](double b, double s) { return s <= 0.5 ? multiply(b, 2 * s) : screen(b, 2 * s - 1); };
  if (m == "multiply") return multiply(cb, cs);
  if (m == "screen") return screen(cb, cs);
  if (m == "overlay") return hard_light(cs, cb);
  if (m == "darken") return std::min(cb, cs);
  if (m == "lighten") return std::max(cb, cs);
  if (m == "color_dodge") return cb == 0 ? 0 : cs >= 1 ? 1 : std::min(1.0, cb / (1 - cs));
  if (m == "color_burn") return cb >= 1 ? 1 : cs <= 0 ? 0 : 1 - std::min(1.0, (1 - cb) / cs);
  if (m == "hard_light") return hard_light(cb, cs);
  if (m == "soft_light") {
    if (cs <= 0.5) return cb - (1 - 2 * cs) * cb * (1 - cb);
    const double d = cb <= 0.25 ? ((16 * cb - 12) * cb + 4) * cb : std::sqrt(cb);
    return cb + (2 * cs - 1) * (d - cb);
  }
  if (m == "difference") return std::fabs(cb - cs);
  if (m == "exclusion") return cb + cs - 2 * cb * cs;
  FAIL("not separable: " << m);
  return 0;
}

// ... and the non-separable ones.
struct C3 {
  double c[3];
};
double lum(const C3& x) { return 0.3 * x.c[0] + 0.59 * x.c[1] + 0.11 * x.c[2]; }
C3 clip_color(C3 x) {
  const double l = lum(x), n = std::min({x.c[0], x.c[1], x.c[2]}), mx = std::max({x.c[0], x.c[1], x.c[2]});
  for (double& v : x.c) {
    if (n < 0) v = l + (v - l) * l / (l - n);
    if (mx > 1) v = l + (v - l) * (1 - l) / (mx - l);
  }
  return x;
}
C3 set_lum(C3 x, double l) {
  const double d = l - lum(x);
  for (double& v : x.c) v += d;
  return clip_color(x);
}
double sat(const C3& x) { return std::max({x.c[0], x.c[1], x.c[2]}) - std::min({x.c[0], x.c[1], x.c[2]}); }
C3 set_sat(C3 x, double s) {
  int i[3] = {0, 1, 2};  // min, mid, max
  std::sort(i, i + 3, [&](int a, int b) { return x.c[a] < x.c[b]; });
  C3 r{{0, 0, 0}};
  if (x.c[i[2]] > x.c[i[0]]) {
    r.c[i[1]] = (x.c[i[1]] - x.c[i[0]]) * s / (x.c[i[2]] - x.c[i[0]]);
    r.c[i[2]] = s;
  }
  return r;
}
C3 blend(const std::string& m, const C3& cb, const C3& cs) {
  if (m == "hsl_hue") return set_lum(set_sat(cs, sat(cb)), lum(cb));
  if (m == "hsl_saturation") return set_lum(set_sat(cb, sat(cs)), lum(cb));
  if (m == "hsl_color") return set_lum(cs, lum(cb));
  if (m == "hsl_luminosity") return set_lum(cb, lum(cs));
  C3 r;
  for (int k = 0; k < 3; k++) r.c[k] = blend_channel(m, cb.c[k], cs.c[k]);
  return r;
}

// The composite of source s over backdrop b (straight colours) with COLR
// mode m, as a straight colour; premultiplied Porter-Duff (Compositing 1
// §9.1) or source-over with blending (§10).
RGBA composite(const std::string& m, RGBA s, RGBA b) {
  const double as = s.a, ab = b.a;
  const C3 cs{{s.r, s.g, s.b}}, cb{{b.r, b.g, b.b}};
  double fa = 0, fb = 0;  // Porter-Duff factors of the source and the backdrop
  bool porter_duff = true, plus = false;
  if (m == "clear") fa = fb = 0;
  else if (m == "src") fa = 1, fb = 0;
  else if (m == "dest") fa = 0, fb = 1;
  else if (m == "src_over") fa = 1, fb = 1 - as;
  else if (m == "dest_over") fa = 1 - ab, fb = 1;
  else if (m == "src_in") fa = ab, fb = 0;
  else if (m == "dest_in") fa = 0, fb = as;
  else if (m == "src_out") fa = 1 - ab, fb = 0;
  else if (m == "dest_out") fa = 0, fb = 1 - as;
  else if (m == "src_atop") fa = ab, fb = 1 - as;
  else if (m == "dest_atop") fa = 1 - ab, fb = as;
  else if (m == "xor") fa = 1 - ab, fb = 1 - as;
  else if (m == "plus") plus = true;
  else porter_duff = false;
  double co[3], ao;
  if (plus) {
    for (int k = 0; k < 3; k++) co[k] = std::min(1.0, cs.c[k] * as + cb.c[k] * ab);
    ao = std::min(1.0, as + ab);
  } else if (porter_duff) {
    for (int k = 0; k < 3; k++) co[k] = fa * as * cs.c[k] + fb * ab * cb.c[k];
    ao = fa * as + fb * ab;
  } else {
    const C3 mix = blend(m, cb, cs);
    for (int k = 0; k < 3; k++) co[k] = as * (1 - ab) * cs.c[k] + ab * (1 - as) * cb.c[k] + as * ab * mix.c[k];
    ao = as + ab - as * ab;
  }
  if (ao <= 0) return {0, 0, 0, 0};
  return {float(co[0] / ao), float(co[1] / ao), float(co[2] / ao), float(ao)};
}

}  // namespace

TEST_CASE("colr v1: every composite mode, region by region", "[text][colr]") {
  Font font;
  if (!font.api()) return;
  // colr_v1_font()'s CompositeMode order: U+E110 + index.
  const char* modes[] = {"clear",     "src",         "dest",       "src_over",   "dest_over",      "src_in",
                         "dest_in",   "src_out",     "dest_out",   "src_atop",   "dest_atop",      "xor",
                         "plus",      "screen",      "overlay",    "darken",     "lighten",        "color_dodge",
                         "color_burn", "hard_light", "soft_light", "difference", "exclusion",      "multiply",
                         "hsl_hue",   "hsl_saturation", "hsl_color", "hsl_luminosity"};
  const RGBA src = pal(5, 0.75), bd = pal(4);
  const RGBA none{0, 0, 0, 0};
  // rectA (backdrop) and rectB (source) overlap in [400, 600] x [200, 600].
  Path a_only = kRectA, b_only = kRectB;
  a_only.append(rect(400, 200, 600, 600));
  b_only.append(rect(400, 200, 600, 600));
  for (size_t i = 0; i < std::size(modes); i++) {
    const std::string m = modes[i];
    INFO("mode " << m);
    std::vector<std::string> warnings;
    const std::shared_ptr<const Scene> s = font.scene(0xE110 + char32_t(i), &warnings);
    REQUIRE(s);
    for (const std::string& w : warnings) UNSCOPED_INFO(w);
    CHECK(warnings.empty());
    Ref r;
    r.fill(a_only, solid(composite(m, none, bd)), {}, FillRule::EvenOdd);
    r.fill(b_only, solid(composite(m, src, none)), {}, FillRule::EvenOdd);
    r.fill(rect(400, 200, 600, 600), solid(composite(m, src, bd)));
    const std::vector<uint8_t> got = render(*s), want = r.pixels();
    std::string where;
    const int d = max_difference(got, want, &where);
    INFO("largest difference at " << where);
    CHECK(d <= 2);
  }
}
