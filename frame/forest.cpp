// Forest frames: the merge of encoded scenes (frame/forest.h).
#include "frame/forest.h"

#include <algorithm>
#include <memory>

#include "core/error.h"
#include "core/sampling/sampling.h"

namespace mpvg {

namespace {

template <class T>
void append(std::vector<T>& dst, const std::vector<T>& src) {
  dst.insert(dst.end(), src.begin(), src.end());
}

uint32_t u32(size_t n) { return static_cast<uint32_t>(n); }

// Where the records of the scene being appended start in the merged tables.
struct Offsets {
  uint32_t paths = 0, paints = 0, groups = 0;
  uint32_t gradients = 0, ramp = 0, textures = 0, levels = 0, texels = 0, patterns = 0, tiles = 0;
  uint32_t meshes = 0, mesh_triangles = 0, mesh_cells = 0, mesh_items = 0;
};

Offsets offsets_of(const EncodedScene& forest, const PaintData& p) {
  Offsets o;
  o.paths = u32(forest.paths.size());
  o.paints = u32(p.paints.size());
  o.groups = u32(p.groups.size());
  o.gradients = u32(p.gradients.size());
  o.ramp = u32(p.ramp_t.size());
  o.textures = u32(p.textures.size());
  o.levels = u32(p.levels.size());
  o.texels = u32(p.texels.size());
  o.patterns = u32(p.patterns.size());
  o.tiles = u32(forest.tiles.size());
  o.meshes = u32(p.meshes.size());
  o.mesh_triangles = u32(p.mesh_triangles.size());
  o.mesh_cells = u32(p.mesh_cells.size());
  o.mesh_items = u32(p.mesh_items.size());
  return o;
}

void append_paint(PaintData& dst, const PaintData& src, const Offsets& o) {
  for (PaintRecord r : src.paints) {
    switch (r.kind) {
      case PAINT_LINEAR:
      case PAINT_RADIAL:
      case PAINT_SWEEP: r.index += o.gradients; break;
      case PAINT_TEXTURE: r.index += o.textures; break;
      case PAINT_PATTERN: r.index += o.patterns; break;
      case PAINT_MESH: r.index += o.meshes; break;
      default: break;
    }
    dst.paints.push_back(r);
  }
  for (GradientRecord g : src.gradients) {
    g.first += o.ramp;
    dst.gradients.push_back(g);
  }
  append(dst.ramp_t, src.ramp_t);
  append(dst.ramp_color, src.ramp_color);
  for (TextureRecord t : src.textures) {
    t.level0 += o.levels;
    dst.textures.push_back(t);
  }
  for (TextureLevel l : src.levels) {
    l.offset += o.texels;
    dst.levels.push_back(l);
  }
  append(dst.texels, src.texels);
  for (PatternRecord p : src.patterns) {
    p.tree += o.tiles;
    dst.patterns.push_back(p);
  }
  append(dst.groups, src.groups);
  for (MeshRecord m : src.meshes) {
    m.cells += o.mesh_cells;
    if (m.ramp != kNoMeshRamp) m.ramp += o.gradients;
    dst.meshes.push_back(m);
  }
  append(dst.mesh_triangles, src.mesh_triangles);
  for (uint32_t c : src.mesh_cells) dst.mesh_cells.push_back(c + o.mesh_items);
  for (uint32_t i : src.mesh_items) dst.mesh_items.push_back(i + o.mesh_triangles);
  dst.aliased = dst.aliased || src.aliased;
}

// A stream's references into the shared tables: fills' paints and group
// records (path ids are the scene's own in a tile, shifted by `paths` in
// the top-level stream).
void shift_stream(std::vector<Entry>& stream, const std::vector<Entry>& src, uint32_t paths, uint32_t groups) {
  for (Entry e : src) {
    if (entry_kind(e) == ENTRY_GROUP) {
      e.data += groups;
    } else if (!entry_is_delimiter(e)) {
      e = make_entry(entry_kind(e), entry_path(e) + paths, e.data);
    }
    stream.push_back(e);
  }
}

void shift_paths(std::vector<PathRecord>& dst, const std::vector<PathRecord>& src, uint32_t paints) {
  for (PathRecord p : src) {
    if (!(p.flags & PATH_CLIP)) p.paint += paints;
    dst.push_back(p);
  }
}

void append_strokes(StrokeBatch& dst, const StrokeBatch& src, uint32_t paths) {
  const uint32_t strokes = u32(dst.strokes.size()), subpaths = u32(dst.subpaths.size());
  const uint32_t segments = u32(dst.segments.size()), dashes = u32(dst.dashes.size());
  for (stroking::StrokeRecord r : src.strokes) {
    r.dash_first += dashes;
    r.path += paths;
    dst.strokes.push_back(r);
  }
  for (stroking::StrokeSubpath s : src.subpaths) {
    s.stroke += strokes;
    s.first_segment += segments;
    s.first_vertex += dst.nvertices;
    dst.subpaths.push_back(s);
  }
  for (stroking::StrokeSegment s : src.segments) {
    s.subpath += subpaths;
    dst.segments.push_back(s);
  }
  append(dst.dashes, src.dashes);
  append(dst.dash_ends, src.dash_ends);
  for (uint32_t e : src.first_element) dst.first_element.push_back(e + dst.nelements);
  dst.nvertices += src.nvertices;
  dst.nelements += src.nelements;
}

}  // namespace

EncodedScene make_forest(const std::vector<ForestScene>& scenes) {
  if (scenes.size() > kMaxForestRoots)
    throw Error("a forest frame takes at most " + std::to_string(kMaxForestRoots) + " scenes");
  EncodedScene out;
  auto paint = std::make_shared<PaintData>();
  size_t segments = 0, paths = 0, stream = 0;
  for (const ForestScene& fs : scenes) {
    if (fs.scene->paint && !fs.scene->paint->device_texels.empty())
      throw Error("a forest frame cannot hold a scene with device texels (filter layers rendered on a GPU)");
    segments += fs.scene->segments.size();
    paths += fs.scene->paths.size();
    stream += fs.scene->stream.size();
  }
  out.segments.reserve(segments);
  out.paths.reserve(paths);
  out.stream.reserve(stream);
  for (const ForestScene& fs : scenes) {
    const EncodedScene& s = *fs.scene;
    if (!s.roots.empty()) throw Error("a forest frame's scenes are single scenes");
    static const PaintData none;
    const PaintData& sp = s.paint ? *s.paint : none;
    const Offsets o = offsets_of(out, *paint);
    if (size_t(o.paths) + s.paths.size() > kMaxPaths) throw Error("a forest frame has more paths than entries can name");
    for (InputSegment seg : s.segments) {
      seg.path += o.paths;
      out.segments.push_back(seg);
    }
    append_strokes(out.strokes, s.strokes, o.paths);
    shift_paths(out.paths, s.paths, o.paints);
    SceneRoot root = scene_roots(s, fs.width, fs.height).front();  // its grid and sampler kinds
    root.stream_begin = u32(out.stream.size());
    shift_stream(out.stream, s.stream, o.paths, o.groups);
    root.stream_end = u32(out.stream.size());
    out.roots.push_back(root);
    out.input_segment_count += s.input_segment_count;
    append_paint(*paint, sp, o);
    for (const EncodedTile& t : s.tiles) {
      EncodedTile tile;
      tile.width = t.width;
      tile.height = t.height;
      tile.scene.segments = t.scene.segments;
      tile.scene.strokes = t.scene.strokes;
      tile.scene.input_segment_count = t.scene.input_segment_count;
      shift_paths(tile.scene.paths, t.scene.paths, o.paints);
      shift_stream(tile.scene.stream, t.scene.stream, 0, o.groups);
      out.tiles.push_back(std::move(tile));
    }
  }
  out.paint = std::move(paint);
  return out;
}

std::vector<SceneRoot> scene_roots(const EncodedScene& scene, int width, int height) {
  if (!scene.roots.empty()) return scene.roots;
  static const PaintData none;
  const PaintData& p = scene.paint ? *scene.paint : none;
  return {SceneRoot{0, u32(scene.stream.size()), width, height, {sampler_kinds(p, false), sampler_kinds(p, true)}}};
}

void forest_grid(const EncodedScene& forest, int& width, int& height) {
  width = height = 0;
  for (const SceneRoot& r : forest.roots) {
    width = std::max(width, r.width);
    height = std::max(height, r.height);
  }
}

}  // namespace mpvg
