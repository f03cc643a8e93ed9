// The PNG stage's filtering and compression on the device (png_encode.cu),
// with the buffers it keeps from image to image.
#pragma once
#include "core/output/deflate.h"
#include "core/output/png_encode.h"
#include "gpu/cuda_util.h"

namespace mpvg::gpu {

class PngStage {
 public:
  // The PNG data of width x height pixels of 8-bit RGBA codes on the device
  // (rgba: one word per pixel, r in the low byte): the channels written
  // and the zlib stream, copied back. The same bytes as
  // png::compress_rgba8 on the CPU.
  png::ImageData run(const uint32_t* rgba, int width, int height);
  // The first half only: the rows filtered on the device and copied back
  // (into storage's memory where it is large enough), for the CPU to
  // deflate (png::encode_filtered). One round trip for an opaque image,
  // two for a translucent one (its rows are longer than the opaque size
  // copied with the flag). The same rows as png::filter_image.
  png::FilteredRows filter(const uint32_t* rgba, int width, int height, std::vector<uint8_t> storage = {});

  size_t launches = 0, syncs = 0;  // issued by the last run

 private:
  // The translucency flag and the filtered rows (flag_ and filtered_ sized
  // for RGBA rows): the first half of both run and filter.
  void launch_filter(const uint32_t* rgba, int width, int height);

  // Filtered rows, the parse's tokens per piece, each chunk's frequencies,
  // codes, deflated bytes (a slot each) and sizes, the stream.
  DeviceBuffer<uint8_t> filtered_, out_;
  DeviceBuffer<uint32_t> flag_, tokens_, counts_, slots_, sizes_, length_;
  DeviceBuffer<deflate::Frequencies> freq_;
  DeviceBuffer<deflate::BlockCode> codes_;
  DeviceBuffer<deflate::AdlerPart> piece_adler_, chunk_adler_;
};

}  // namespace mpvg::gpu
