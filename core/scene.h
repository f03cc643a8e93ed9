// The scene model (paper §3).
//
// A scene is a stream of elements described by the grammar
//
//   scene     -> fill*                        (the dummy root push/pop is implicit)
//   fill      -> F | ( clip-path* | fill* )
//   clip-path -> C | ( clip-path* | clip-path* )
//
// where F is a filled path, C a clip test, and '(' '|' ')' are push, activate
// and pop. A clip-path area is the union of the clip-paths before its '|';
// nesting is intersection. Internally the stream is stored top-most first,
// so that samples can be blended front to back and stop once opaque.
//
// Frontends never write the stream directly: they use SceneBuilder, which
// takes content in painter's (back-to-front) order, checks the grammar, and
// reverses every fill* list when it finishes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace mpvg {

enum class SegmentType : uint8_t {
  Line,    // 2 control points
  Quad,    // integral quadratic, 3 control points
  RQuad,   // rational quadratic (conic), 3 control points + weight of the middle one
  Cubic,   // integral cubic, 4 control points
  RCubic,  // rational cubic: representable, rejected by abstraction (paper §2)
};

inline int segment_degree(SegmentType t) {
  switch (t) {
    case SegmentType::Line: return 1;
    case SegmentType::Quad:
    case SegmentType::RQuad: return 2;
    default: return 3;
  }
}

enum class FillRule : uint8_t { NonZero, EvenOdd };

// Path geometry in user space: a list of contours, each a chain of segments
// sharing endpoints. Segment i of a contour uses points[first_point ..
// first_point + degree]; the next segment starts at its last point.
class Path {
 public:
  struct Segment {
    SegmentType type;
    uint32_t first_point;
    uint32_t first_weight;  // index into weights (RQuad: 1, RCubic: 4), or 0
  };
  struct Contour {
    uint32_t first_segment = 0;
    uint32_t segment_count = 0;
    uint32_t start_point = 0;
    bool closed = false;  // an explicit close ('Z'); fills close every contour anyway
  };

  void move_to(Vec2 p);
  void line_to(Vec2 p);
  void quad_to(Vec2 p1, Vec2 p2);
  void rquad_to(Vec2 p1, Vec2 p2, double w);
  void cubic_to(Vec2 p1, Vec2 p2, Vec2 p3);
  void rcubic_to(Vec2 p1, Vec2 p2, Vec2 p3, double w0, double w1, double w2, double w3);
  void close();

  bool empty() const { return segments_.empty(); }
  Vec2 current_point() const { return points_.empty() ? Vec2{} : points_.back(); }
  bool has_current_point() const { return !points_.empty(); }

  const std::vector<Vec2>& points() const { return points_; }
  const std::vector<double>& weights() const { return weights_; }
  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<Contour>& contours() const { return contours_; }

  // Contour i alone, as a path of its own (the same commands replayed).
  Path contour_path(size_t i) const;
  // Appends the contours of `other`, as if its commands followed ours.
  void append(const Path& other);

 private:
  void ensure_contour();
  void add_segment(SegmentType t, uint32_t first_weight);

  std::vector<Vec2> points_;
  std::vector<double> weights_;
  std::vector<Segment> segments_;
  std::vector<Contour> contours_;
  bool open_contour_ = false;
};

// Straight (non-premultiplied) RGBA with sRGB-encoded components in [0, 1].
struct RGBA {
  float r = 0, g = 0, b = 0, a = 1;
};

// Paints are evaluated per sample (sampling.h). Only solid colours exist so
// far; gradients and textures will add kinds and an index into their tables.
enum class PaintType : uint8_t { Solid };

struct Paint {
  PaintType type = PaintType::Solid;
  RGBA color;
  float opacity = 1;  // multiplies color.a (fill-opacity × opacity)
};

// One path instance of the stream: geometry, its transform to scene units,
// fill rule, and for fills the paint.
struct ScenePath {
  uint32_t geometry = 0;
  Affine xf;
  FillRule rule = FillRule::NonZero;
  bool is_clip = false;
  uint32_t paint = 0;  // fills only
};

enum class ElementKind : uint8_t { Push, Activate, Pop, Fill, Clip };

struct Element {
  ElementKind kind;
  uint32_t path;  // Fill and Clip: index into Scene::paths
};

struct Scene {
  double width = 0, height = 0;  // intrinsic size, in scene units (CSS px)
  std::vector<Path> geometries;
  std::vector<ScenePath> paths;  // indexed by Element::path; stream order
  std::vector<Paint> paints;
  std::vector<Element> stream;   // top-most first

  // Number of input segments over all path instances (an instance counts its
  // geometry again), plus the closing lines that fills add.
  size_t segment_count() const;
};

// Builds a Scene from painter's-order content, enforcing the grammar above.
// Misuse (e.g. fill() inside a clip section, unbalanced push/pop) throws
// mpvg::Error.
class SceneBuilder {
 public:
  SceneBuilder(double width, double height);
  ~SceneBuilder();
  SceneBuilder(const SceneBuilder&) = delete;
  SceneBuilder& operator=(const SceneBuilder&) = delete;

  uint32_t add_geometry(Path p);

  // A filled path, drawn over what came before it.
  void fill(uint32_t geometry, const Affine& xf, FillRule rule, const Paint& paint);

  // push(): start a clip group. Until activate(), the group's clip-path area
  // is the union of clip() tests and nested groups. After activate(), its
  // content follows: fills (in a fill context) or clip-paths (when the group
  // is itself a clip-path). pop() ends the group.
  void push();
  void clip(uint32_t geometry, const Affine& xf, FillRule rule);
  void activate();
  void pop();

  // Nesting depth of open groups (0 at the top level).
  size_t depth() const;

  Scene finish();

 private:
  struct Node;
  struct Frame;
  Node* current();
  Frame& frame();

  Scene scene_;
  std::vector<Node*> pool_;
  std::vector<Frame> frames_;
  Node* root_ = nullptr;
};

// A text dump of a scene: sizes, every path with its geometry, and the
// stream, one element a line. Parser tests compare dumps with expected text.
std::string dump(const Scene& scene);

}  // namespace mpvg
