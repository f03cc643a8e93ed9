// The CUDA executor of filter graphs (gpu/filter.cu), on the current
// device.
#pragma once
#include <memory>
#include <vector>

#include "frame/filter_layers.h"

namespace mpvg::gpu {

// The graphs of many layers, run together: layers whose graphs have one
// shape (the same ops wired the same way) in batches, each step one launch
// over all of a batch. sources[k] is layer k's source on the device
// (premultiplied, in its source_linear space; layers[k]->source is not
// read). Returns each result as texels of a frame integrated in `gamma`
// (filter_texel), left on the device (ExecutorTexels::device).
std::vector<std::shared_ptr<const Image>> run_filters_cuda(const std::vector<const FilterLayer*>& layers,
                                                           const std::vector<const float*>& sources, Gamma gamma);

// The same with each layer's source taken from its host image
// (layers[k]->source).
std::vector<std::shared_ptr<const Image>> run_filters_cuda(const std::vector<const FilterLayer*>& layers, Gamma gamma);

// An executor image's texels on the host (tests): width x height texels.
std::vector<Texel16> download_texels(const Image& image);

// One layer's graph from its host source to its host result, as
// run_filter_cpu gives it (tests compare the two).
FilterResult run_filter_cuda(const FilterLayer& layer);

}  // namespace mpvg::gpu
