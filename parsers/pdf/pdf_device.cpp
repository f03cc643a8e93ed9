// The lowering device: MuPDF's drawing operations into a SceneBuilder.
//
// MuPDF's rules hold here: no C++ exception leaves a device callback (each
// body runs under catch_all, which records the first error and lets the
// page finish), and no fz_try block jumps over C++ objects with
// destructors (the only fz_try is in Document, around plain calls).
//
// Clip and mask nesting: clip_path / clip_stroke_path push a clip group
// that lasts until pop_clip; begin_mask opens a group and its mask, the
// mask's content follows until end_mask, then the masked content until
// pop_clip closes the group. A stack remembers which one each pop_clip
// closes.
#include <mupdf/fitz.h>
#include <mupdf/pdf.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/paint/mesh_build.h"
#include "stroker/stroke_adjust.h"
#include "parsers/pdf/pdf_device.h"
#include "frame/scene_builder.h"

namespace mpvg::pdf::detail {

namespace {

Affine to_affine(fz_matrix m) { return Affine{m.a, m.b, m.c, m.d, m.e, m.f}; }

// fz_path to Path, in the path's own space.
struct PathBuilder {
  Path p;
  static PathBuilder* of(void* arg) { return static_cast<PathBuilder*>(arg); }
  static void moveto(fz_context*, void* a, float x, float y) { of(a)->p.move_to({x, y}); }
  static void lineto(fz_context*, void* a, float x, float y) { of(a)->p.line_to({x, y}); }
  static void curveto(fz_context*, void* a, float x1, float y1, float x2, float y2, float x3, float y3) {
    of(a)->p.cubic_to({x1, y1}, {x2, y2}, {x3, y3});
  }
  static void quadto(fz_context*, void* a, float x1, float y1, float x2, float y2) {
    of(a)->p.quad_to({x1, y1}, {x2, y2});
  }
  static void closepath(fz_context*, void* a) { of(a)->p.close(); }
};

Path to_path(fz_context* ctx, const fz_path* path) {
  static const fz_path_walker walker = {PathBuilder::moveto,  PathBuilder::lineto, PathBuilder::curveto,
                                        PathBuilder::closepath, PathBuilder::quadto, nullptr,
                                        nullptr,                nullptr};
  PathBuilder b;
  fz_walk_path(ctx, path, &walker, &b);
  return std::move(b.p);
}

// MuPDF calls that may throw, each under its own fz_try, so that no error
// unwinds through a callback's C++ frames.
fz_path* outline_glyph(fz_context* ctx, fz_font* font, int gid, fz_matrix m) {
  fz_path* volatile p = nullptr;
  fz_try(ctx) { p = fz_outline_glyph(ctx, font, gid, m); }
  fz_catch(ctx) { p = nullptr; }
  return p;
}

}  // namespace

GlyphCache::~GlyphCache() {
  for (fz_font* f : fonts_) fz_drop_font(ctx_, f);
}

const Path* GlyphCache::outline(fz_font* font, int gid) {
  auto [it, inserted] = glyphs_.try_emplace({font, gid});
  if (inserted) {
    // A font seen for the first time is kept, so that its address is not
    // reused by another font while the cache holds entries for it.
    if (std::find(fonts_.begin(), fonts_.end(), font) == fonts_.end()) fonts_.push_back(fz_keep_font(ctx_, font));
    if (fz_path* path = outline_glyph(ctx_, font, gid, fz_identity)) {
      it->second = to_path(ctx_, path);
      fz_drop_path(ctx_, path);
    }
  }
  return it->second ? &*it->second : nullptr;
}

namespace {

bool run_t3_glyph(fz_context* ctx, fz_font* font, int gid, fz_matrix trm, fz_device* dev) {
  volatile bool ok = true;
  fz_try(ctx) { fz_run_t3_glyph(ctx, font, gid, trm, dev); }
  fz_catch(ctx) { ok = false; }
  return ok;
}

// cs's colour into RGB (or into `to`: DeviceCMYK for print preview).
bool convert_color(fz_context* ctx, fz_colorspace* cs, const float* color, float* rgb, fz_color_params cp,
                   fz_colorspace* to = nullptr) {
  volatile bool ok = true;
  fz_try(ctx) { fz_convert_color(ctx, cs, color, to ? to : fz_device_rgb(ctx), rgb, nullptr, cp); }
  fz_catch(ctx) { ok = false; }
  return ok;
}

// An image decoded at the resolution it is drawn at and converted to RGB
// with alpha (premultiplied, as MuPDF keeps pixmaps), or for a stencil mask
// its one alpha channel as it is; null on failure. `pixels` maps the image's
// unit square to output pixels: MuPDF subsamples by a power of two while
// decoding, keeping at least a texel per pixel (a 20000 x 20000 image on a
// page 1250 pixels wide is decoded at 2500 x 2500, never held whole).
// (`to`: DeviceCMYK instead of RGB, for print preview.)
fz_pixmap* rgb_pixmap(fz_context* ctx, fz_image* image, fz_color_params cp, fz_matrix pixels,
                      fz_colorspace* to = nullptr) {
  fz_pixmap* volatile decoded = nullptr;
  fz_pixmap* volatile rgb = nullptr;
  fz_try(ctx) {
    decoded = fz_get_pixmap_from_image(ctx, image, nullptr, &pixels, nullptr, nullptr);
    rgb = fz_pixmap_colorspace(ctx, decoded)
              ? fz_convert_pixmap(ctx, decoded, to ? to : fz_device_rgb(ctx), nullptr, nullptr, cp, 1)
              : fz_keep_pixmap(ctx, decoded);
  }
  fz_always(ctx) { fz_drop_pixmap(ctx, decoded); }
  fz_catch(ctx) { rgb = nullptr; }
  return rgb;
}

// Is cs RGB-based: RGB, BGR or Lab, or an indexed or Separation/DeviceN
// space over one (colours an output profile converts)?
bool rgb_based(fz_context* ctx, fz_colorspace* cs) {
  for (int depth = 0; cs && depth < 4; depth++) {
    switch (fz_colorspace_type(ctx, cs)) {
      case FZ_COLORSPACE_RGB:
      case FZ_COLORSPACE_BGR:
      case FZ_COLORSPACE_LAB: return true;
      case FZ_COLORSPACE_INDEXED: cs = cs->u.indexed.base; break;
      case FZ_COLORSPACE_SEPARATION: cs = cs->u.separation.base; break;
      default: return false;
    }
  }
  return false;
}

LineCap to_cap(fz_linecap c) {
  switch (c) {
    case FZ_LINECAP_ROUND: return LineCap::Round;
    case FZ_LINECAP_SQUARE: return LineCap::Square;
    default: return LineCap::Butt;  // triangle caps (XPS) come later
  }
}

}  // namespace

struct Lowering {
  fz_device super;  // first: MuPDF's device
  SceneBuilder* b;  // the page's, or the tile's being captured
  // Maps the device space MuPDF draws in (the page's scene units) to b's:
  // the identity, or inside a tile the inverse of the tile's placement.
  Affine adjust;
  Affine device;
  double page_w = 0, page_h = 0;  // scene units  // page points to output pixels (stroke tolerance, thin lines)
  // Thin lines snapped to the pixel grid (ThinLines::Snap): page content's
  // paths and strokes, not glyphs, clips or pattern cells (whose grid is
  // not the page's).
  bool snap = false;
  // What each pop_clip to come closes, innermost last.
  enum Pop : uint8_t { ClipGroup, MaskedGroup };
  std::vector<Pop> pops;
  GlyphCache* glyph_cache;
  std::set<std::string> warned;
  std::vector<std::string>* warnings;
  std::string error;  // the first failure inside a callback

  static Lowering* of(fz_device* d) { return reinterpret_cast<Lowering*>(d); }

  Affine place(fz_matrix m) const { return adjust * to_affine(m); }
  // Maps a placed path's user space (xf = place(ctm)) to output pixels.
  Affine to_pixels(const Affine& xf) const { return device * adjust.inverted() * xf; }
  bool snapping() const { return snap && tiles.empty(); }

  // Tiling patterns being captured, innermost last: each one's tile is a
  // scene of its own, then a pattern paint on the area it covers.
  struct Tile {
    std::unique_ptr<SceneBuilder> builder;  // null: not captured (drawn once)
    SceneBuilder* parent = nullptr;
    Affine parent_adjust, placement;  // placement: tile units to the parent's units
    Affine pattern_space;             // the pattern space to the parent's units
    fz_rect area{};                   // in pattern space
    size_t pops = 0;
    bool clipped = false;
  };
  std::vector<Tile> tiles;

  void warn(const std::string& w) {
    if (warned.insert(w).second) warnings->push_back(w);
  }

  // Runs f, turning any C++ exception into the recorded error, and adds
  // its time to lower_ms (callbacks nest: a Type 3 glyph runs through this
  // device from inside fill_text; only the outermost is timed).
  double lower_ms = 0;
  int nesting = 0;
  template <class F>
  void guarded(F&& f) {
    if (!error.empty()) return;
    const auto t0 = nesting++ == 0 ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    try {
      f();
    } catch (const std::exception& e) {
      error = e.what();
    } catch (...) {
      error = "unknown error";
    }
    if (--nesting == 0)
      lower_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  Paint solid(fz_context* ctx, fz_colorspace* cs, const float* color, float alpha, fz_color_params cp) {
    Paint p;
    p.opacity = alpha;
    if (ink_mode()) {
      to_inks(ctx, cs, color, cp);
      p.color = RGBA{pass_ink(0), pass_ink(1), pass_ink(2), 1};
      return p;
    }
    float rgb[3] = {0, 0, 0};
    if (cs && !convert_color(ctx, cs, color, rgb, cp)) warn("a colour could not be converted: black used");
    p.color = RGBA{rgb[0], rgb[1], rgb[2], 1};
    return p;
  }

  // Print preview (core/inks/inks.h): the page's inks and the pass drawn; null
  // for RGB. Inside a soft mask's content (rgb_depth > 0) colours stay RGB:
  // its luminosity is the mask.
  const InkTarget* inks = nullptr;
  int rgb_depth = 0;
  bool ink_mode() const { return inks && rgb_depth == 0; }
  // The last colour solid() converted, as ink amounts, which inks it paints
  // (all but where it overprints) and whether it overprints at all.
  std::vector<float> ink_values;
  std::vector<bool> painted;
  bool overprints = false;
  float pass_ink(int k) const { return inks->pass.inks[k] >= 0 ? ink_values[inks->pass.inks[k]] : 0.0f; }

  // (cs, color) as ink amounts (PDF 32000-1 §8.6.6, §11.7.4): a Separation
  // or DeviceN colour puts its tints on the inks it names (process names
  // on C, M, Y, K; All on every ink; None on none); a colorant the page's
  // inks lack sends the whole colour through its alternate to CMYK, as do
  // other spaces (DeviceCMYK as it is). With overprint on (cp.op), a
  // colour paints only its own inks (other spaces: the process inks), and
  // with OPM 1 a DeviceCMYK colour only its non-zero components;
  // otherwise it paints every ink (knockout).
  void to_inks(fz_context* ctx, fz_colorspace* cs, const float* color, fz_color_params cp) {
    const size_t n = kProcessInks + inks->spots.size();
    ink_values.assign(n, 0.0f);
    painted.assign(n, true);
    overprints = false;
    if (!cs) return;
    auto process_only = [&] {
      if (cp.op)
        for (size_t i = kProcessInks; i < n; i++) painted[i] = false;
    };
    if (fz_colorspace_is_device_n(ctx, cs)) {
      const int m = fz_colorspace_n(ctx, cs);
      std::vector<int> target(m, -2);  // -1: None
      bool all_known = true;
      for (int i = 0; i < m && all_known; i++) {
        const char* name = fz_colorspace_colorant(ctx, cs, i);
        const std::string s = name ? name : "";
        static const char* process[] = {"Cyan", "Magenta", "Yellow", "Black"};
        for (int k = 0; k < kProcessInks; k++)
          if (s == process[k]) target[i] = k;
        for (size_t k = 0; k < inks->spots.size(); k++)
          if (s == inks->spots[k]) target[i] = static_cast<int>(kProcessInks + k);
        if (s == "All") target[i] = static_cast<int>(n);
        if (s == "None") target[i] = -1;
        all_known = target[i] != -2;
      }
      if (all_known) {
        std::vector<bool> named(n, false);
        for (int i = 0; i < m; i++) {
          const float v = std::clamp(color[i], 0.0f, 1.0f);
          if (target[i] == static_cast<int>(n)) {
            std::fill(ink_values.begin(), ink_values.end(), v);
            std::fill(named.begin(), named.end(), true);
          } else if (target[i] >= 0) {
            ink_values[target[i]] = v;
            named[target[i]] = true;
          }
        }
        if (cp.op) painted = named;
        overprints = cp.op != 0;
        return;
      }
    }
    float cmyk[4] = {0, 0, 0, 0};
    const bool direct = fz_colorspace_type(ctx, cs) == FZ_COLORSPACE_CMYK && !fz_colorspace_is_indexed(ctx, cs);
    float rgb[3];
    if (direct) {
      for (int k = 0; k < 4; k++) cmyk[k] = std::clamp(color[k], 0.0f, 1.0f);
    } else if (inks->profile && rgb_based(ctx, cs) && convert_color(ctx, cs, color, rgb, cp)) {
      inks->profile->rgb_to_cmyk(rgb, cmyk, 1, cp.ri);  // through the press's profile
    } else if (!convert_color(ctx, cs, color, cmyk, cp, fz_device_cmyk(ctx))) {
      warn("a colour could not be converted: black used");
      cmyk[3] = 1;
    }
    for (int k = 0; k < 4; k++) ink_values[k] = cmyk[k];
    process_only();
    // A DeviceCMYK colour under OPM 1, and a Separation or DeviceN colour
    // drawn through its alternate (colorants the page's inks lack), paint
    // only their non-zero process inks, as Ghostscript simulates them.
    if (cp.op && ((cp.opm && direct) || fz_colorspace_is_device_n(ctx, cs)))
      for (int k = 0; k < 4; k++) painted[k] = cmyk[k] != 0.0f;
    overprints = cp.op != 0;
  }

  // Draws what draw() adds with the colour solid() converted last: where
  // it overprints inks of this pass, inside a group that keeps those
  // channels as the backdrop has them (core/inks/inks.h).
  template <class F>
  void painting(F&& draw) {
    Group g;
    if (ink_mode() && overprints && overprint_group(inks->pass, painted, &g)) {
      b->begin_group(g);
      draw();
      b->end_group();
    } else {
      draw();
    }
  }

  // The style of a stroke, placed by ctm. Width 0 is the thinnest visible
  // line: one output pixel. The stroke stage builds the outline when the
  // page is rendered.
  StrokeStyle stroke_style(const fz_stroke_state* s, const Affine& ctm) {
    StrokeStyle st;
    const Affine to_device = to_pixels(ctm);
    const double scale = std::sqrt(std::fabs(to_device.a * to_device.d - to_device.b * to_device.c));
    st.width = s->linewidth > 0 ? s->linewidth : (scale > 0 ? 1.0 / scale : 1.0);
    st.cap = to_cap(s->start_cap);
    switch (s->linejoin) {
      case FZ_LINEJOIN_ROUND: st.join = LineJoin::Round; break;
      case FZ_LINEJOIN_BEVEL: st.join = LineJoin::Bevel; break;
      default: st.join = LineJoin::Miter; break;
    }
    st.miter_limit = s->miterlimit;
    // dash_list is declared float[32] but MuPDF allocates the state with
    // room for dash_len entries (fz_new_stroke_state_with_dash_len): read
    // them through a pointer, not by indexing the array past 32.
    const float* dashes = s->dash_list;
    st.dashes.assign(dashes, dashes + std::max(0, s->dash_len));
    st.dash_offset = s->dash_phase;
    return st;
  }

  // A centreline without contours strokes nothing; one whose contours have
  // no segments ("M p Z") still has caps.
  void stroke(Path centreline, const Affine& xf, const StrokeStyle& style, const Paint& paint) {
    if (centreline.contours().empty()) return;
    b->stroke(b->add_geometry(std::move(centreline)), xf, style, paint);
  }

  void fill(Path geometry, const Affine& xf, FillRule rule, const Paint& paint) {
    if (geometry.empty()) return;
    b->fill(b->add_geometry(std::move(geometry)), xf, rule, paint);
  }
  // A clip group around what follows: the path filled with `rule`, or
  // with `stroke` the stroke of the centreline.
  void clip(Path geometry, const Affine& xf, FillRule rule, const StrokeStyle* stroke = nullptr) {
    b->push();
    if (stroke ? !geometry.contours().empty() : !geometry.empty()) {
      const uint32_t g = b->add_geometry(std::move(geometry));
      if (stroke)
        b->clip_stroke(g, xf, *stroke);
      else
        b->clip(g, xf, rule);
    }
    b->activate();
    pops.push_back(ClipGroup);
  }

  // Calls f(glyph path in user space) for every glyph of `text`; Type 3
  // glyphs without an outline run their procedures through this device.
  template <class F>
  void glyphs(fz_context* ctx, const fz_text* text, fz_matrix ctm, F&& f) {
    for (const fz_text_span* span = text->head; span; span = span->next) {
      for (int i = 0; i < span->len; i++) {
        const fz_text_item& it = span->items[i];
        if (it.gid < 0) continue;
        fz_matrix tm = span->trm;
        tm.e = it.x;
        tm.f = it.y;
        if (const Path* outline = glyph_cache->outline(span->font, it.gid)) {
          if (!outline->empty()) f(outline->transformed(to_affine(tm)));
        } else if (!fz_font_t3_procs(ctx, span->font) ||
                   !run_t3_glyph(ctx, span->font, it.gid, fz_concat(tm, ctm), &super)) {
          warn("a glyph without an outline was skipped");
        }
      }
    }
  }

  // An image as a texture paint on the unit square that `ctm` places (MuPDF
  // puts the image's top-left pixel at the unit square's origin); the
  // pixmap's premultiplied samples become straight RGBA. A stencil mask
  // (one alpha channel) is white where it paints, tinted by `tint`.
  // Magnified, an image is smoothed only with /Interpolate true; without
  // it its pixels stay squares, as MuPDF and Acrobat draw them.
  // Returns the paint (and the placement in *xf), or nothing.
  std::optional<Paint> image_paint(fz_context* ctx, fz_image* img, fz_matrix ctm, float alpha, fz_color_params cp,
                                   RGBA tint, Affine* xf_out) {
    const Affine px = device * to_affine(ctm);
    const bool in_inks = ink_mode();
    // Print preview: CMYK samples, RGB-based images through the press's
    // profile (decoded as RGB, converted a row at a time below).
    const bool profiled = in_inks && inks->profile && rgb_based(ctx, img->colorspace);
    fz_pixmap* pix = rgb_pixmap(ctx, img, cp, fz_matrix{float(px.a), float(px.b), float(px.c), float(px.d),
                                                       float(px.e), float(px.f)},
                                in_inks && !profiled ? fz_device_cmyk(ctx) : nullptr);
    if (!pix) {
      warn("an image could not be decoded: skipped");
      return std::nullopt;
    }
    auto im = std::make_shared<Image>();
    im->width = fz_pixmap_width(ctx, pix);
    im->height = fz_pixmap_height(ctx, pix);
    const int n = fz_pixmap_components(ctx, pix), stride = fz_pixmap_stride(ctx, pix);
    const bool has_alpha = fz_pixmap_alpha(ctx, pix) != 0;
    const unsigned char* samples = fz_pixmap_samples(ctx, pix);
    im->rgba8.resize(size_t(im->width) * im->height * 4);
    std::vector<float> row_rgb, row_cmyk;
    std::vector<unsigned char> row;
    for (int y = 0; y < im->height; y++) {
      const unsigned char* line = samples + size_t(y) * stride;
      int m = n;
      if (profiled && n >= 3) {
        // This row's straight RGB through the profile, into CMYK samples
        // premultiplied again (as the loop below reads MuPDF's).
        row_rgb.resize(size_t(im->width) * 3);
        row_cmyk.resize(size_t(im->width) * 4);
        row.resize(size_t(im->width) * 5);
        for (int x = 0; x < im->width; x++) {
          const unsigned char* s = line + size_t(x) * n;
          const int a = has_alpha ? s[n - 1] : 255;
          for (int k = 0; k < 3; k++) row_rgb[size_t(x) * 3 + k] = a ? std::min(1.0f, s[k] / float(a)) : 0.0f;
        }
        inks->profile->rgb_to_cmyk(row_rgb.data(), row_cmyk.data(), im->width, cp.ri);
        for (int x = 0; x < im->width; x++) {
          const int a = has_alpha ? line[size_t(x) * n + n - 1] : 255;
          for (int k = 0; k < 4; k++)
            row[size_t(x) * 5 + k] = static_cast<unsigned char>(std::lround(row_cmyk[size_t(x) * 4 + k] * a));
          row[size_t(x) * 5 + 4] = static_cast<unsigned char>(a);
        }
        line = row.data();
        m = 5;
      }
      for (int x = 0; x < im->width; x++) {
        const unsigned char* s = line + size_t(x) * m;
        const int n = m;
        const int a = has_alpha ? s[n - 1] : 255;
        uint8_t* d = &im->rgba8[(size_t(y) * im->width + x) * 4];
        for (int k = 0; k < 3; k++) {
          // Print preview: the pass's inks out of C, M, Y, K (spots: none).
          const int c = in_inks ? inks->pass.inks[k] : k;
          d[k] = n < 3 ? 255
                 : c < 0 || c >= (in_inks ? 4 : 3)
                     ? 0
                     : static_cast<uint8_t>(a ? std::min(255, (s[c] * 255 + a / 2) / a) : 0);
        }
        d[3] = static_cast<uint8_t>(a);
      }
    }
    fz_drop_pixmap(ctx, pix);
    const Affine xf = place(ctm);
    Texture t;
    t.image = std::move(im);
    t.xf = xf * Affine::scale(1.0 / t.image->width, 1.0 / t.image->height);
    t.tint = tint;
    t.filter = img->interpolate ? TextureFilter::Bilinear : TextureFilter::Nearest;
    Paint paint;
    paint.type = PaintType::Texture;
    paint.opacity = alpha;
    paint.index = b->add_texture(std::move(t));
    *xf_out = xf;
    return paint;
  }
  void image(fz_context* ctx, fz_image* img, fz_matrix ctm, float alpha, fz_color_params cp, RGBA tint) {
    Affine xf;
    if (const auto paint = image_paint(ctx, img, ctm, alpha, cp, tint, &xf))
      fill(Path::rectangle(0, 0, 1, 1), xf, FillRule::NonZero, *paint);
  }
  // A clip by an image mask: a group masked by the image's alpha, until
  // pop_clip.
  void clip_image(fz_context* ctx, fz_image* img, fz_matrix ctm) {
    b->begin_group(Group{});
    Group m;
    m.mask = MaskType::Alpha;
    b->begin_group(m);
    image(ctx, img, ctm, 1, fz_default_color_params, RGBA{1, 1, 1, 1});
    b->end_group();
    pops.push_back(MaskedGroup);
  }

  void close(Pop p) {
    if (p == ClipGroup) b->pop();
    if (p == MaskedGroup) b->end_group();
  }
};

namespace {

void fill_path(fz_context* ctx, fz_device* dev, const fz_path* path, int even_odd, fz_matrix ctm, fz_colorspace* cs,
               const float* color, float alpha, fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Affine xf = l->place(ctm);
    Path p = to_path(ctx, path);
    if (l->snapping()) p = adjust_fill(p, l->to_pixels(xf));
    const Paint paint = l->solid(ctx, cs, color, alpha, cp);
    l->painting([&] { l->fill(std::move(p), xf, even_odd ? FillRule::EvenOdd : FillRule::NonZero, paint); });
  });
}

void stroke_path(fz_context* ctx, fz_device* dev, const fz_path* path, const fz_stroke_state* stroke, fz_matrix ctm,
                 fz_colorspace* cs, const float* color, float alpha, fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Affine xf = l->place(ctm);
    StrokeStyle st = l->stroke_style(stroke, xf);
    Path p = to_path(ctx, path);
    if (l->snapping()) p = adjust_stroke(p, &st.width, l->to_pixels(xf));
    const Paint paint = l->solid(ctx, cs, color, alpha, cp);
    l->painting([&] { l->stroke(std::move(p), xf, st, paint); });
  });
}

void clip_path(fz_context* ctx, fz_device* dev, const fz_path* path, int even_odd, fz_matrix ctm, fz_rect) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    l->clip(to_path(ctx, path), l->place(ctm), even_odd ? FillRule::EvenOdd : FillRule::NonZero);
  });
}

void clip_stroke_path(fz_context* ctx, fz_device* dev, const fz_path* path, const fz_stroke_state* stroke,
                      fz_matrix ctm, fz_rect) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Affine xf = l->place(ctm);
    const StrokeStyle st = l->stroke_style(stroke, xf);
    l->clip(to_path(ctx, path), xf, FillRule::NonZero, &st);
  });
}

// What fz_process_shade hands over: vertices in the device space MuPDF
// draws in, colours converted to sRGB (or, for a shading with a Function,
// the function's input t in [0, 1]).
struct MeshCapture {
  fz_shade* shade;
  fz_color_params cp;
  Lowering* lowering;  // print preview: its inks
  Mesh mesh;
  bool bad_color = false;
};

void mesh_prepare(fz_context* ctx, void* arg, fz_vertex* v, const float* c) {
  MeshCapture* m = static_cast<MeshCapture*>(arg);
  if (m->shade->use_function) {
    v->c[0] = c[0];
    v->c[1] = v->c[2] = 0;  // unused, but mesh_triangle copies them into the vertex's colour
  } else {
    if (m->lowering->ink_mode()) {
      m->lowering->to_inks(ctx, m->shade->colorspace, c, m->cp);
      for (int k = 0; k < 3; k++) v->c[k] = m->lowering->pass_ink(k);
      return;
    }
    float rgb[3] = {0, 0, 0};
    if (!convert_color(ctx, m->shade->colorspace, c, rgb, m->cp)) m->bad_color = true;
    for (int k = 0; k < 3; k++) v->c[k] = rgb[k];
  }
}

void mesh_triangle(fz_context*, void* arg, fz_vertex* a, fz_vertex* b, fz_vertex* c) {
  MeshCapture* m = static_cast<MeshCapture*>(arg);
  try {
    for (const fz_vertex* v : {a, b, c})
      m->mesh.vertices.push_back({{v->p.x, v->p.y}, RGBA{v->c[0], v->c[1], v->c[2], 1}});
  } catch (...) {
    m->bad_color = true;  // out of memory: the mesh is dropped below
  }
}

// fz_process_shade under its own fz_try; false when MuPDF failed.
bool process_shade(fz_context* ctx, fz_shade* shade, fz_matrix ctm, MeshCapture* capture) {
  volatile bool ok = true;
  fz_try(ctx) { fz_process_shade(ctx, shade, ctm, fz_infinite_rect, mesh_prepare, mesh_triangle, capture); }
  fz_catch(ctx) { ok = false; }
  return ok;
}

// Mesh shadings whose outline has more edges than this are filled over
// their box (Mesh::area_by_triangles).
constexpr size_t kMaxMeshOutline = 16384;

// Shadings: axial and radial ones as gradient paints over the shading's
// box (or the page), the colour function as MuPDF samples it (256 stops
// converted to sRGB), Extend as the gradient's extend flags. Mesh shadings
// (types 4 to 7, patches subdivided as MuPDF does) and function-based ones
// (type 1, sampled on MuPDF's grid) as a mesh paint over the union of
// their triangles, the colour interpolated per sample.
void fill_shade(fz_context* ctx, fz_device* dev, fz_shade* shade, fz_matrix ctm, float alpha, fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const fz_matrix to_device = fz_concat(shade->matrix, ctm);
    const fz_rect r = shade->bbox;
    const bool bounded = !fz_is_infinite_rect(r) && r.x1 > r.x0 && r.y1 > r.y0;
    auto ramp = [&]() {
      std::vector<ColorStop> stops;
      for (int i = 0; i < 256; i++)
        stops.push_back({i / 255.0, l->solid(ctx, shade->colorspace, shade->function[i], 1, cp).color});
      return stops;
    };
    Paint paint;
    paint.opacity = alpha;
    if (shade->type == FZ_LINEAR || shade->type == FZ_RADIAL) {
      Gradient g;
      g.xf = l->place(to_device);
      const auto& c = shade->u.l_or_r.coords;
      g.p0 = {c[0][0], c[0][1]};
      g.p1 = {c[1][0], c[1][1]};
      g.focal = g.p0;
      g.focal_radius = c[0][2];
      g.center = g.p1;
      g.radius = c[1][2];
      g.extend_start = shade->u.l_or_r.extend[0] != 0;
      g.extend_end = shade->u.l_or_r.extend[1] != 0;
      g.stops = ramp();
      paint.type = shade->type == FZ_LINEAR ? PaintType::LinearGradient : PaintType::RadialGradient;
      paint.index = l->b->add_gradient(std::move(g));
      const Path area = bounded ? Path::rectangle(r.x0, r.y0, r.x1, r.y1) : Path::rectangle(0, 0, l->page_w, l->page_h);
      l->fill(area, bounded ? l->place(to_device) : l->adjust, FillRule::NonZero, paint);
      return;
    }
    // Vertices come out in device space; the shading's box is in shading
    // space and clips them.
    MeshCapture capture{shade, cp, l, {}, false};
    if (!process_shade(ctx, shade, to_device, &capture) || capture.mesh.vertices.empty()) {
      l->warn("a shading could not be read: skipped");
      return;
    }
    if (capture.bad_color) l->warn("a colour could not be converted: black used");
    if (shade->use_function) capture.mesh.ramp = ramp();
    capture.mesh.xf = l->adjust;
    // An outline of many edges (a soup of small overlapping triangles,
    // not a subdivided patch) would weigh on the shortcut tree in every
    // cell it crosses: the mesh's box is filled instead, and the triangles
    // decide per sample where it paints.
    bool soup = false;
    Path area = mesh_outline(capture.mesh, kMaxMeshOutline, &soup);
    if (area.empty() && !soup) return;
    if (soup) {
      double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
      for (const MeshVertex& v : capture.mesh.vertices) {
        x0 = std::min(x0, v.p.x);
        y0 = std::min(y0, v.p.y);
        x1 = std::max(x1, v.p.x);
        y1 = std::max(y1, v.p.y);
      }
      area = Path::rectangle(x0, y0, x1, y1);
      capture.mesh.area_by_triangles = true;
    }
    paint.type = PaintType::Mesh;
    paint.index = l->b->add_mesh(std::move(capture.mesh));
    if (bounded) l->clip(Path::rectangle(r.x0, r.y0, r.x1, r.y1), l->place(to_device), FillRule::NonZero);
    l->fill(std::move(area), l->adjust, FillRule::NonZero, paint);
    if (bounded) {
      l->close(l->pops.back());
      l->pops.pop_back();
    }
  });
}

// Text as glyph outlines, curves in object precision (every render mode
// reaches one of these or ignore_text).
void fill_text(fz_context* ctx, fz_device* dev, const fz_text* text, fz_matrix ctm, fz_colorspace* cs,
               const float* color, float alpha, fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Paint paint = l->solid(ctx, cs, color, alpha, cp);
    const Affine xf = l->place(ctm);
    l->painting([&] {
      l->glyphs(ctx, text, ctm, [&](Path p) { l->fill(std::move(p), xf, FillRule::NonZero, paint); });
    });
  });
}

void stroke_text(fz_context* ctx, fz_device* dev, const fz_text* text, const fz_stroke_state* stroke, fz_matrix ctm,
                 fz_colorspace* cs, const float* color, float alpha, fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Paint paint = l->solid(ctx, cs, color, alpha, cp);
    const Affine xf = l->place(ctm);
    const StrokeStyle st = l->stroke_style(stroke, xf);
    l->painting([&] { l->glyphs(ctx, text, ctm, [&](Path p) { l->stroke(std::move(p), xf, st, paint); }); });
  });
}

// A text clip: the union of its glyphs.
void clip_text(fz_context* ctx, fz_device* dev, const fz_text* text, fz_matrix ctm, fz_rect) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Affine xf = l->place(ctm);
    l->b->push();
    l->glyphs(ctx, text, ctm, [&](Path p) { l->b->clip(l->b->add_geometry(std::move(p)), xf, FillRule::NonZero); });
    l->b->activate();
    l->pops.push_back(Lowering::ClipGroup);
  });
}

void clip_stroke_text(fz_context* ctx, fz_device* dev, const fz_text* text, const fz_stroke_state* stroke,
                      fz_matrix ctm, fz_rect) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    const Affine xf = l->place(ctm);
    l->b->push();
    const StrokeStyle st = l->stroke_style(stroke, xf);
    l->glyphs(ctx, text, ctm, [&](Path p) {
      if (!p.empty()) l->b->clip_stroke(l->b->add_geometry(std::move(p)), xf, st);
    });
    l->b->activate();
    l->pops.push_back(Lowering::ClipGroup);
  });
}

// Tiling patterns: the cell's content, captured into a tile scene in
// pattern space (from the view box's corner, one period xstep x ystep,
// clipped to the view box), repeated by a pattern paint over `area` (in
// pattern space, as MuPDF's interpreter passes it).
// Returning 0 tells MuPDF the content comes once, for us to repeat.
int begin_tile(fz_context*, fz_device* dev, fz_rect area, fz_rect view, float xstep, float ystep, fz_matrix ctm,
               int) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    Lowering::Tile t;
    t.parent = l->b;
    t.parent_adjust = l->adjust;
    t.area = area;
    t.pops = l->pops.size();
    const double w = view.x1 - view.x0, h = view.y1 - view.y0;
    t.pattern_space = l->place(ctm);
    t.placement = t.pattern_space * Affine::translate(view.x0, view.y0);
    if (xstep > 0 && ystep > 0 && w > 0 && h > 0 && t.placement.invertible()) {
      t.builder = std::make_unique<SceneBuilder>(xstep, ystep);
      t.builder->set_budget(l->b->budget());
      l->b = t.builder.get();
      l->adjust = t.placement.inverted() * t.parent_adjust;
      if (w < xstep || h < ystep) {  // gaps between cells: the content stays in its box
        t.clipped = true;
        l->b->push();
        l->b->clip(l->b->add_geometry(Path::rectangle(0, 0, w, h)), Affine{}, FillRule::NonZero);
        l->b->activate();
      }
    } else {
      l->warn("a tiling pattern with an empty or reversed cell was drawn once");
    }
    l->tiles.push_back(std::move(t));
  });
  return 0;
}

void end_tile(fz_context*, fz_device* dev) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    if (l->tiles.empty()) return;
    Lowering::Tile t = std::move(l->tiles.back());
    l->tiles.pop_back();
    if (!t.builder) return;
    while (l->pops.size() > t.pops) {  // clips the cell's content left open
      l->close(l->pops.back());
      l->pops.pop_back();
    }
    if (t.clipped) l->b->pop();
    Pattern pattern;
    pattern.tile = std::make_shared<Scene>(t.builder->finish());
    if (t.builder->flattened_groups()) l->warn(flattened_groups_warning(t.builder->flattened_groups()));
    pattern.xf = t.placement;
    l->b = t.parent;
    l->adjust = t.parent_adjust;
    Paint paint;
    paint.type = PaintType::Pattern;
    paint.index = l->b->add_pattern(std::move(pattern));
    l->fill(Path::rectangle(t.area.x0, t.area.y0, t.area.x1, t.area.y1), t.pattern_space, FillRule::NonZero, paint);
  });
}

void pop_clip(fz_context*, fz_device* dev) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    if (l->pops.empty()) return;
    const Lowering::Pop p = l->pops.back();
    l->pops.pop_back();
    l->close(p);
  });
}

void begin_mask(fz_context* ctx, fz_device* dev, fz_rect, int luminosity, fz_colorspace* cs, const float* bc,
                fz_color_params cp) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    l->b->begin_group(Group{});
    l->rgb_depth++;  // the mask's content and backdrop colour: RGB luminosity
    Group m;
    m.mask = luminosity ? MaskType::Luminance : MaskType::Alpha;
    // PDF's luminosity (Lum of the non-separable blend modes).
    m.luminance[0] = 0.3f;
    m.luminance[1] = 0.59f;
    m.luminance[2] = 0.11f;
    if (luminosity && cs && bc) {
      const Paint p = l->solid(ctx, cs, bc, 1, cp);
      m.backdrop = p.color;
    }
    l->b->begin_group(m);
    l->pops.push_back(Lowering::MaskedGroup);
  });
}

void end_mask(fz_context*, fz_device* dev) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    l->b->end_group();
    l->rgb_depth--;
  });
}

void begin_group(fz_context*, fz_device* dev, fz_rect, fz_colorspace*, int isolated, int knockout, int blendmode,
                 float alpha) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] {
    Group g;
    g.opacity = alpha;
    g.blend = static_cast<BlendMode>(blendmode & FZ_BLEND_MODEMASK);
    g.isolated = isolated != 0;
    g.knockout = knockout != 0;
    if (l->ink_mode()) set_ink_blend(g, l->inks->pass);
    l->b->begin_group(g);
  });
}

void end_group(fz_context*, fz_device* dev) {
  Lowering* l = Lowering::of(dev);
  l->guarded([&] { l->b->end_group(); });
}

}  // namespace

Lowered lower_page(fz_context* ctx, fz_page* page, const fz_matrix& ctm, const Affine& device, double width,
                   double height, SceneBuilder& b, GlyphCache& glyphs, const PageOptions& options,
                   const InkTarget* inks) {
  const bool annotations = options.annotations;
  Lowered out;
  std::vector<std::string>& warnings = out.warnings;
  Lowering* l = fz_new_derived_device(ctx, Lowering);
  fz_device* dev = &l->super;
  // fz_new_derived_device zero-fills; the C++ members are constructed here
  // and destroyed below, before the device is dropped.
  l->b = &b;
  l->adjust = Affine{};
  l->device = device;
  l->page_w = width;
  l->page_h = height;
  l->snap = options.thin_lines == ThinLines::Snap;
  l->inks = inks;
  l->rgb_depth = 0;
  l->warnings = &warnings;
  l->glyph_cache = &glyphs;
  new (&l->pops) std::vector<Lowering::Pop>();
  new (&l->tiles) std::vector<Lowering::Tile>();
  new (&l->warned) std::set<std::string>();
  new (&l->error) std::string();
  new (&l->ink_values) std::vector<float>();
  new (&l->painted) std::vector<bool>();
  dev->fill_path = fill_path;
  dev->stroke_path = stroke_path;
  dev->clip_path = clip_path;
  dev->clip_stroke_path = clip_stroke_path;
  dev->pop_clip = pop_clip;
  dev->begin_mask = begin_mask;
  dev->end_mask = end_mask;
  dev->begin_group = begin_group;
  dev->end_group = end_group;
  dev->begin_tile = begin_tile;
  dev->end_tile = end_tile;
  dev->fill_text = fill_text;
  dev->stroke_text = stroke_text;
  dev->clip_text = clip_text;
  dev->clip_stroke_text = clip_stroke_text;
  dev->fill_shade = fill_shade;
  dev->fill_image = [](fz_context* c, fz_device* d, fz_image* img, fz_matrix m, float alpha, fz_color_params cp) {
    Lowering* low = Lowering::of(d);
    low->guarded([&] { low->image(c, img, m, alpha, cp, RGBA{1, 1, 1, 1}); });
  };
  dev->fill_image_mask = [](fz_context* c, fz_device* d, fz_image* img, fz_matrix m, fz_colorspace* cs,
                            const float* color, float alpha, fz_color_params cp) {
    Lowering* low = Lowering::of(d);
    low->guarded([&] {
      const RGBA tint = low->solid(c, cs, color, 1, cp).color;
      low->painting([&] { low->image(c, img, m, alpha, cp, tint); });
    });
  };
  dev->clip_image_mask = [](fz_context* c, fz_device* d, fz_image* img, fz_matrix m, fz_rect) {
    Lowering* low = Lowering::of(d);
    low->guarded([&] { low->clip_image(c, img, m); });
  };
  std::string error;
  pdf_page* pdf = pdf_page_from_fz_page(ctx, page);
  const auto t0 = std::chrono::steady_clock::now();
  fz_try(ctx) {
    if (pdf) {
      pdf_run_page_contents_with_usage(ctx, pdf, dev, ctm, "View", nullptr);
      if (annotations) {
        pdf_run_page_annots_with_usage(ctx, pdf, dev, ctm, "Print", nullptr);
        pdf_run_page_widgets_with_usage(ctx, pdf, dev, ctm, "Print", nullptr);
      }
    } else if (annotations) {
      fz_run_page(ctx, page, dev, ctm, nullptr);
    } else {
      fz_run_page_contents(ctx, page, dev, ctm, nullptr);
    }
    fz_close_device(ctx, dev);
  }
  fz_catch(ctx) {
    error = fz_caught_message(ctx);
  }
  out.run_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  out.lower_ms = l->lower_ms;
  if (error.empty()) error = l->error;
  if (error.empty() && !l->tiles.empty()) error = "a tiling pattern was left open";
  // Clips, masks and groups MuPDF left open (an interrupted page).
  if (error.empty()) {
    while (!l->pops.empty()) {
      l->close(l->pops.back());
      l->pops.pop_back();
    }
  }
  l->error.~basic_string();
  l->ink_values.~vector();
  l->painted.~vector();
  l->warned.~set();
  l->pops.~vector();
  l->tiles.~vector();
  fz_drop_device(ctx, dev);
  if (!error.empty()) throw Error(error);  // Document::page names the page
  return out;
}

}  // namespace mpvg::pdf::detail
