// Images decoded at the resolution the output needs: rows come in from a
// decoder one at a time and every k x k block of texels (fewer at the
// right and bottom edges) becomes one texel, the average of the block with
// premultiplied alpha, as the first levels of the texture's mip chain
// would hold it. Only one row of sums is kept besides the output, so a
// 16000 x 16000 PNG shown 100 pixels wide costs 16000 x 16000 / k^2
// texels, not a gigabyte.
//
// Header-only: the PNG decoder and OpenImageIO's module both use it.
// Internal to the SVG frontend.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace mpvg::svg::detail {

// What a decoder may produce (svg_resources.h decode_raster).
struct DecodeRequest {
  // The box reduction for an image of w x h texels: 1 is full size. The
  // caller knows how large the image will be drawn.
  std::function<int(int w, int h)> reduction;
  // Texels of the decoded (reduced) image at most.
  size_t max_pixels = size_t(1) << 28;
  // Texels at most of a full-size image that a decoder holds whole before
  // reducing it (GIF, WebP and interlaced PNG decoders give no rows before
  // the whole image is decoded).
  size_t max_whole_pixels = size_t(1) << 26;
  // Texels read at most, however much they are reduced: a decoder's time
  // (a JPEG header may claim 65500 x 65500 pixels that 500 bytes cannot
  // hold, and libjpeg decodes every missing row as grey; 2^30 texels take
  // a few seconds).
  size_t max_decoded_pixels = size_t(1) << 30;
};

template <class T>
class RowReducer {
 public:
  // An image of w x h texels reduced by k.
  RowReducer(int w, int h, int k)
      : w_(w), h_(h), k_(k), out_w_((w + k - 1) / k), out_h_((h + k - 1) / k),
        sums_(size_t(out_w_) * 4), pixels_(size_t(out_w_) * out_h_ * 4) {}

  int width() const { return out_w_; }
  int height() const { return out_h_; }

  // Row y (rows in order, 0 to h - 1): w straight-alpha RGBA texels.
  void add_row(int y, const T* rgba) {
    for (int x = 0; x < w_; x++) {
      const T* p = rgba + size_t(x) * 4;
      uint64_t* s = &sums_[size_t(x / k_) * 4];
      const uint64_t a = p[3];
      s[0] += p[0] * a;
      s[1] += p[1] * a;
      s[2] += p[2] * a;
      s[3] += a;
    }
    if ((y + 1) % k_ != 0 && y + 1 != h_) return;
    const int oy = y / k_;
    const uint64_t rows = uint64_t(y - oy * k_ + 1);
    T* out = &pixels_[size_t(oy) * out_w_ * 4];
    for (int ox = 0; ox < out_w_; ox++) {
      uint64_t* s = &sums_[size_t(ox) * 4];
      const uint64_t cols = uint64_t(std::min(k_, w_ - ox * k_));
      const uint64_t n = rows * cols;
      for (int c = 0; c < 3; c++) out[ox * 4 + c] = s[3] ? T((s[c] + s[3] / 2) / s[3]) : T(0);
      out[ox * 4 + 3] = T((s[3] + n / 2) / n);
      s[0] = s[1] = s[2] = s[3] = 0;
    }
  }

  std::vector<T>& pixels() { return pixels_; }

 private:
  int w_, h_, k_;
  int out_w_, out_h_;
  std::vector<uint64_t> sums_;
  std::vector<T> pixels_;
};

}  // namespace mpvg::svg::detail
