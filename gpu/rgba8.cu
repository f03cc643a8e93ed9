// The PNG stage's 8-bit conversion on the device (core/output/rgba8.h): the
// rendered float image becomes straight-alpha 8-bit codes before it is
// copied back, a quarter of the bytes.
#include "core/output/rgba8.h"
#include "gpu/context.cuh"

namespace mpvg::gpu {

namespace {

constexpr unsigned kBlock = 256;

__global__ void k_rgba8(const float4* image, size_t n, bool linear, const SrgbCodeTable* table, uint32_t* out) {
  const size_t i = blockIdx.x * size_t(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const float4 p = image[i];
  out[i] = rgba8_pixel(p.x, p.y, p.z, p.w, linear, *table);
}

}  // namespace

void Context::Impl::convert_rgba8(bool linear) {
  if (srgb_table.size() == 0) srgb_table.upload(std::vector<SrgbCodeTable>{srgb_code_table()});
  const size_t n = size_t(out_width) * out_height;
  rgba8.resize(n);
  if (n) {
    k_rgba8<<<grid_for(n, kBlock), kBlock>>>(image.data(), n, linear, srgb_table.data(), rgba8.data());
    launched();
  }
}

std::shared_ptr<uint8_t> Context::Impl::device_rgba8(bool linear) {
  convert_rgba8(linear);
  const size_t bytes = 4 * size_t(out_width) * out_height;
  void* p = nullptr;
  MPVG_CUDA(cudaMalloc(&p, bytes ? bytes : 4));
  std::shared_ptr<uint8_t> out(static_cast<uint8_t*>(p), [](uint8_t* q) { cudaFree(q); });
  if (bytes) MPVG_CUDA(cudaMemcpyAsync(p, rgba8.data(), bytes, cudaMemcpyDeviceToDevice, cudaStreamPerThread));
  MPVG_CUDA(cudaStreamSynchronize(cudaStreamPerThread));
  syncs++;
  return out;
}

std::vector<uint8_t> Context::Impl::download_rgba8(bool linear, std::vector<uint8_t> out) {
  convert_rgba8(linear);
  const size_t n = size_t(out_width) * out_height;
  out.resize(4 * n);
  if (n) MPVG_CUDA(cudaMemcpy(out.data(), rgba8.data(), 4 * n, cudaMemcpyDeviceToHost));
  syncs++;
  return out;
}

}  // namespace mpvg::gpu
