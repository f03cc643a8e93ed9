// Backend choice at run time (--backend auto|cuda|cpu). Built in every
// configuration: without nvcc, the CUDA side reports itself unavailable and
// auto renders on the CPU.
#pragma once
#include <string>

#include "core/renderer.h"

namespace mpvg {

// Is a CUDA device usable? If not, *why says why (one line).
bool cuda_available(std::string* why = nullptr);

// Renders with options.backend: Cpu, Cuda (throws mpvg::Error when no device
// can be used), or Auto (CUDA when available, else the CPU, with a one-line
// note in stats->note).
ImageF render(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

}  // namespace mpvg
