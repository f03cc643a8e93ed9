#include "core/scene.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <unordered_set>

#include "core/error.h"
#include "core/paint/group.h"

namespace mpvg {

// ---------------------------------------------------------------- Path

void Path::ensure_contour() {
  if (points_.empty()) throw Error("path segment without a current point");
  if (!open_contour_) {
    // A segment after close() starts a new contour at the current point.
    Contour c;
    c.first_segment = static_cast<uint32_t>(segments_.size());
    c.start_point = static_cast<uint32_t>(points_.size() - 1);
    contours_.push_back(c);
    open_contour_ = true;
  }
}

void Path::move_to(Vec2 p) {
  points_.push_back(p);
  Contour c;
  c.first_segment = static_cast<uint32_t>(segments_.size());
  c.start_point = static_cast<uint32_t>(points_.size() - 1);
  contours_.push_back(c);
  open_contour_ = true;
}

void Path::add_segment(SegmentType t, uint32_t first_weight) {
  const uint32_t deg = static_cast<uint32_t>(segment_degree(t));
  Segment s{t, static_cast<uint32_t>(points_.size() - 1 - deg), first_weight};
  segments_.push_back(s);
  contours_.back().segment_count++;
}

void Path::line_to(Vec2 p) {
  ensure_contour();
  points_.push_back(p);
  add_segment(SegmentType::Line, 0);
}

void Path::quad_to(Vec2 p1, Vec2 p2) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  add_segment(SegmentType::Quad, 0);
}

void Path::rquad_to(Vec2 p1, Vec2 p2, double w) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  weights_.push_back(w);
  add_segment(SegmentType::RQuad, static_cast<uint32_t>(weights_.size() - 1));
}

void Path::cubic_to(Vec2 p1, Vec2 p2, Vec2 p3) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  points_.push_back(p3);
  add_segment(SegmentType::Cubic, 0);
}

void Path::rcubic_to(Vec2 p1, Vec2 p2, Vec2 p3, double w0, double w1, double w2, double w3) {
  ensure_contour();
  points_.push_back(p1);
  points_.push_back(p2);
  points_.push_back(p3);
  const uint32_t first = static_cast<uint32_t>(weights_.size());
  weights_.insert(weights_.end(), {w0, w1, w2, w3});
  add_segment(SegmentType::RCubic, first);
}

void Path::close() {
  if (!open_contour_ || contours_.empty()) return;
  Contour& c = contours_.back();
  const Vec2 start = points_[c.start_point];
  if (c.segment_count > 0 && points_.back() != start) line_to(start);
  c.closed = true;
  open_contour_ = false;
}

Path Path::contour_path(size_t i) const {
  const Contour& c = contours_.at(i);
  Path out;
  out.move_to(points_[c.start_point]);
  for (uint32_t k = c.first_segment; k < c.first_segment + c.segment_count; k++) {
    const Segment& s = segments_[k];
    const Vec2* p = &points_[s.first_point];
    const double* w = weights_.data() + s.first_weight;
    switch (s.type) {
      case SegmentType::Line: out.line_to(p[1]); break;
      case SegmentType::Quad: out.quad_to(p[1], p[2]); break;
      case SegmentType::RQuad: out.rquad_to(p[1], p[2], w[0]); break;
      case SegmentType::Cubic: out.cubic_to(p[1], p[2], p[3]); break;
      case SegmentType::RCubic: out.rcubic_to(p[1], p[2], p[3], w[0], w[1], w[2], w[3]); break;
    }
  }
  if (c.closed) out.close();
  return out;
}

Path Path::rectangle(double x0, double y0, double x1, double y1) {
  Path p;
  p.move_to({x0, y0});
  p.line_to({x1, y0});
  p.line_to({x1, y1});
  p.line_to({x0, y1});
  p.close();
  return p;
}

Path Path::transformed(const Affine& m) const {
  Path out = *this;
  for (Vec2& p : out.points_) p = m.apply(p);
  return out;
}

void Path::append(const Path& other) {
  const auto np = static_cast<uint32_t>(points_.size());
  const auto nw = static_cast<uint32_t>(weights_.size());
  const auto ns = static_cast<uint32_t>(segments_.size());
  points_.insert(points_.end(), other.points_.begin(), other.points_.end());
  weights_.insert(weights_.end(), other.weights_.begin(), other.weights_.end());
  for (Segment s : other.segments_) {
    s.first_point += np;
    if (s.type == SegmentType::RQuad || s.type == SegmentType::RCubic) s.first_weight += nw;
    segments_.push_back(s);
  }
  for (Contour c : other.contours_) {
    c.first_segment += ns;
    c.start_point += np;
    contours_.push_back(c);
  }
  if (!other.contours_.empty()) open_contour_ = other.open_contour_;
}

size_t path_bytes(const Path& p) {
  // (Capacities: what the arrays hold, grown by doubling.)
  return sizeof(Path) + p.points().capacity() * sizeof(Vec2) + p.weights().capacity() * sizeof(double) +
         p.segments().capacity() * sizeof(Path::Segment) + p.contours().capacity() * sizeof(Path::Contour);
}

size_t Scene::segment_count() const {
  size_t n = 0;
  for (const ScenePath& sp : paths) {
    const Path& g = geometries[sp.geometry];
    if (sp.stroke >= 0) {
      // A stroke's segments are made when it is rendered: about ten per
      // centreline segment (bodies, joins, caps; more for dashes and tight
      // curves), as an estimate.
      n += 10 * (g.segments().size() + g.contours().size());
      continue;
    }
    n += g.segments().size();
    for (const Path::Contour& c : g.contours()) {
      if (c.segment_count == 0) continue;
      const Path::Segment& last = g.segments()[c.first_segment + c.segment_count - 1];
      const Vec2 end = g.points()[last.first_point + segment_degree(last.type)];
      if (end != g.points()[c.start_point]) n++;
    }
  }
  return n;
}

// ---------------------------------------------------------------- builder

struct SceneBuilder::Node {
  // Clip: a clip group '(' clip_items '|' content ')'. Transparency: a
  // group '{' mask? content '}' (mask: another Transparency node).
  enum Kind { Fill, Clip, ClipGroup, Transparency } kind;
  ScenePath path;                   // Fill and Clip leaves
  std::vector<Node*> clip_items;    // ClipGroup: before '|'
  std::vector<Node*> content;       // ClipGroup: after '|'; Transparency: its fill list
  uint32_t group = 0;               // Transparency: index into the scene's groups
  Node* mask = nullptr;             // Transparency: its mask, if any
};

struct SceneBuilder::Frame {
  Node* group;
  bool clip_context;  // the group is a clip-path (its content holds clip-paths)
  bool activated;
};

SceneBuilder::SceneBuilder(double width, double height) {
  scene_.width = width;
  scene_.height = height;
  root_ = new Node{Node::ClipGroup, {}, {}, {}};
  pool_.push_back(root_);
  frames_.push_back({root_, false, true});
}

SceneBuilder::~SceneBuilder() {
  for (Node* n : pool_) delete n;
}

SceneBuilder::Frame& SceneBuilder::frame() { return frames_.back(); }

void SceneBuilder::charge_elements(size_t n, size_t b) {
  if (budget_)
    budget_->charge(n * (sizeof(Node) + sizeof(ScenePath) + sizeof(Element) + sizeof(Paint)) + b,
                    "the scene's elements");
}

uint32_t SceneBuilder::add_geometry(Path p) {
  if (budget_) budget_->charge(path_bytes(p), "the scene's geometry");
  scene_.geometries.push_back(std::move(p));
  return static_cast<uint32_t>(scene_.geometries.size() - 1);
}

size_t SceneBuilder::depth() const { return frames_.size() - 1; }

namespace {

bool finite(double v) { return std::isfinite(v); }
bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
bool finite(const Affine& m) { return finite(m.a) && finite(m.b) && finite(m.c) && finite(m.d) && finite(m.e) && finite(m.f); }
bool finite(const RGBA& c) { return finite(c.r) && finite(c.g) && finite(c.b) && finite(c.a); }

}  // namespace

uint32_t SceneBuilder::add_gradient(Gradient g) {
  if (g.stops.empty()) throw Error("scene: gradient without stops");
  if (!finite(g.xf) || !finite(g.p0) || !finite(g.p1) || !finite(g.focal) || !finite(g.center) ||
      !finite(g.focal_radius) || !finite(g.radius) || !finite(g.start_angle) || !finite(g.end_angle))
    throw Error("scene: gradient with a non-finite parameter");
  for (size_t i = 0; i < g.stops.size(); i++) {
    if (!finite(g.stops[i].offset) || !finite(g.stops[i].color)) throw Error("scene: gradient stop with a non-finite value");
    if (i > 0 && g.stops[i].offset < g.stops[i - 1].offset) throw Error("scene: gradient stops out of order");
  }
  scene_.gradients.push_back(std::move(g));
  return static_cast<uint32_t>(scene_.gradients.size() - 1);
}

uint32_t SceneBuilder::add_texture(Texture t) {
  const Image* im = t.image.get();
  if (!im || im->width <= 0 || im->height <= 0) throw Error("scene: texture without an image");
  const size_t n = size_t(im->width) * size_t(im->height) * 4;
  if ((im->bits == 8 && im->rgba8.size() != n) || (im->bits == 16 && im->rgba16.size() != n) ||
      (im->bits != 8 && im->bits != 16))
    throw Error("scene: texture image data does not match its size and depth");
  if (!finite(t.xf) || !finite(t.tint)) throw Error("scene: texture with a non-finite parameter");
  scene_.textures.push_back(std::move(t));
  return static_cast<uint32_t>(scene_.textures.size() - 1);
}

uint32_t SceneBuilder::add_pattern(Pattern p) {
  if (!p.tile || !(p.tile->width > 0) || !(p.tile->height > 0)) throw Error("scene: pattern without a tile");
  if (!finite(p.xf) || !finite(p.tile->width) || !finite(p.tile->height))
    throw Error("scene: pattern with a non-finite parameter");
  scene_.patterns.push_back(std::move(p));
  return static_cast<uint32_t>(scene_.patterns.size() - 1);
}

uint32_t SceneBuilder::add_mesh(Mesh m) {
  if (m.vertices.empty() || m.vertices.size() % 3 != 0) throw Error("scene: mesh without whole triangles");
  if (!finite(m.xf)) throw Error("scene: mesh with a non-finite parameter");
  for (const MeshVertex& v : m.vertices)
    if (!finite(v.p) || !finite(v.color)) throw Error("scene: mesh vertex with a non-finite value");
  for (size_t i = 0; i < m.ramp.size(); i++) {
    if (!finite(m.ramp[i].offset) || !finite(m.ramp[i].color)) throw Error("scene: mesh ramp with a non-finite value");
    if (i > 0 && m.ramp[i].offset < m.ramp[i - 1].offset) throw Error("scene: mesh ramp out of order");
  }
  if (budget_)
    budget_->charge(m.vertices.size() * sizeof(MeshVertex) + m.ramp.size() * sizeof(ColorStop), "a mesh shading");
  scene_.meshes.push_back(std::move(m));
  return static_cast<uint32_t>(scene_.meshes.size() - 1);
}

namespace {

bool finite_rect(const FilterRect& r) { return finite(r.x) && finite(r.y) && finite(r.w) && finite(r.h); }

void check_primitive(const FilterPrimitive& p, int32_t index) {
  auto input_ok = [&](int32_t in) { return in >= FILTER_STROKE_PAINT && in < index; };
  if (!input_ok(p.in) || !input_ok(p.in2)) throw Error("scene: filter primitive with an unknown input");
  for (int32_t in : p.inputs)
    if (!input_ok(in)) throw Error("scene: filter merge node with an unknown input");
  const double values[] = {p.dx, p.dy, p.std_dev_x, p.std_dev_y, p.k[0], p.k[1], p.k[2], p.k[3], p.radius_x,
                           p.radius_y, p.divisor, p.bias, p.scale, p.surface_scale, p.diffuse_constant,
                           p.specular_constant, p.specular_exponent, p.base_frequency_x, p.base_frequency_y, p.seed,
                           p.light.azimuth, p.light.elevation, p.light.x, p.light.y, p.light.z, p.light.points_at_x,
                           p.light.points_at_y, p.light.points_at_z, p.light.specular_exponent,
                           p.light.limiting_cone_angle};
  for (double v : values)
    if (!finite(v)) throw Error("scene: filter primitive with a non-finite parameter");
  for (float v : p.color)
    if (!std::isfinite(v)) throw Error("scene: filter primitive with a non-finite colour");
  for (float v : p.matrix)
    if (!std::isfinite(v)) throw Error("scene: filter colour matrix with a non-finite value");
  for (const TransferFunction& f : p.funcs)
    for (float v : f.table)
      if (!std::isfinite(v)) throw Error("scene: filter transfer table with a non-finite value");
  if (!finite_rect(p.subregion) || !finite(p.image_xf)) throw Error("scene: filter subregion not finite");
  if (p.kind == FilterKind::ConvolveMatrix &&
      (p.order_x < 1 || p.order_y < 1 || p.kernel.size() != static_cast<size_t>(p.order_x) * p.order_y ||
       p.target_x < 0 || p.target_x >= p.order_x || p.target_y < 0 || p.target_y >= p.order_y))
    throw Error("scene: filter convolution kernel of the wrong size");
  if (p.kind == FilterKind::Turbulence && p.num_octaves < 0) throw Error("scene: turbulence with negative octaves");
  // feBlend: the blend modes and plus-lighter, not the other Porter-Duff
  // operators (those are feComposite's).
  if (p.kind == FilterKind::Blend && p.blend_mode > static_cast<uint8_t>(BlendMode::PlusLighter))
    throw Error("scene: filter blend with an unknown mode");
}

}  // namespace

uint32_t SceneBuilder::add_filter(FilterEffect f) {
  if (!f.source) throw Error("scene: filter without a source");
  if (!finite(f.xf) || !finite_rect(f.region)) throw Error("scene: filter with a non-finite parameter");
  for (size_t i = 0; i < f.primitives.size(); i++) check_primitive(f.primitives[i], static_cast<int32_t>(i));
  if (budget_) budget_->charge(f.primitives.size() * sizeof(FilterPrimitive), "a filter's primitives");
  scene_.filters.push_back(std::move(f));
  return static_cast<uint32_t>(scene_.filters.size() - 1);
}

void SceneBuilder::fill(uint32_t geometry, const Affine& xf, FillRule rule, const Paint& paint, bool aliased) {
  Frame& f = frame();
  if (f.clip_context || !f.activated) throw Error("scene grammar: fill inside a clip-path");
  if (geometry >= scene_.geometries.size()) throw Error("scene: unknown geometry");
  const size_t servers = paint.type == PaintType::Solid            ? 1
                         : paint.type == PaintType::Texture        ? scene_.textures.size()
                         : paint.type == PaintType::Pattern        ? scene_.patterns.size()
                         : paint.type == PaintType::Mesh           ? scene_.meshes.size()
                         : paint.type == PaintType::Filter         ? scene_.filters.size()
                                                                   : scene_.gradients.size();
  if (paint.index >= servers) throw Error("scene: paint refers to an unknown paint server");
  charge_elements(1);
  Node* n = new Node{Node::Fill, {}, {}, {}};
  pool_.push_back(n);
  n->path.geometry = geometry;
  n->path.xf = xf;
  n->path.rule = rule;
  n->path.is_clip = false;
  n->path.aliased = aliased;
  scene_.paints.push_back(paint);
  n->path.paint = static_cast<uint32_t>(scene_.paints.size() - 1);
  f.group->content.push_back(n);
}

void SceneBuilder::stroke(uint32_t geometry, const Affine& xf, const StrokeStyle& style, const Paint& paint,
                          bool aliased) {
  charge_elements(0, sizeof(StrokeStyle) + style.dashes.size() * sizeof(double));
  fill(geometry, xf, FillRule::NonZero, paint, aliased);
  Node* n = frame().group->content.back();
  n->path.stroke = static_cast<int32_t>(scene_.strokes.size());
  scene_.strokes.push_back(style);
}

void SceneBuilder::clip(uint32_t geometry, const Affine& xf, FillRule rule, bool aliased) {
  Frame& f = frame();
  const bool in_clip_section = !f.activated;
  if (!in_clip_section && !f.clip_context) throw Error("scene grammar: clip test outside a clip-path");
  if (geometry >= scene_.geometries.size()) throw Error("scene: unknown geometry");
  charge_elements(1);
  Node* n = new Node{Node::Clip, {}, {}, {}};
  pool_.push_back(n);
  n->path.geometry = geometry;
  n->path.xf = xf;
  n->path.rule = rule;
  n->path.is_clip = true;
  n->path.aliased = aliased;
  (in_clip_section ? f.group->clip_items : f.group->content).push_back(n);
}

void SceneBuilder::clip_stroke(uint32_t geometry, const Affine& xf, const StrokeStyle& style, bool aliased) {
  charge_elements(0, sizeof(StrokeStyle) + style.dashes.size() * sizeof(double));
  clip(geometry, xf, FillRule::NonZero, aliased);
  Frame& f = frame();
  Node* n = (!f.activated ? f.group->clip_items : f.group->content).back();
  n->path.stroke = static_cast<int32_t>(scene_.strokes.size());
  scene_.strokes.push_back(style);
}

void SceneBuilder::push() {
  Frame& f = frame();
  const bool in_clip_section = !f.activated;
  charge_elements(1);
  Node* n = new Node{Node::ClipGroup, {}, {}, {}};
  pool_.push_back(n);
  const bool clip_context = in_clip_section || f.clip_context;
  (in_clip_section ? f.group->clip_items : f.group->content).push_back(n);
  frames_.push_back({n, clip_context, false});
}

void SceneBuilder::activate() {
  Frame& f = frame();
  if (frames_.size() == 1 || f.activated) throw Error("scene grammar: activate without a matching push");
  f.activated = true;
}

void SceneBuilder::pop() {
  if (frames_.size() == 1 || frame().group->kind != Node::ClipGroup)
    throw Error("scene grammar: pop without a matching push");
  if (!frame().activated) throw Error("scene grammar: pop before activate");
  frames_.pop_back();
}

void SceneBuilder::begin_group(const Group& g) {
  Frame& f = frame();
  if (f.clip_context || !f.activated) throw Error("scene grammar: group inside a clip-path");
  if (!std::isfinite(g.opacity) || !finite(g.backdrop) || !std::isfinite(g.luminance[0]) ||
      !std::isfinite(g.luminance[1]) || !std::isfinite(g.luminance[2]))
    throw Error("scene: group with a non-finite parameter");
  if (static_cast<unsigned>(g.blend) > static_cast<unsigned>(BlendMode::Xor) ||
      static_cast<unsigned>(g.mask) > static_cast<unsigned>(MaskType::Alpha) ||
      static_cast<unsigned>(g.channels[0]) > 2 || static_cast<unsigned>(g.channels[1]) > 2 ||
      static_cast<unsigned>(g.channels[2]) > 2)
    throw Error("scene: group with an unknown blend mode or mask type");
  charge_elements(1, sizeof(Group));
  Node* n = new Node{Node::Transparency, {}, {}, {}};
  pool_.push_back(n);
  n->group = static_cast<uint32_t>(scene_.groups.size());
  scene_.groups.push_back(g);
  scene_.groups.back().back_to_front = false;
  if (g.mask != MaskType::None) {
    // A mask is evaluated on its own: onto transparency, whatever it says.
    scene_.groups.back().isolated = true;
    Node* owner = f.group;
    if (owner->kind != Node::Transparency || owner->mask || !owner->content.empty())
      throw Error("scene grammar: a mask must be the first content of a group");
    owner->mask = n;
  } else {
    f.group->content.push_back(n);
  }
  frames_.push_back({n, false, true});
}

void SceneBuilder::end_group() {
  if (frames_.size() == 1 || frame().group->kind != Node::Transparency)
    throw Error("scene grammar: end_group without a matching begin_group");
  frames_.pop_back();
}

namespace {

// Groups at finish(): which fill lists must run back to front, and which
// groups change nothing.
template <class Node>
struct GroupAnalysis {
  std::vector<Group>& groups;

  // Does a child group need its backdrop when composited (a blend mode, or
  // non-isolated content that blends)?
  bool needs_backdrop(const Node* n) const {
    const Group& g = groups[n->group];
    return !composites_normally(g) || (!g.isolated && g.back_to_front);
  }
  // Does anything in a fill list (clip groups' content included) meet its
  // backdrop?
  bool blends(const std::vector<Node*>& items) const {
    for (const Node* n : items) {
      if (n->kind == Node::ClipGroup && blends(n->content)) return true;
      if (n->kind == Node::Transparency && needs_backdrop(n)) return true;
    }
    return false;
  }
  // Does a fill list (clip groups' content included) hold a source-atop
  // group, the one operator that is not its source over transparency?
  bool atop(const std::vector<Node*>& items) const {
    for (const Node* n : items) {
      if (n->kind == Node::ClipGroup && atop(n->content)) return true;
      if (n->kind == Node::Transparency && groups[n->group].blend == BlendMode::SourceAtop) return true;
    }
    return false;
  }
  bool no_op(const Node* n) const {
    const Group& g = groups[n->group];
    return g.opacity == 1 && composites_normally(g) && !n->mask && !g.knockout &&
           (!g.isolated || !g.back_to_front);
  }
  // Settles every group below the list (children first), then dissolves the
  // list's no-op groups into it (unless the list is a knockout group's).
  void list(std::vector<Node*>& items, bool knockout) {
    std::vector<Node*> out;
    for (Node* n : items) {
      if (n->kind == Node::ClipGroup) list(n->content, knockout);
      if (n->kind != Node::Transparency) {
        out.push_back(n);
        continue;
      }
      group(n);
      if (!knockout && no_op(n))
        out.insert(out.end(), n->content.begin(), n->content.end());
      else
        out.push_back(n);
    }
    items.swap(out);
  }
  void group(Node* n) {
    if (n->mask) group(n->mask);
    Group& g = groups[n->group];
    list(n->content, g.knockout);
    // An isolated knockout group composites each element onto transparency,
    // which every blend mode (and plus-lighter, xor) leaves as the element
    // itself: its list can run front to back, the top-most element that
    // covers winning. Source-atop onto transparency is nothing, which only
    // the back-to-front list computes.
    g.back_to_front = blends(n->content) && !(g.knockout && g.isolated && !atop(n->content));
    if (!g.back_to_front) g.isolated = true;  // nothing inside sees the backdrop
  }
};

struct Emitter {
  Scene& scene;

  void path(const ScenePath& p, ElementKind kind) {
    scene.paths.push_back(p);
    scene.stream.push_back({kind, static_cast<uint32_t>(scene.paths.size() - 1)});
  }
  void mark(ElementKind kind, uint32_t index = 0) { scene.stream.push_back({kind, index}); }

  template <class Node>
  void clip_list(const std::vector<Node*>& items) {
    // A union: order does not change the result; keep the input order.
    for (const Node* n : items) {
      if (n->kind == Node::Clip) {
        path(n->path, ElementKind::Clip);
      } else {
        mark(ElementKind::Push);
        clip_list(n->clip_items);
        mark(ElementKind::Activate);
        clip_list(n->content);
        mark(ElementKind::Pop);
      }
    }
  }

  template <class Node>
  void group(const Node* n) {
    mark(ElementKind::BeginGroup, n->group);
    if (n->mask) group(n->mask);
    fill_list(n->content, scene.groups[n->group].back_to_front);
    mark(ElementKind::EndGroup, n->group);
  }

  // Painter's order in; top-most first out, unless the list runs back to
  // front.
  template <class Node>
  void fill_list(const std::vector<Node*>& items, bool back_to_front) {
    const size_t n = items.size();
    for (size_t k = 0; k < n; k++) {
      const Node* it = items[back_to_front ? k : n - 1 - k];
      if (it->kind == Node::Fill) {
        path(it->path, ElementKind::Fill);
      } else if (it->kind == Node::Transparency) {
        group(it);
      } else {
        mark(ElementKind::Push);
        clip_list(it->clip_items);
        mark(ElementKind::Activate);
        fill_list(it->content, back_to_front);
        mark(ElementKind::Pop);
      }
    }
  }
};

// Groups and masks past the sample stack's depth (kMaxGroupDepth), at
// finish(): each group that would be nested deeper is dissolved into its
// parent's list, its opacity folded into the paints of everything inside
// it (exact where its fills do not overlap one another, as for a single
// path); its blend mode, knockout and mask, and a mask that would sit past
// the limit, are dropped. Counts what it flattened.
template <class Node>
struct DeepGroups {
  std::vector<Group>& groups;
  std::vector<Paint>& paints;
  size_t flattened = 0;

  // A list at `depth` groups deep (what its items are nested in).
  void list(std::vector<Node*>& items, int depth) {
    std::vector<Node*> out;
    for (Node* n : items) {
      if (n->kind == Node::ClipGroup) list(n->content, depth);
      if (n->kind != Node::Transparency) {
        out.push_back(n);
        continue;
      }
      if (depth + 1 > kMaxGroupDepth) {
        flattened++;
        fold(n->content, groups[n->group].opacity);
        out.insert(out.end(), n->content.begin(), n->content.end());
        continue;
      }
      if (n->mask && depth + 2 > kMaxGroupDepth) {
        flattened++;
        n->mask = nullptr;
      }
      if (n->mask) list(n->mask->content, depth + 2);
      list(n->content, depth + 1);
      out.push_back(n);
    }
    items.swap(out);
  }
  // Multiplies the paints of a flattened group's content by its opacity,
  // and dissolves the groups inside it the same way.
  void fold(std::vector<Node*>& items, float opacity) {
    std::vector<Node*> out;
    for (Node* n : items) {
      if (n->kind == Node::Fill) paints[n->path.paint].opacity *= opacity;
      if (n->kind == Node::ClipGroup) fold(n->content, opacity);
      if (n->kind != Node::Transparency) {
        out.push_back(n);
        continue;
      }
      flattened++;
      fold(n->content, opacity * groups[n->group].opacity);
      out.insert(out.end(), n->content.begin(), n->content.end());
    }
    items.swap(out);
  }
};

// Deepest nesting of groups in a stream.
int group_nesting(const std::vector<Element>& stream) {
  int d = 0, most = 0;
  for (const Element& e : stream) {
    if (e.kind == ElementKind::BeginGroup) most = std::max(most, ++d);
    if (e.kind == ElementKind::EndGroup) d--;
  }
  return most;
}

}  // namespace

namespace {

// Replays a finished scene's stream into a builder in painter's order: fill
// lists were reversed by finish(), clip lists kept their order.
struct Replay {
  const Scene& s;
  SceneBuilder& b;
  const Affine& xf;
  std::vector<int64_t> geometry, gradient, texture, pattern, mesh, filter;
  size_t i = 0;

  uint32_t geom(uint32_t g) {
    if (geometry[g] < 0) geometry[g] = b.add_geometry(s.geometries[g]);
    return static_cast<uint32_t>(geometry[g]);
  }
  // A paint server of s, mapped by xf and added to b on first use.
  template <class Server, class Add>
  uint32_t server(std::vector<int64_t>& added, const std::vector<Server>& from, uint32_t index, Add add) {
    if (added[index] < 0) {
      Server v = from[index];
      v.xf = xf * v.xf;
      added[index] = add(std::move(v));
    }
    return static_cast<uint32_t>(added[index]);
  }
  Paint paint(const Paint& p) {
    Paint out = p;
    switch (p.type) {
      case PaintType::Solid: break;
      case PaintType::LinearGradient:
      case PaintType::RadialGradient:
      case PaintType::SweepGradient:
        out.index = server(gradient, s.gradients, p.index, [&](Gradient g) { return b.add_gradient(std::move(g)); });
        break;
      case PaintType::Texture:
        out.index = server(texture, s.textures, p.index, [&](Texture t) { return b.add_texture(std::move(t)); });
        break;
      case PaintType::Pattern:
        out.index = server(pattern, s.patterns, p.index, [&](Pattern t) { return b.add_pattern(std::move(t)); });
        break;
      case PaintType::Mesh:
        out.index = server(mesh, s.meshes, p.index, [&](Mesh m) { return b.add_mesh(std::move(m)); });
        break;
      case PaintType::Filter:
        // The source is in s's scene units: it is mapped by xf as well.
        out.index = server(filter, s.filters, p.index, [&](FilterEffect f) {
          if (!xf.is_identity()) {
            SceneBuilder sb(f.source->width, f.source->height);
            sb.append(*f.source, xf);
            f.source = std::make_shared<const Scene>(sb.finish());
          }
          return b.add_filter(std::move(f));
        });
        break;
    }
    return out;
  }

  // The items of a list, each as [first, last) element range, up to the '|'
  // or ')' that ends it (not consumed) or the end.
  std::vector<std::pair<size_t, size_t>> items() {
    std::vector<std::pair<size_t, size_t>> out;
    while (i < s.stream.size() && s.stream[i].kind != ElementKind::Pop &&
           s.stream[i].kind != ElementKind::Activate && s.stream[i].kind != ElementKind::EndGroup) {
      const size_t first = i;
      skip_item();
      out.push_back({first, i});
    }
    return out;
  }

  // A group at stream position `at`: '(' clip-list '|' list ')'.
  void group(size_t at, bool clip_context, bool back_to_front = false) {
    b.push();
    i = at + 1;
    clip_list();
    i++;  // '|'
    b.activate();
    if (clip_context)
      clip_list();
    else
      fill_list(back_to_front);
  }

  void clip_list() {
    for (const auto& [first, last] : items()) {
      const size_t resume = last;
      const Element& e = s.stream[first];
      if (e.kind == ElementKind::Clip) {
        const ScenePath& sp = s.paths[e.path];
        if (sp.stroke >= 0)
          b.clip_stroke(geom(sp.geometry), xf * sp.xf, s.strokes[sp.stroke], sp.aliased);
        else
          b.clip(geom(sp.geometry), xf * sp.xf, sp.rule, sp.aliased);
      } else {
        group(first, true);
        b.pop();
      }
      i = resume;
    }
  }

  // A transparency group at stream position `at`: '{' mask? list '}'.
  void transparency(size_t at) {
    const Group& g = s.groups[s.stream[at].path];
    b.begin_group(g);
    i = at + 1;
    if (i < s.stream.size() && s.stream[i].kind == ElementKind::BeginGroup &&
        s.groups[s.stream[i].path].mask != MaskType::None) {
      const size_t first = i;
      skip_item();
      const size_t resume = i;
      transparency(first);
      i = resume;
    }
    fill_list(g.back_to_front);
    b.end_group();
  }
  // Moves i past the item at i: an element, or a group with its content.
  void skip_item() {
    int depth = 0;
    do {
      const ElementKind k = s.stream[i].kind;
      if (k == ElementKind::Push || k == ElementKind::BeginGroup) depth++;
      if (k == ElementKind::Pop || k == ElementKind::EndGroup) depth--;
      i++;
    } while (depth > 0);
  }

  // A fill list, stored top-most first or (back_to_front) in painter's order.
  void fill_list(bool back_to_front = false) {
    const auto list = items();
    const size_t end = i;
    const size_t n = list.size();
    for (size_t k = 0; k < n; k++) {
      const auto& item = list[back_to_front ? k : n - 1 - k];
      const Element& e = s.stream[item.first];
      if (e.kind == ElementKind::Fill) {
        const ScenePath& sp = s.paths[e.path];
        if (sp.stroke >= 0)
          b.stroke(geom(sp.geometry), xf * sp.xf, s.strokes[sp.stroke], paint(s.paints[sp.paint]), sp.aliased);
        else
          b.fill(geom(sp.geometry), xf * sp.xf, sp.rule, paint(s.paints[sp.paint]), sp.aliased);
      } else if (e.kind == ElementKind::BeginGroup) {
        transparency(item.first);
      } else {
        group(item.first, false, back_to_front);
        b.pop();
      }
    }
    i = end;
  }
};

}  // namespace

void SceneBuilder::append(const Scene& other, const Affine& xf) {
  Replay r{other,
           *this,
           xf,
           std::vector<int64_t>(other.geometries.size(), -1),
           std::vector<int64_t>(other.gradients.size(), -1),
           std::vector<int64_t>(other.textures.size(), -1),
           std::vector<int64_t>(other.patterns.size(), -1),
           std::vector<int64_t>(other.meshes.size(), -1),
           std::vector<int64_t>(other.filters.size(), -1)};
  r.fill_list();
}

Scene SceneBuilder::finish() {
  if (frames_.size() != 1) throw Error("scene grammar: unbalanced push/pop or groups at the end of the scene");
  // The stream and the lists it is made from, about 64 bytes an element.
  charge_elements(0, pool_.size() * 64);
  Scene out;
  out.width = scene_.width;
  out.height = scene_.height;
  out.geometries = std::move(scene_.geometries);
  out.strokes = std::move(scene_.strokes);
  out.paints = std::move(scene_.paints);
  out.gradients = std::move(scene_.gradients);
  out.textures = std::move(scene_.textures);
  out.patterns = std::move(scene_.patterns);
  out.meshes = std::move(scene_.meshes);
  out.filters = std::move(scene_.filters);
  out.groups = std::move(scene_.groups);
  GroupAnalysis<Node> analysis{out.groups};
  analysis.list(root_->content, false);
  if (analysis.blends(root_->content)) {
    // The top level meets its backdrop: it runs back to front inside an
    // isolated group, so that everything outside groups stays front to back.
    Node* wrap = new Node{Node::Transparency, {}, {}, {}};
    pool_.push_back(wrap);
    wrap->group = static_cast<uint32_t>(out.groups.size());
    out.groups.push_back(Group{});
    wrap->content.swap(root_->content);
    analysis.group(wrap);
    root_->content.push_back(wrap);
  }
  DeepGroups<Node> deep{out.groups, out.paints};
  deep.list(root_->content, 0);
  flattened_groups_ = deep.flattened;
  Emitter e{out};
  e.fill_list(root_->content, false);
  if (group_nesting(out.stream) > kMaxGroupDepth)
    throw Error("scene: groups and masks nested more than " + std::to_string(kMaxGroupDepth) +
                " deep (with the group around a top level that blends)");
  scene_ = Scene{};
  return out;
}

std::string flattened_groups_warning(size_t n) {
  return "groups and masks nested more than " + std::to_string(kMaxGroupDepth) + " deep: " + std::to_string(n) +
         " drawn flattened (opacity folded into their content; their masks and blend modes ignored)";
}

// ---------------------------------------------------------------- dump

namespace {

void appendf(std::string& s, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& s, const char* fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  const int n = vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n > 0) s.append(buf, static_cast<size_t>(n) < sizeof buf ? static_cast<size_t>(n) : sizeof buf - 1);
}

const char* paint_type_name(PaintType t) {
  switch (t) {
    case PaintType::Solid: return "solid";
    case PaintType::LinearGradient: return "linear";
    case PaintType::RadialGradient: return "radial";
    case PaintType::Texture: return "texture";
    case PaintType::Pattern: return "pattern";
    case PaintType::Mesh: return "mesh";
    case PaintType::Filter: return "filter";
    case PaintType::SweepGradient: return "sweep";
  }
  return "?";
}

void append_matrix(std::string& s, const Affine& m) {
  if (!m.is_identity()) appendf(s, " matrix(%g %g %g %g %g %g)", m.a, m.b, m.c, m.d, m.e, m.f);
}

void dump_into(std::string& s, const Scene& scene, const std::string& indent);

void dump_servers(std::string& s, const Scene& scene, const std::string& indent) {
  static const char* const spreads[] = {"pad", "reflect", "repeat"};
  for (size_t i = 0; i < scene.gradients.size(); i++) {
    const Gradient& g = scene.gradients[i];
    appendf(s, "%sgradient %zu linear %g %g %g %g radial %g %g %g %g %g %g %s %s", indent.c_str(), i, g.p0.x, g.p0.y,
            g.p1.x, g.p1.y, g.focal.x, g.focal.y, g.focal_radius, g.center.x, g.center.y, g.radius,
            spreads[static_cast<int>(g.spread)], g.interpolation == ColorSpace::Srgb ? "srgb" : "linearrgb");
    if (!g.extend_start || !g.extend_end) appendf(s, " extend %d %d", g.extend_start ? 1 : 0, g.extend_end ? 1 : 0);
    // The sweep's angles (around `center`) where they are not the defaults.
    if (g.start_angle != 0 || g.end_angle != 360) appendf(s, " sweep %g %g", g.start_angle, g.end_angle);
    append_matrix(s, g.xf);
    s += "\n";
    appendf(s, "%s  stops", indent.c_str());
    for (const ColorStop& st : g.stops)
      appendf(s, " %g rgba(%g,%g,%g,%g)", st.offset, st.color.r, st.color.g, st.color.b, st.color.a);
    s += "\n";
  }
  static const char* const filters[] = {"nearest", "bilinear", "bicubic"};
  static const char* const wraps[] = {"clamp", "repeat", "decal"};
  for (size_t i = 0; i < scene.textures.size(); i++) {
    const Texture& t = scene.textures[i];
    appendf(s, "%stexture %zu image %dx%dx%d %s %s %s", indent.c_str(), i, t.image->width, t.image->height,
            t.image->bits, filters[static_cast<int>(t.filter)], wraps[static_cast<int>(t.wrap_x)],
            wraps[static_cast<int>(t.wrap_y)]);
    if (t.tint.r != 1 || t.tint.g != 1 || t.tint.b != 1 || t.tint.a != 1)
      appendf(s, " tint rgba(%g,%g,%g,%g)", t.tint.r, t.tint.g, t.tint.b, t.tint.a);
    append_matrix(s, t.xf);
    s += "\n";
  }
  for (size_t i = 0; i < scene.patterns.size(); i++) {
    const Pattern& p = scene.patterns[i];
    appendf(s, "%spattern %zu", indent.c_str(), i);
    append_matrix(s, p.xf);
    s += "\n";
    dump_into(s, *p.tile, indent + "    ");
  }
  for (size_t i = 0; i < scene.meshes.size(); i++) {
    const Mesh& m = scene.meshes[i];
    appendf(s, "%smesh %zu triangles %zu", indent.c_str(), i, m.vertices.size() / 3);
    if (!m.ramp.empty()) appendf(s, " ramp %zu stops", m.ramp.size());
    append_matrix(s, m.xf);
    s += "\n";
  }
}

const char* filter_kind_name(FilterKind k) {
  static const char* const names[] = {"blend", "colormatrix", "componenttransfer", "composite", "convolvematrix",
                                      "diffuselighting", "displacementmap", "dropshadow", "flood", "gaussianblur",
                                      "image", "merge", "morphology", "offset", "specularlighting", "tile",
                                      "turbulence"};
  return names[static_cast<int>(k)];
}

void append_input(std::string& s, int32_t in) {
  static const char* const named[] = {"SourceGraphic", "SourceAlpha", "BackgroundImage", "BackgroundAlpha",
                                      "FillPaint", "StrokePaint"};
  if (in >= 0) appendf(s, " %d", in);
  else appendf(s, " %s", named[-in - 1]);
}

// A primitive's inputs and the parameters its kind reads.
void dump_primitive(std::string& s, const FilterPrimitive& p, size_t i, const std::string& indent) {
  appendf(s, "%s%zu %s", indent.c_str(), i, filter_kind_name(p.kind));
  const FilterKind k = p.kind;
  const bool two = k == FilterKind::Blend || k == FilterKind::Composite || k == FilterKind::DisplacementMap;
  const bool none = k == FilterKind::Flood || k == FilterKind::Image || k == FilterKind::Turbulence ||
                    k == FilterKind::Merge;
  if (!none) {
    s += " in";
    append_input(s, p.in);
  }
  if (two) {
    s += " in2";
    append_input(s, p.in2);
  }
  if (k == FilterKind::Merge) {
    s += " nodes";
    for (int32_t in : p.inputs) append_input(s, in);
  }
  appendf(s, " subregion %g %g %g %g%s", p.subregion.x, p.subregion.y, p.subregion.w, p.subregion.h,
          p.linear_rgb ? "" : " srgb");
  static const char* const edges[] = {"none", "duplicate", "wrap", "mirror"};
  static const char* const ops[] = {"over", "in", "out", "atop", "xor", "arithmetic", "lighter"};
  switch (k) {
    case FilterKind::Flood:
    case FilterKind::DropShadow:
      appendf(s, " color rgba(%g,%g,%g,%g)", p.color[0], p.color[1], p.color[2], p.color[3]);
      if (k == FilterKind::Flood) break;
      [[fallthrough]];
    case FilterKind::Offset:
      appendf(s, " d %g %g", p.dx, p.dy);
      if (k == FilterKind::Offset) break;
      appendf(s, " std %g %g", p.std_dev_x, p.std_dev_y);
      break;
    case FilterKind::GaussianBlur: appendf(s, " std %g %g edge %s", p.std_dev_x, p.std_dev_y, edges[int(p.edge_mode)]); break;
    case FilterKind::Blend: appendf(s, " mode %s", blend_mode_name(static_cast<BlendMode>(p.blend_mode))); break;
    case FilterKind::Composite:
      appendf(s, " op %s", ops[int(p.op)]);
      if (p.op == CompositeOp::Arithmetic) appendf(s, " k %g %g %g %g", p.k[0], p.k[1], p.k[2], p.k[3]);
      break;
    case FilterKind::ColorMatrix:
      s += " matrix";
      for (float v : p.matrix) appendf(s, " %g", v);
      break;
    case FilterKind::ComponentTransfer: {
      static const char* const types[] = {"identity", "table", "discrete", "linear", "gamma"};
      for (int c = 0; c < 4; c++) {
        const TransferFunction& f = p.funcs[c];
        appendf(s, " %c:%s", "rgba"[c], types[int(f.type)]);
        if (f.type == TransferType::Table || f.type == TransferType::Discrete)
          for (float v : f.table) appendf(s, ",%g", v);
        if (f.type == TransferType::Linear) appendf(s, ",%g,%g", f.slope, f.intercept);
        if (f.type == TransferType::Gamma) appendf(s, ",%g,%g,%g", f.amplitude, f.exponent, f.offset);
      }
      break;
    }
    case FilterKind::Morphology: appendf(s, " %s %g %g", p.dilate ? "dilate" : "erode", p.radius_x, p.radius_y); break;
    case FilterKind::ConvolveMatrix:
      appendf(s, " order %d %d target %d %d divisor %g bias %g edge %s%s kernel", p.order_x, p.order_y, p.target_x,
              p.target_y, p.divisor, p.bias, edges[int(p.edge_mode)], p.preserve_alpha ? " preserve-alpha" : "");
      for (float v : p.kernel) appendf(s, " %g", v);
      break;
    case FilterKind::DisplacementMap:
      appendf(s, " scale %g channels %c %c", p.scale, "RGBA"[p.x_channel & 3], "RGBA"[p.y_channel & 3]);
      break;
    case FilterKind::DiffuseLighting:
    case FilterKind::SpecularLighting: {
      appendf(s, " surface %g color rgba(%g,%g,%g,%g)", p.surface_scale, p.color[0], p.color[1], p.color[2],
              p.color[3]);
      if (k == FilterKind::DiffuseLighting) appendf(s, " kd %g", p.diffuse_constant);
      else appendf(s, " ks %g exponent %g", p.specular_constant, p.specular_exponent);
      const LightSource& l = p.light;
      if (l.type == LightType::Distant) appendf(s, " distant %g %g", l.azimuth, l.elevation);
      if (l.type == LightType::Point) appendf(s, " point %g %g %g", l.x, l.y, l.z);
      if (l.type == LightType::Spot) {
        appendf(s, " spot %g %g %g at %g %g %g exponent %g", l.x, l.y, l.z, l.points_at_x, l.points_at_y,
                l.points_at_z, l.specular_exponent);
        if (l.has_cone) appendf(s, " cone %g", l.limiting_cone_angle);
      }
      break;
    }
    case FilterKind::Turbulence:
      appendf(s, " %s freq %g %g octaves %d seed %g%s", p.fractal_noise ? "fractalnoise" : "turbulence",
              p.base_frequency_x, p.base_frequency_y, p.num_octaves, p.seed, p.stitch_tiles ? " stitch" : "");
      break;
    case FilterKind::Image:
      if (p.image) appendf(s, " image %dx%d", p.image->width, p.image->height);
      append_matrix(s, p.image_xf);
      if (p.image_pixelated) s += " pixelated";
      if (p.scene) s += " scene";
      break;
    case FilterKind::Merge:
    case FilterKind::Tile: break;
  }
  s += "\n";
  if (k == FilterKind::Image && p.scene) dump_into(s, *p.scene, indent + "    ");
}

void dump_filters(std::string& s, const Scene& scene, const std::string& indent) {
  for (size_t i = 0; i < scene.filters.size(); i++) {
    const FilterEffect& f = scene.filters[i];
    appendf(s, "%sfilter %zu region %g %g %g %g", indent.c_str(), i, f.region.x, f.region.y, f.region.w, f.region.h);
    append_matrix(s, f.xf);
    if (f.fill_paint[3] > 0)
      appendf(s, " fill rgba(%g,%g,%g,%g)", f.fill_paint[0], f.fill_paint[1], f.fill_paint[2], f.fill_paint[3]);
    if (f.stroke_paint[3] > 0)
      appendf(s, " stroke rgba(%g,%g,%g,%g)", f.stroke_paint[0], f.stroke_paint[1], f.stroke_paint[2],
              f.stroke_paint[3]);
    s += "\n";
    for (size_t k = 0; k < f.primitives.size(); k++) dump_primitive(s, f.primitives[k], k, indent + "  ");
    appendf(s, "%s  source\n", indent.c_str());
    dump_into(s, *f.source, indent + "    ");
  }
}

void dump_groups(std::string& s, const Scene& scene, const std::string& indent) {
  for (size_t i = 0; i < scene.groups.size(); i++) {
    const Group& g = scene.groups[i];
    appendf(s, "%sgroup %zu opacity %g %s%s%s", indent.c_str(), i, g.opacity, blend_mode_name(g.blend),
            g.isolated ? "" : " non-isolated", g.knockout ? " knockout" : "");
    if (g.mask == MaskType::Alpha) s += " mask alpha";
    if (!(g.channels[0] == ChannelRule::Blend && g.channels[1] == ChannelRule::Blend &&
          g.channels[2] == ChannelRule::Blend)) {
      s += " channels";
      for (ChannelRule r : g.channels)
        s += r == ChannelRule::Blend ? " blend" : r == ChannelRule::Source ? " source" : " backdrop";
    }
    if (g.subtractive) s += " subtractive";
    if (g.mask == MaskType::Luminance) {
      appendf(s, " mask luminance %g %g %g %s", g.luminance[0], g.luminance[1], g.luminance[2],
              g.luminance_space == ColorSpace::Srgb ? "srgb" : "linearrgb");
      if (g.backdrop.a != 0)
        appendf(s, " backdrop rgba(%g,%g,%g,%g)", g.backdrop.r, g.backdrop.g, g.backdrop.b, g.backdrop.a);
    }
    if (g.back_to_front) s += " back-to-front";
    s += "\n";
  }
}

void dump_into(std::string& s, const Scene& scene, const std::string& indent) {
  const char* in = indent.c_str();
  appendf(s, "%sscene %g %g\n", in, scene.width, scene.height);
  for (size_t i = 0; i < scene.paths.size(); i++) {
    const ScenePath& sp = scene.paths[i];
    appendf(s, "%spath %zu %s %s", in, i, sp.is_clip ? "clip" : "fill",
            sp.rule == FillRule::NonZero ? "nonzero" : "evenodd");
    if (!sp.is_clip) {
      const Paint& p = scene.paints[sp.paint];
      if (p.type == PaintType::Solid)
        appendf(s, " rgba(%g,%g,%g,%g) opacity %g", p.color.r, p.color.g, p.color.b, p.color.a, p.opacity);
      else
        appendf(s, " %s %u opacity %g", paint_type_name(p.type), p.index, p.opacity);
    }
    if (sp.aliased) s += " aliased";
    if (sp.stroke >= 0) {
      static const char* joins[] = {"miter", "miter-clip", "arcs", "round", "bevel"};
      static const char* caps[] = {"butt", "round", "square"};
      const StrokeStyle& st = scene.strokes[sp.stroke];
      appendf(s, " stroke %g %s %s %g", st.width, joins[static_cast<int>(st.join)], caps[static_cast<int>(st.cap)],
              st.miter_limit);
      if (!st.dashes.empty()) {
        s += " dashes";
        for (double d : st.dashes) appendf(s, " %g", d);
        appendf(s, " offset %g", st.dash_offset);
      }
    }
    append_matrix(s, sp.xf);
    s += "\n";
    const Path& g = scene.geometries[sp.geometry];
    for (const Path::Contour& c : g.contours()) {
      const Vec2 p0 = g.points()[c.start_point];
      appendf(s, "%s  M %g %g", in, p0.x, p0.y);
      for (uint32_t k = 0; k < c.segment_count; k++) {
        const Path::Segment& seg = g.segments()[c.first_segment + k];
        const Vec2* p = &g.points()[seg.first_point];
        switch (seg.type) {
          case SegmentType::Line: appendf(s, " L %g %g", p[1].x, p[1].y); break;
          case SegmentType::Quad: appendf(s, " Q %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y); break;
          case SegmentType::RQuad:
            appendf(s, " R %g %g %g %g w %g", p[1].x, p[1].y, p[2].x, p[2].y, g.weights()[seg.first_weight]);
            break;
          case SegmentType::Cubic:
            appendf(s, " C %g %g %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
            break;
          case SegmentType::RCubic:
            appendf(s, " RC %g %g %g %g %g %g", p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y);
            break;
        }
      }
      if (c.closed) s += " Z";
      s += "\n";
    }
  }
  dump_servers(s, scene, indent);
  dump_filters(s, scene, indent);
  dump_groups(s, scene, indent);
  s += indent + "stream";
  for (const Element& e : scene.stream) {
    switch (e.kind) {
      case ElementKind::Push: s += " ("; break;
      case ElementKind::Activate: s += " |"; break;
      case ElementKind::Pop: s += " )"; break;
      case ElementKind::Fill: appendf(s, " F%u", e.path); break;
      case ElementKind::Clip: appendf(s, " C%u", e.path); break;
      case ElementKind::BeginGroup: appendf(s, " {%u", e.path); break;
      case ElementKind::EndGroup: s += " }"; break;
    }
  }
  s += "\n";
}

}  // namespace

const char* blend_mode_name(BlendMode m) {
  static const char* const names[] = {"normal",       "multiply",    "screen",     "overlay",    "darken",
                                      "lighten",      "color-dodge", "color-burn", "hard-light", "soft-light",
                                      "difference",   "exclusion",   "hue",        "saturation", "color",
                                      "luminosity",   "plus-lighter", "source-atop", "xor"};
  static_assert(sizeof names / sizeof names[0] == static_cast<size_t>(BlendMode::Xor) + 1, "a name per mode");
  const auto i = static_cast<size_t>(m);
  return i < sizeof names / sizeof names[0] ? names[i] : "?";
}

std::string dump(const Scene& scene) {
  std::string s;
  dump_into(s, scene, "");
  return s;
}

}  // namespace mpvg

namespace mpvg {

namespace {

// Each tile once: a tile shared by many patterns is not walked again.
bool aliased_in(const Scene& scene, std::unordered_set<const Scene*>& seen) {
  if (!seen.insert(&scene).second) return false;
  for (const ScenePath& p : scene.paths)
    if (p.aliased) return true;
  for (const Pattern& p : scene.patterns)
    if (p.tile && aliased_in(*p.tile, seen)) return true;
  for (const FilterEffect& f : scene.filters)
    if (f.source && aliased_in(*f.source, seen)) return true;
  return false;
}

}  // namespace

bool has_aliased_paths(const Scene& scene) {
  std::unordered_set<const Scene*> seen;
  return aliased_in(scene, seen);
}

}  // namespace mpvg
