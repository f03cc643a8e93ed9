// SceneBuilder: how frontends make a Scene (core/scene.h, paper §3). It
// takes content in painter's order, checks the grammar of core/scene.h,
// decides which groups run back to front, dissolves groups that change
// nothing or are nested too deep, and reverses every other fill* list when
// it finishes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/memory_budget.h"
#include "core/scene.h"

namespace mpvg {

// Builds a Scene from painter's-order content, enforcing the grammar above.
// Misuse (e.g. fill() inside a clip section, unbalanced push/pop) throws
// mpvg::Error.
class SceneBuilder {
 public:
  SceneBuilder(double width, double height);
  // Charges what the scene holds to `budget` as it grows, before it grows
  // (frontends that build into the builder as they read: PDF pages);
  // null (the default): nothing is counted. Throws ResourceError past it.
  void set_budget(MemoryBudget* budget) { budget_ = budget; }
  MemoryBudget* budget() const { return budget_; }
  ~SceneBuilder();
  SceneBuilder(const SceneBuilder&) = delete;
  SceneBuilder& operator=(const SceneBuilder&) = delete;

  uint32_t add_geometry(Path p);

  // Paint servers, referred to by Paint::index. Invalid ones (no stops,
  // non-finite numbers, a missing or inconsistent image, an empty tile)
  // throw mpvg::Error.
  uint32_t add_gradient(Gradient g);
  uint32_t add_texture(Texture t);
  uint32_t add_pattern(Pattern p);
  uint32_t add_mesh(Mesh m);
  // A filter effect (core/filters/filter.h): its source, region and primitives are
  // checked (inputs refer to earlier primitives, finite parameters).
  uint32_t add_filter(FilterEffect f);

  // A filled path, drawn over what came before it. `aliased`: see
  // ScenePath::aliased (clip tests take it too).
  void fill(uint32_t geometry, const Affine& xf, FillRule rule, const Paint& paint, bool aliased = false);
  // The stroke of a path (its centreline `geometry`, in the user space xf
  // maps to scene units), drawn like a fill.
  void stroke(uint32_t geometry, const Affine& xf, const StrokeStyle& style, const Paint& paint, bool aliased = false);

  // push(): start a clip group. Until activate(), the group's clip-path area
  // is the union of clip() tests and nested groups. After activate(), its
  // content follows: fills (in a fill context) or clip-paths (when the group
  // is itself a clip-path). pop() ends the group.
  void push();
  void clip(uint32_t geometry, const Affine& xf, FillRule rule, bool aliased = false);
  // A clip test with the stroke of a centreline (PDF's stroked text and
  // paths as clips).
  void clip_stroke(uint32_t geometry, const Affine& xf, const StrokeStyle& style, bool aliased = false);
  void activate();
  void pop();

  // Nesting depth of open clip groups and transparency groups (0 at the
  // top level).
  size_t depth() const;

  // begin_group(): a transparency group, in a fill context, whose content
  // follows until end_group(). A group whose Group::mask is set is a mask:
  // it may only be the first content of another group, and holds fills.
  // Transparency groups and masks are evaluated per sample at most
  // kMaxGroupDepth deep (core/paint/group.h; a scene whose top level needs a
  // back-to-front group gets one around it, which counts too): finish()
  // dissolves groups nested deeper into their parents' lists, their
  // opacity folded into the paints of their content (exact where those
  // fills do not overlap), their blend modes, knockout and masks dropped,
  // and counts them (flattened_groups(): frontends warn). A non-finite
  // opacity or a misplaced mask throw mpvg::Error.
  //
  // finish() dissolves groups that change nothing (opacity 1, normal
  // blending, no mask, not knockout, in a parent that is not knockout, and
  // isolated only where nothing inside blends), marks non-isolated groups
  // whose content does not blend as isolated (the same result), and sets
  // Group::back_to_front.
  void begin_group(const Group& g);
  void end_group();

  // Appends the whole content of `other`, mapped by `xf` (other's units to
  // ours), in a fill context: its geometry, paints and paint servers (their
  // transforms composed with xf), clip groups and fills, in the same order.
  // Embeds one document in another (an SVG <image> of an SVG file).
  void append(const Scene& other, const Affine& xf);

  Scene finish();
  // Groups and masks the last finish() flattened or dropped for nesting
  // past kMaxGroupDepth.
  size_t flattened_groups() const { return flattened_groups_; }

 private:
  struct Node;
  struct Frame;
  Node* current();
  Frame& frame();

  // Charges for n elements (their nodes, paths and paints) and b bytes more.
  void charge_elements(size_t n, size_t b = 0);

  Scene scene_;
  MemoryBudget* budget_ = nullptr;
  std::vector<Node*> pool_;
  std::vector<Frame> frames_;
  Node* root_ = nullptr;
  size_t flattened_groups_ = 0;
};

// The warning frontends give when SceneBuilder::flattened_groups() is n > 0.
std::string flattened_groups_warning(size_t n);

}  // namespace mpvg
