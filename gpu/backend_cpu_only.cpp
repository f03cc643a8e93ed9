// The backend dispatcher of a build without CUDA.
#include "core/error.h"
#include "gpu/backend.h"

namespace mpvg {

bool cuda_available(std::string* why) {
  if (why) *why = "mpvg was built without CUDA";
  return false;
}

ImageF render(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
  if (options.backend == Backend::Cuda) throw Error("CUDA backend unavailable: mpvg was built without CUDA");
  ImageF img = render_cpu(scene, options, stats);
  if (stats && options.backend == Backend::Auto) stats->note = "no CUDA backend in this build; rendered on the CPU";
  return img;
}

}  // namespace mpvg
