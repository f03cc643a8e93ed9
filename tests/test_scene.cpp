// The scene model: SceneBuilder::append replays a finished scene into
// another in the same order, its paint servers' transforms composed.
#include <memory>

#include "core/scene.h"
#include "tests/catch.h"
#include "tests/random_scenes.h"
#include "frame/scene_builder.h"
#include "frame/scene_info.h"

using namespace mpvg;

TEST_CASE("append replays a scene element for element", "[scene]") {
  for (uint32_t seed = 1; seed <= 40; seed++) {
    INFO("seed " << seed);
    const Scene s = random_scenes::clip_scene(seed, 3, 50, seed % 2 == 0);
    SceneBuilder b(s.width, s.height);
    b.append(s, Affine{});
    const Scene copy = b.finish();
    CHECK(dump(copy) == dump(s));
  }
}

TEST_CASE("append maps geometry and paint servers by the transform", "[scene]") {
  SceneBuilder inner(10, 10);
  Path p;
  p.move_to({0, 0});
  p.line_to({10, 0});
  p.line_to({0, 10});
  p.close();
  Gradient g;
  g.p0 = {0, 0};
  g.p1 = {10, 0};
  g.stops = {{0, RGBA{1, 0, 0, 1}}, {1, RGBA{0, 0, 1, 1}}};
  Paint paint;
  paint.type = PaintType::LinearGradient;
  paint.index = inner.add_gradient(g);
  inner.push();
  inner.clip(inner.add_geometry(p), Affine{}, FillRule::EvenOdd);
  inner.activate();
  inner.fill(inner.add_geometry(p), Affine::scale(2, 2), FillRule::NonZero, paint);
  inner.pop();
  const Scene in = inner.finish();

  SceneBuilder outer(100, 100);
  const Affine xf = Affine::translate(5, 7);
  outer.append(in, xf);
  const Scene out = outer.finish();
  CHECK(dump(out) == R"(scene 100 100
path 0 clip evenodd matrix(1 0 0 1 5 7)
  M 0 0 L 10 0 L 0 10 L 0 0 Z
path 1 fill nonzero linear 0 opacity 1 matrix(2 0 0 2 5 7)
  M 0 0 L 10 0 L 0 10 L 0 0 Z
gradient 0 linear 0 0 10 0 radial 0 0 0 0 0 0 pad srgb matrix(1 0 0 1 5 7)
  stops 0 rgba(1,0,0,1) 1 rgba(0,0,1,1)
stream ( C0 | F1 )
)");
}

namespace {

void fill_square(SceneBuilder& b, double x0, float r) {
  Paint p;
  p.color = RGBA{r, 0, 0, 1};
  b.fill(b.add_geometry(oracle::rect(x0, 0, x0 + 4, 4)), Affine{}, FillRule::NonZero, p);
}

// The stream line of a dump.
std::string stream_of(const Scene& s) {
  const std::string d = dump(s);
  return d.substr(d.rfind("stream"));
}

}  // namespace

TEST_CASE("groups: lists run front to back unless a blend mode needs its backdrop", "[scene][groups]") {
  SceneBuilder b(10, 10);
  fill_square(b, 0, 0.1f);
  Group g;
  g.opacity = 0.5f;
  b.begin_group(g);
  fill_square(b, 1, 0.2f);
  fill_square(b, 2, 0.3f);
  b.end_group();
  fill_square(b, 3, 0.4f);
  const Scene s = b.finish();
  // Top-most first everywhere: F0 is the last square, the group's list reversed too.
  CHECK(stream_of(s) == "stream F0 {0 F1 F2 } F3\n");
  CHECK_FALSE(s.groups[0].back_to_front);
  CHECK(s.paints[s.paths[1].paint].color.r == 0.3f);
}

TEST_CASE("groups: a blend mode makes its list back to front; the top level is wrapped", "[scene][groups]") {
  SceneBuilder b(10, 10);
  fill_square(b, 0, 0.1f);
  Group outer;
  outer.opacity = 0.5f;
  b.begin_group(outer);
  fill_square(b, 1, 0.2f);
  Group multiply;
  multiply.blend = BlendMode::Multiply;
  b.begin_group(multiply);
  fill_square(b, 2, 0.3f);
  fill_square(b, 3, 0.4f);
  b.end_group();
  b.end_group();
  const Scene s = b.finish();
  // outer's list runs back to front (painter's order: F0 then the multiply
  // group); the multiply group's own list is front to back. The top level
  // does not blend: no wrapper.
  CHECK(stream_of(s) == "stream {0 F0 {1 F1 F2 } } F3\n");
  CHECK(s.groups[0].back_to_front);
  CHECK_FALSE(s.groups[1].back_to_front);

  SceneBuilder top(10, 10);
  fill_square(top, 0, 0.1f);
  top.begin_group(multiply);
  fill_square(top, 1, 0.2f);
  top.end_group();
  const Scene t = top.finish();
  REQUIRE(t.groups.size() == 2);
  CHECK(stream_of(t) == "stream {1 F0 {0 F1 } }\n");
  CHECK(t.groups[1].back_to_front);
  CHECK(t.groups[1].blend == BlendMode::Normal);
}

TEST_CASE("groups: no-op groups are dissolved, non-isolated ones that do not blend become isolated",
          "[scene][groups]") {
  SceneBuilder b(10, 10);
  Group noop;
  b.begin_group(noop);
  fill_square(b, 0, 0.1f);
  Group faded;
  faded.opacity = 0.5f;
  faded.isolated = false;
  b.begin_group(faded);
  fill_square(b, 1, 0.2f);
  b.end_group();
  b.end_group();
  Group knockout;
  knockout.knockout = true;
  b.begin_group(knockout);
  b.begin_group(noop);  // kept: its fills would knock each other out if dissolved
  fill_square(b, 2, 0.3f);
  fill_square(b, 3, 0.4f);
  b.end_group();
  b.end_group();
  const Scene s = b.finish();
  CHECK(stream_of(s) == "stream {2 {3 F0 F1 } } {1 F2 } F3\n");
  CHECK(s.groups[1].isolated);
}

TEST_CASE("groups: masks come first, misuse is an error", "[scene][groups]") {
  SceneBuilder b(10, 10);
  Group g;
  b.begin_group(g);
  Group m;
  m.mask = MaskType::Alpha;
  b.begin_group(m);
  fill_square(b, 0, 1.0f);
  b.end_group();
  fill_square(b, 1, 0.2f);
  fill_square(b, 2, 0.3f);
  CHECK_THROWS_WITH(b.begin_group(m), Catch::Contains("first content"));
  b.end_group();
  const Scene s = b.finish();
  CHECK(stream_of(s) == "stream {0 {1 F0 } F1 F2 }\n");


  SceneBuilder clip(10, 10);
  clip.push();
  CHECK_THROWS_WITH(clip.begin_group(g), Catch::Contains("inside a clip-path"));
  SceneBuilder bad(10, 10);
  CHECK_THROWS_WITH(bad.end_group(), Catch::Contains("without a matching begin_group"));
  bad.begin_group(g);
  CHECK_THROWS_WITH(bad.pop(), Catch::Contains("pop without a matching push"));
  CHECK_THROWS_WITH(bad.finish(), Catch::Contains("unbalanced"));
}

TEST_CASE("groups: append replays groups and masks in the same order", "[scene][groups]") {
  SceneBuilder b(10, 10);
  fill_square(b, 0, 0.1f);
  Group outer;
  outer.opacity = 0.5f;
  b.begin_group(outer);
  Group m;
  m.mask = MaskType::Luminance;
  b.begin_group(m);
  fill_square(b, 1, 1.0f);
  b.end_group();
  fill_square(b, 2, 0.2f);
  Group screen;
  screen.blend = BlendMode::Screen;
  b.begin_group(screen);
  fill_square(b, 3, 0.3f);
  b.end_group();
  b.end_group();
  const Scene s = b.finish();
  SceneBuilder c(10, 10);
  c.append(s, Affine{});
  const Scene copy = c.finish();
  CHECK(dump(copy) == dump(s));
}
