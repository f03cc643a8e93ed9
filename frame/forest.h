// Forest frames (issue 27): several scenes rendered by one pass of the
// pipeline. Each scene keeps its own coordinates and its own grid of unit
// areas. Their encodings are concatenated (paths, segments, strokes, paint
// tables and pattern tiles, every index shifted), and the shortcut tree gets
// one root per scene: nodes 0 .. n-1, with Cell::root naming the scene of
// every cell. Stroking, abstraction, subdivision and pruning then run once
// over all of them, the per-frame cost of launches and host round trips
// paid once, while no cell ever mixes two scenes.
//
// Each root's tree is the tree its scene gets in a frame of its own, so that
// each scene renders to the same image, byte for byte (the tree's shape
// decides which unit areas are sampled as uniform leaves, which rounds
// differently): the roots share one root square (same_frame_grid), each has
// the coarse grid of its own density (in_root_grid, core/tree/tree.h) and its
// own sampler specialisation (SceneRoot::kinds), and a forest whose tree
// would pass TreeParams::max_entries is refused (kForestCapped) rather
// than built coarser.
#pragma once
#include <cstddef>
#include <vector>

#include "frame/encoding.h"

namespace mpvg {

// Cell::root is 16 bits.
constexpr size_t kMaxForestRoots = 65535;

// One scene of a forest, before the merge: the scene as encode() made it
// (one scene, not a forest) and its grid of unit areas.
struct ForestScene {
  const EncodedScene* scene = nullptr;
  int width = 0, height = 0;
};

// The scenes as one forest, in order (scene k is root k), each copied once
// into arrays sized for all of them. Throws mpvg::Error for more than
// kMaxForestRoots scenes, for one that is already a forest, or when the
// paths together are more than entries can name.
EncodedScene make_forest(const std::vector<ForestScene>& scenes);

// The roots of a scene: a forest's, or the whole stream as one root over
// width x height unit areas.
std::vector<SceneRoot> scene_roots(const EncodedScene& scene, int width, int height);

// The grid a forest's tree is built over: every root square has the side
// the largest of its scenes needs (core/tree/tree.h, tree_root_size).
void forest_grid(const EncodedScene& forest, int& width, int& height);

}  // namespace mpvg
