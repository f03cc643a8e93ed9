// The scene model: SceneBuilder::append replays a finished scene into
// another in the same order, its paint servers' transforms composed.
#include <memory>

#include "core/scene.h"
#include "tests/catch.h"
#include "tests/random_scenes.h"

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
