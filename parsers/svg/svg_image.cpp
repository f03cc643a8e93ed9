// The <image> element (SVG 2 embedded.html#ImageElement): raster images as
// texture paints on the rectangle they show in, SVG documents converted as
// scenes of their own and appended as vectors.
//
// Placement, as in SVG 2 and resvg: x, y, width and height give the
// viewport. An auto width or height (absent, "auto" or invalid) takes the
// image's intrinsic size, or keeps its aspect ratio when the other is
// given; a zero or negative one disables rendering. preserveAspectRatio
// places the image's box (its pixels, or an SVG document's width x height)
// in the viewport, and what shows is clipped to the viewport: the drawn
// rectangle is the intersection of the placed box and the viewport, in the
// element's user space (any transform then applies to it).
//
// An embedded SVG document is parsed and converted by a converter of its
// own: it maps its viewBox to its width x height as a root document does,
// and the <image>'s preserveAspectRatio then places that box (resvg's two
// steps). Its strokes are prepared for the scale it ends up at on screen.
// Nothing inherits across the document boundary. Its relative hrefs
// resolve against its own folder (a data: document keeps the embedding
// document's), under the same allowed folders. A document is embedded at
// most kMaxImageDepth deep, and an <image> of a document that is already
// being embedded is cut: a document that shows itself draws one copy of
// itself, as browsers (which load nothing for an SVG image) and resvg do.
// A resource is read, decoded or parsed once per document tree
// (ImageCache); every drawing of an SVG document is converted anew (its
// strokes depend on its scale) and copied into the scene, under the
// shared budgets of element instances and kMaxEmbeddedSegments.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "parsers/svg/svg_converter.h"
#include "parsers/svg/svg_css.h"
#include "frame/scene_info.h"

namespace mpvg::svg::detail {

namespace {

// An href as warnings show it: a data: URI by its header only.
std::string shown_href(std::string_view href) {
  href = trim(href);
  if (href.size() >= 5 && iequals(href.substr(0, 5), "data:")) {
    const size_t header = std::min<size_t>(std::min(href.find(','), href.size()), 40);
    return std::string(href.substr(0, header)) + ",...";
  }
  if (href.size() > 80) return std::string(href.substr(0, 77)) + "...";
  return std::string(href);
}

// 'text', built piece by piece (GCC 12 warns falsely about "'" + string).
std::string in_quotes(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '\'';
  out += text;
  out += '\'';
  return out;
}

// The intersection of two rectangles; w or h <= 0 when they do not overlap.
ViewBox intersect(const ViewBox& a, const ViewBox& b) {
  const double x0 = std::max(a.x, b.x), y0 = std::max(a.y, b.y);
  const double x1 = std::min(a.x + a.w, b.x + b.w), y1 = std::min(a.y + a.h, b.y + b.h);
  return {x0, y0, x1 - x0, y1 - y0};
}

// The box [0, w] x [0, h] mapped by a scale-and-translate `m`.
ViewBox placed_box(const Affine& m, double w, double h) { return {m.e, m.f, w * m.a, h * m.d}; }

// `width` x `height` placed in `vp` by preserveAspectRatio: the box's
// units to the viewport's user space.
Affine place_in(const ViewBox& vp, const AspectRatio& ar, double width, double height) {
  return Affine::translate(vp.x, vp.y) * view_box_transform(ViewBox{0, 0, width, height}, ar, vp.w, vp.h);
}

}  // namespace

const LoadedImage& Converter::load_image(const std::string& href) {
  const auto key = std::make_pair(s_.base_dir, href);
  if (const auto it = s_.images->find(key); it != s_.images->end()) return it->second;
  LoadedImage li;
  std::string why;
  std::optional<Resource> r = fetch_resource(href, s_.base_dir, s_.allowed_dirs, &why);
  if (!r) {
    li.error = why;
  } else {
    li.path = r->path;
    const ImageKind kind = sniff_image(r->bytes, r->mime);
    switch (kind) {
      case ImageKind::Png:
      case ImageKind::Jpeg:
      case ImageKind::Gif:
      case ImageKind::Webp:
        // Decoded where it is drawn, at the size needed there.
        li.raster_bytes = std::make_shared<const std::vector<uint8_t>>(std::move(r->bytes));
        break;
      case ImageKind::Svg:
      case ImageKind::Svgz: {
        // Parsed once, however often it is drawn.
        std::optional<std::string> text;
        if (kind == ImageKind::Svgz)
          text = gunzip(r->bytes, &why);
        else
          text.emplace(r->bytes.begin(), r->bytes.end());
        if (!text) {
          li.error = in_quotes(shown_href(href)) + ": " + why;
          break;
        }
        try {
          li.svg = std::make_shared<const Document>(parse_document(*text));
        } catch (const Error& err) {
          li.error = in_quotes(shown_href(href)) + ": " + err.what();
        }
        break;
      }
      case ImageKind::Unknown:
        li.error = in_quotes(shown_href(href)) + " is not a PNG, JPEG, GIF, WebP or SVG image";
        break;
    }
  }
  return s_.images->emplace(key, std::move(li)).first->second;
}

namespace {

// The largest stretch of m's linear part: output pixels per texel along the
// direction it magnifies most.
double largest_stretch(const Affine& m) {
  const double e = m.a * m.a + m.b * m.b + m.c * m.c + m.d * m.d, det = m.a * m.d - m.b * m.c;
  return std::sqrt(std::max(0.0, (e + std::sqrt(std::max(0.0, e * e - 4 * det * det))) / 2));
}

}  // namespace

std::shared_ptr<const Image> Converter::raster_for(const LoadedImage& li,
                                                   const std::function<Affine(int w, int h)>& texels, int* k,
                                                   std::string* why) {
  auto factor = [&](int w, int h) {
    // Images up to 4 Mpixels (16 MB) keep every texel: the renderer's mip
    // chain minifies them as it always has.
    if (size_t(w) * size_t(h) <= (size_t(1) << 22)) return 1;
    const double s = largest_stretch(device_ * texels(w, h));
    if (!(s > 0) || !std::isfinite(s)) return 1;
    return static_cast<int>(std::clamp(std::floor(1 / s), 1.0, 65536.0));
  };
  if (li.width > 0) {
    *k = factor(li.width, li.height);
    if (const auto it = li.rasters.find(*k); it != li.rasters.end()) return it->second;
  }
  DecodeRequest request;
  request.reduction = factor;
  request.max_pixels = s_.options.max_image_pixels;
  request.max_whole_pixels = s_.options.max_whole_image_pixels;
  int w = 0, h = 0;
  std::shared_ptr<const Image> image = decode_raster(*li.raster_bytes, why, request, &w, &h);
  if (!image) return nullptr;
  li.width = w;
  li.height = h;
  *k = factor(w, h);
  li.rasters[*k] = image;
  return image;
}

void Converter::texture_fill(std::shared_ptr<const Image> image, const Affine& texels, TextureFilter filter,
                             double opacity, uint32_t shape, const Affine& space) {
  Texture t;
  t.image = std::move(image);
  t.xf = texels;
  t.filter = filter;
  t.wrap_x = t.wrap_y = TextureWrap::Clamp;
  t.tint = {1, 1, 1, static_cast<float>(opacity)};
  textures_.push_back(std::move(t));
  Paint paint;
  paint.type = PaintType::Texture;
  paint.index = static_cast<uint32_t>(textures_.size() - 1);
  paints_.push_back(paint);
  Op fill = Op::of(OpKind::Fill);
  fill.shape = shape;
  fill.xf = space;
  fill.paint = static_cast<uint32_t>(paints_.size() - 1);
  ops_.push_back(fill);
}

uint32_t Converter::rect_shape(const ViewBox& r) {
  add_shape(rect_path(r.x, r.y, r.w, r.h, 0, 0));
  return static_cast<uint32_t>(shapes_.size() - 1);
}

void Converter::image(const Element& e, const Style& st, const Affine& space) {
  // href wins over xlink:href (SVG 2 linking.html#XLinkRefAttrs); without
  // one there is no image.
  const std::string* href = e.attribute("href");
  if (!href) href = e.attribute("xlink:href");
  if (!href || trim(*href).empty()) return;
  const double em = st.inh.font_size;
  auto given = [&](const char* name, Axis axis) -> std::optional<double> {
    const std::string* a = e.attribute(name);
    if (!a) return std::nullopt;
    const auto l = parse_length(*a);
    if (!l) return std::nullopt;  // "auto", or invalid: auto
    return to_user(*l, axis, em);
  };
  const std::optional<double> width = given("width", Axis::X), height = given("height", Axis::Y);
  if ((width && !(*width > 0)) || (height && !(*height > 0))) return;
  const double x = length(e, "x", Axis::X, 0, em), y = length(e, "y", Axis::Y, 0, em);
  AspectRatio ar;
  if (const std::string* a = e.attribute("preserveAspectRatio")) ar = parse_aspect_ratio(*a).value_or(ar);
  // The viewport for an intrinsic size iw x ih (CSS Images 3's default
  // sizing with the image's natural size and ratio).
  auto viewport = [=](double iw, double ih) {
    ViewBox vp{x, y, width.value_or(iw), height.value_or(ih)};
    if (width && !height) vp.h = iw > 0 ? ih * (*width / iw) : 0;
    if (height && !width) vp.w = ih > 0 ? iw * (*height / ih) : 0;
    return vp;
  };

  const LoadedImage& li = load_image(*href);
  if (!li.error.empty()) {
    warn("<image> not rendered: " + li.error);
    return;
  }
  if (li.raster_bytes) {
    // Texel units of a w x h raster to scene units, as placed below.
    auto texels = [&](int w, int h) { return space * place_in(viewport(w, h), ar, w, h); };
    std::string why;
    int k = 1;
    const std::shared_ptr<const Image> raster = raster_for(li, texels, &k, &why);
    if (!raster) {
      warn("<image> not rendered: " + in_quotes(shown_href(*href)) + ": " + why);
      return;
    }
    const double iw = li.width, ih = li.height;
    const ViewBox vp = viewport(iw, ih);
    if (!(vp.w > 0 && vp.h > 0)) return;
    // The bounding box is the viewport (SVG 2 coords.html#BoundingBoxes).
    Op bounds = Op::of(OpKind::Bounds);
    bounds.shape = rect_shape(vp);
    bounds.xf = space;
    ops_.push_back(bounds);
    if (!st.inh.visible) return;
    const Affine place = place_in(vp, ar, iw, ih);
    const ViewBox shown = intersect(vp, placed_box(place, iw, ih));
    if (!(shown.w > 0 && shown.h > 0)) return;
    // texel (i, j) covers [i, i+1] x [j, j+1] of the placed box
    // A reduced raster's texels cover k x k of the image's own (the last
    // row and column partly outside it, where nothing is drawn).
    texture_fill(raster, space * place * Affine::scale(k, k), st.inh.image_rendering, 1, rect_shape(shown), space);
    return;
  }

  std::optional<Embedded> doc = embed_document(li, shown_href(*href), viewport, ar, space);
  if (!doc) return;
  Op bounds = Op::of(OpKind::Bounds);
  bounds.shape = rect_shape(doc->viewport);
  bounds.xf = space;
  ops_.push_back(bounds);
  if (!st.inh.visible || doc->scene.paths.empty()) return;
  const ViewBox shown = intersect(doc->viewport, placed_box(doc->place, doc->scene.width, doc->scene.height));
  if (!(shown.w > 0 && shown.h > 0)) return;
  // The document clipped to what shows of it: a clip group around the
  // appended scene.
  ops_.push_back(Op::of(OpKind::Push));
  Op clip = Op::of(OpKind::Clip);
  clip.shape = rect_shape(shown);
  clip.xf = space;
  ops_.push_back(clip);
  ops_.push_back(Op::of(OpKind::Activate));
  Op append = Op::of(OpKind::Append);
  append.scene = static_cast<uint32_t>(embedded_.size());
  append.xf = space * doc->place;
  embedded_.push_back(std::move(doc->scene));
  ops_.push_back(append);
  ops_.push_back(Op::of(OpKind::Pop));
}

std::optional<Converter::Embedded> Converter::embed_document(const LoadedImage& li, const std::string& shown,
                                                             const std::function<ViewBox(double, double)>& viewport,
                                                             const AspectRatio& ar, const Affine& space) {
  if (s_.image_depth + 1 > kMaxImageDepth) {
    warn("SVG images nested more than " + std::to_string(kMaxImageDepth) + " deep: the innermost are not rendered");
    return std::nullopt;
  }
  if (!li.path.empty() && std::find(s_.documents.begin(), s_.documents.end(), li.path) != s_.documents.end()) {
    warn("<image> " + in_quotes(shown) + " embeds a document that is already being drawn: the inner copy is not rendered");
    return std::nullopt;
  }
  Embedded out;
  std::vector<std::string> warnings;
  try {
    const Document& doc = *li.svg;
    // The document's strokes are prepared for the scale its scene units
    // end up at in our output pixels, known once its size is.
    ParseOptions options = s_.options;
    options.export_id.clear();  // the outer document's
    options.query = false;
    bool sized = false;
    options.view = [&](double w, double h) {
      out.viewport = viewport(w, h);
      sized = w > 0 && h > 0 && out.viewport.w > 0 && out.viewport.h > 0;
      out.place = sized ? place_in(out.viewport, ar, w, h) : Affine{};
      return device_ * space * out.place;
    };
    Session session(doc, options, warnings);
    session.base_dir = li.path.empty() ? s_.base_dir : std::filesystem::path(li.path).parent_path().string();
    session.allowed_dirs = li.reads_nothing ? std::vector<std::string>{} : s_.allowed_dirs;
    session.image_depth = s_.image_depth + 1;
    session.documents = s_.documents;
    if (!li.path.empty()) session.documents.push_back(li.path);
    // Not even what the document around it has read already.
    session.images = li.reads_nothing ? std::make_shared<ImageCache>() : s_.images;
    // One budget of element instances and filter effects for the whole
    // document tree; filters nest across documents too.
    session.instances = s_.instances;
    session.embedded_segments = s_.embedded_segments;
    session.filter_effects = s_.filter_effects;
    session.filter_depth = s_.filter_depth;
    Converter conv(session, Affine{}, level_);
    out.scene = conv.run();
    s_.instances = session.instances;
    s_.filter_effects = session.filter_effects;
    s_.stroked_paths += session.stroked_paths;
    for (std::string& w : warnings) warn(std::move(w));
    if (!sized) return std::nullopt;
    // What this embedding adds, the documents it embeds in turn included
    // (they are part of its scene).
    const size_t segments = segment_count(out.scene);
    if (s_.embedded_segments + segments > kMaxEmbeddedSegments) {
      warn("embedded SVG documents would add more than " + std::to_string(kMaxEmbeddedSegments) +
           " segments: further ones are not rendered");
      return std::nullopt;
    }
    s_.embedded_segments += segments;
    tile_encodings_ += conv.tile_encodings_;
  } catch (const Error& err) {
    for (std::string& w : warnings) warn(std::move(w));
    warn("<image> " + in_quotes(shown) + " not rendered: " + err.what());
    return std::nullopt;
  }
  return out;
}

}  // namespace mpvg::svg::detail
