#include "lib/compare/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace mpvg::image_compare {

namespace {

template <class T>
Picture from_straight(const T* px, int width, int height, int channels, float scale) {
  Picture p;
  p.width = width;
  p.height = height;
  const size_t n = size_t(width) * size_t(height);
  p.values.resize(n * 4);
  for (size_t i = 0; i < n; i++) {
    const T* s = px + i * size_t(channels);
    float r, g, b, a = 1.0f;
    if (channels <= 2) {
      r = g = b = s[0] * scale;
      if (channels == 2) a = s[1] * scale;
    } else {
      r = s[0] * scale, g = s[1] * scale, b = s[2] * scale;
      if (channels == 4) a = s[3] * scale;
    }
    float* d = &p.values[i * 4];
    d[0] = r * a, d[1] = g * a, d[2] = b * a, d[3] = a;
  }
  return p;
}

// Luma of a premultiplied pixel over white (the diff image's grey); for
// inks, the paper less the most ink.
float shade(const Picture& p, size_t i) {
  const float* q = &p.values[i * size_t(p.channels)];
  if (!p.colour) {
    float most = 0;
    for (int c = 0; c < p.channels; c++)
      if (p.names.size() <= size_t(c) || p.names[c] != "A") most = std::max(most, q[c]);
    return 1.0f - most;
  }
  const float white = 1.0f - q[3];
  return 0.299f * (q[0] + white) + 0.587f * (q[1] + white) + 0.114f * (q[2] + white);
}

// The antialiasing-aware mode's questions about a pixel (image_compare.h).
class Edges {
 public:
  // The ringing rule compares in linear light, where a filter's ringing is
  // a fraction of the edge's contrast whatever the colours (sRGB codes
  // stretch it near black).
  Edges(const Picture& a, const Picture& b)
      : a_(a), b_(b), la_(linear(a)), lb_(linear(b)), w_(a.width), h_(a.height), n_(a.channels) {}

  // How far (the largest over channels) p's value in `x` lies outside the
  // range of values `y` has within `radius` pixels of p.
  double outside(const Picture& x, const Picture& y, int px, int py, int radius) const {
    float lo[kMaxChannels], hi[kMaxChannels];
    range(y, px, py, radius, lo, hi);
    const float* v = &x.values[(size_t(py) * w_ + px) * n_];
    double e = 0;
    for (int c = 0; c < n_; c++) e = std::max(e, double(std::max({0.0f, lo[c] - v[c], v[c] - hi[c]})));
    return e;
  }

  // Both ways: a's value against b's neighbourhood and b's against a's
  // (as compared, or in linear light).
  double unexplained(int x, int y, bool in_linear = false) const {
    const Picture& a = in_linear ? la_ : a_;
    const Picture& b = in_linear ? lb_ : b_;
    return std::max(outside(a, b, x, y, 1), outside(b, a, x, y, 1));
  }

  // The contrast of the edges within `radius` of p in either image, in
  // linear light: the largest range of a channel over both neighbourhoods.
  double contrast(int x, int y, int radius) const {
    float lo[kMaxChannels], hi[kMaxChannels];
    range(la_, x, y, radius, lo, hi);
    range(lb_, x, y, radius, lo, hi, false);
    double c = 0;
    for (int k = 0; k < n_; k++) c = std::max(c, double(hi[k] - lo[k]));
    return c;
  }

 private:
  // The range of each channel of p within `radius` of (x, y), widening
  // lo and hi as they are unless `fresh`.
  void range(const Picture& p, int x, int y, int radius, float* lo, float* hi, bool fresh = true) const {
    if (fresh) std::fill(lo, lo + n_, 2.0f), std::fill(hi, hi + n_, -1.0f);
    for (int ny = std::max(0, y - radius); ny <= std::min(h_ - 1, y + radius); ny++)
      for (int nx = std::max(0, x - radius); nx <= std::min(w_ - 1, x + radius); nx++) {
        const float* q = &p.values[(size_t(ny) * w_ + nx) * n_];
        for (int c = 0; c < n_; c++) lo[c] = std::min(lo[c], q[c]), hi[c] = std::max(hi[c], q[c]);
      }
  }

  // p with its colour decoded from sRGB, premultiplied (inks are amounts
  // already: as they are).
  static Picture linear(const Picture& p) {
    Picture l = p;
    if (!p.colour) return l;
    for (size_t i = 0; i < l.values.size(); i += 4) {
      const float a = l.values[i + 3];
      for (int c = 0; c < 3 && a > 0; c++) {
        const float v = std::min(1.0f, l.values[i + c] / a);
        l.values[i + c] = a * (v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f));
      }
    }
    return l;
  }

  const Picture& a_;
  const Picture& b_;
  const Picture la_, lb_;
  int w_, h_, n_;
};

// A difference the antialiasing-aware mode forgives: each image's value
// within the other's range around the pixel (up to the threshold: an edge
// that moved by less than a pixel, or was sampled otherwise), or, within
// two pixels of an edge, outside it by at most aa_ring times the edge's
// contrast, in linear light (a wider filter's ringing).
bool forgiven(const Edges& edges, int x, int y, const Options& o) {
  if (edges.unexplained(x, y) <= std::min(o.fail, o.warn)) return true;
  return edges.unexplained(x, y, true) <= o.aa_ring * edges.contrast(x, y, 2);
}

uint8_t to8(float v) { return static_cast<uint8_t>(std::lround(std::min(1.0f, std::max(0.0f, v)) * 255.0f)); }

}  // namespace

Picture from_straight8(const uint8_t* pixels, int width, int height, int channels) {
  return from_straight(pixels, width, height, channels, 1.0f / 255.0f);
}

Picture from_straight16(const uint16_t* pixels, int width, int height, int channels) {
  return from_straight(pixels, width, height, channels, 1.0f / 65535.0f);
}

Result compare(const Picture& a, const Picture& b, const Options& o, std::vector<uint8_t>* diff) {
  Result r;
  r.width = a.width;
  r.height = a.height;
  r.width_b = b.width;
  r.height_b = b.height;
  r.channels = a.channels;
  r.channels_b = b.channels;
  if (a.width != b.width || a.height != b.height) {
    r.same_size = false;
    r.verdict = Verdict::Fail;
    return r;
  }
  if (a.channels != b.channels || a.colour != b.colour || a.names != b.names || a.channels > kMaxChannels) {
    r.same_channels = false;
    r.verdict = Verdict::Fail;
    return r;
  }
  const int nc = a.channels;
  const int w = a.width, h = a.height;
  const size_t n = size_t(w) * size_t(h);
  r.pixels = n;
  if (diff) {
    // A faded grey copy of a.
    diff->assign(n * 4, 255);
    for (size_t i = 0; i < n; i++) {
      const uint8_t g = to8(1.0f - 0.15f * (1.0f - shade(a, i)));
      (*diff)[i * 4] = (*diff)[i * 4 + 1] = (*diff)[i * 4 + 2] = g;
    }
  }
  std::unique_ptr<Edges> edges;  // the antialiasing-aware mode's (linear copies of both images)
  if (o.antialiasing) edges = std::make_unique<Edges>(a, b);
  double sum = 0, sum2 = 0;
  std::vector<float> largest(n);  // each pixel's largest channel difference, for the percentiles
  bool hard_fail = false, hard_warn = false;
  const double lowest = std::min(o.fail, o.warn);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      const size_t i = size_t(y) * w + x;
      double d = 0;
      for (int c = 0; c < nc; c++) {
        const double e = std::fabs(double(a.values[i * nc + c]) - double(b.values[i * nc + c]));
        sum += e;
        sum2 += e * e;
        d = std::max(d, e);
      }
      largest[i] = static_cast<float>(d);
      if (d > 0) r.differing++;
      if (d > r.max_difference) r.max_difference = d, r.max_x = x, r.max_y = y;
      if (d <= lowest) continue;
      if (edges && forgiven(*edges, x, y, o)) {
        r.antialiased++;
        if (diff) (*diff)[i * 4] = 255, (*diff)[i * 4 + 1] = 215, (*diff)[i * 4 + 2] = 0;
        continue;
      }
      const bool failed = d > o.fail, warned = d > o.warn;
      r.failed += failed;
      r.warned += warned;
      hard_fail = hard_fail || d > o.hardfail;
      hard_warn = hard_warn || d > o.hardwarn;
      if (diff && (failed || warned)) {
        uint8_t* q = &(*diff)[i * 4];
        q[0] = 255, q[1] = failed ? 0 : 140, q[2] = 0;
      }
    }
  auto percentile = [&](double q) {
    const size_t k = std::min(n - 1, static_cast<size_t>(q * double(n)));
    std::nth_element(largest.begin(), largest.begin() + std::ptrdiff_t(k), largest.end());
    return double(largest[k]);
  };
  if (n) {
    r.p99_difference = percentile(0.99);
    r.p999_difference = percentile(0.999);
  }
  r.mean_difference = n ? sum / (double(nc) * n) : 0;
  r.rms_difference = n ? std::sqrt(sum2 / (double(nc) * n)) : 0;
  r.psnr = r.rms_difference > 0 ? 20.0 * std::log10(1.0 / r.rms_difference) : std::numeric_limits<double>::infinity();
  const double percent = n ? 100.0 / double(n) : 0;
  if (hard_fail || double(r.failed) * percent > o.failpercent) r.verdict = Verdict::Fail;
  else if (hard_warn || double(r.warned) * percent > o.warnpercent) r.verdict = Verdict::Warn;
  return r;
}

const char* verdict_name(Verdict v) {
  return v == Verdict::Pass ? "PASS" : v == Verdict::Warn ? "WARNING" : "FAILURE";
}

std::string to_json(const Result& r, const Options& o) {
  auto num = [](double v) {
    if (std::isinf(v)) return std::string("null");
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", v);
    return std::string(b);
  };
  std::string s = "{\"result\":\"";
  s += verdict_name(r.verdict);
  s += "\",\"same_size\":" + std::string(r.same_size ? "true" : "false");
  s += ",\"same_channels\":" + std::string(r.same_channels ? "true" : "false");
  s += ",\"width\":" + std::to_string(r.width) + ",\"height\":" + std::to_string(r.height);
  s += ",\"a\":{\"width\":" + std::to_string(r.width) + ",\"height\":" + std::to_string(r.height) +
       ",\"channels\":" + std::to_string(r.channels) + "}";
  s += ",\"b\":{\"width\":" + std::to_string(r.width_b) + ",\"height\":" + std::to_string(r.height_b) +
       ",\"channels\":" + std::to_string(r.channels_b) + "}";
  s += ",\"pixels\":" + std::to_string(r.pixels) + ",\"differing\":" + std::to_string(r.differing);
  s += ",\"failed\":" + std::to_string(r.failed) + ",\"warned\":" + std::to_string(r.warned);
  s += ",\"antialiased\":" + std::to_string(r.antialiased);
  s += ",\"max_difference\":" + num(r.max_difference) + ",\"max_at\":[" + std::to_string(r.max_x) + "," +
       std::to_string(r.max_y) + "]";
  s += ",\"mean_difference\":" + num(r.mean_difference) + ",\"rms_difference\":" + num(r.rms_difference);
  s += ",\"p99_difference\":" + num(r.p99_difference) + ",\"p999_difference\":" + num(r.p999_difference);
  s += ",\"psnr\":" + num(r.psnr);
  s += ",\"fail\":" + num(o.fail) + ",\"failpercent\":" + num(o.failpercent) + ",\"hardfail\":" + num(o.hardfail);
  s += ",\"warn\":" + num(o.warn) + ",\"warnpercent\":" + num(o.warnpercent) + ",\"hardwarn\":" + num(o.hardwarn);
  s += ",\"antialiasing\":" + std::string(o.antialiasing ? "true" : "false") + "}";
  return s;
}

}  // namespace mpvg::image_compare
