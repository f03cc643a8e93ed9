#include "frame/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/paint/group.h"

namespace mpvg {

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

}  // namespace mpvg
