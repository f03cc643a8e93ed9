// The CUDA executor of filter graphs (gpu/filter.cu): core/filter_layers.h's
// FilterRunner on the current device.
#pragma once
#include "core/filter_layers.h"

namespace mpvg::gpu {

FilterResult run_filter_cuda(const FilterLayer& layer);

}  // namespace mpvg::gpu
