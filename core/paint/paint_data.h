// Host storage of the paint tables (core/paint/paint.h): what the encoder
// produces, what the CPU sampler reads and the GPU uploads.
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include "core/paint/group.h"
#include "core/paint/paint.h"

namespace mpvg {

// Host copies of the paint tables (core/paint/paint.h). PaintTables views them.
struct PaintData {
  std::vector<PaintRecord> paints;
  std::vector<GradientRecord> gradients;
  std::vector<float> ramp_t;
  std::vector<Rgba4> ramp_color;
  std::vector<TextureRecord> textures;
  std::vector<TextureLevel> levels;
  std::vector<Texel16> texels;
  // Texel ranges that stay in device memory (ExecutorTexels::device): they
  // follow `texels` in the texel table, at offset >= texels.size(); a GPU
  // frame copies them in on the device, the CPU cannot render them.
  struct DeviceTexels {
    uint64_t offset = 0, count = 0;
    const Texel16* src = nullptr;
    std::shared_ptr<const void> owner;
  };
  std::vector<DeviceTexels> device_texels;
  std::vector<PatternRecord> patterns;
  std::vector<GroupRecord> groups;
  std::vector<MeshRecord> meshes;
  std::vector<MeshTriangle> mesh_triangles;
  std::vector<uint32_t> mesh_cells, mesh_items;
  // Some path of the scene or of a pattern tile is aliased (PATH_ALIASED):
  // the samplers must be the ones that handle it (core/sampling/sampling.h).
  bool aliased = false;

  // Pointers into these vectors; `tiles` are the tile trees' views.
  PaintTables view(const TreeView* tiles) const {
    return PaintTables{paints.data(),   gradients.data(), ramp_t.data(),         ramp_color.data(), textures.data(),
                       levels.data(),   texels.data(),    patterns.data(),       tiles,             groups.data(),
                       meshes.data(),   mesh_triangles.data(), mesh_cells.data(), mesh_items.data()};
  }
  // Entries of the texel table: the host's and the device's.
  size_t texel_count() const {
    size_t n = texels.size();
    for (const DeviceTexels& d : device_texels) n += d.count;
    return n;
  }
  size_t bytes() const {
    return paints.size() * sizeof(PaintRecord) + gradients.size() * sizeof(GradientRecord) +
           ramp_t.size() * sizeof(float) + ramp_color.size() * sizeof(Rgba4) +
           textures.size() * sizeof(TextureRecord) + levels.size() * sizeof(TextureLevel) +
           texel_count() * sizeof(Texel16) + patterns.size() * sizeof(PatternRecord) +
           groups.size() * sizeof(GroupRecord) + meshes.size() * sizeof(MeshRecord) +
           mesh_triangles.size() * sizeof(MeshTriangle) + (mesh_cells.size() + mesh_items.size()) * sizeof(uint32_t);
  }
};

}  // namespace mpvg
