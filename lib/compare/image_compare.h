// Image comparison for golden-image tests (mpvg-compare, mpvg.compare()):
// two images of one size, pixel by pixel, with OpenImageIO idiff's
// thresholds and an antialiasing-aware mode.
//
// Pixels are compared premultiplied, channels in [0, 1]: a pixel's
// difference is the largest |a - b| over its four channels, so colour under
// no coverage counts for nothing and faint coverage for little.
//
//   fail, failpercent   a pixel whose difference exceeds `fail` fails; the
//                       images fail when more than failpercent % of the
//                       pixels fail (idiff -fail, -failpercent)
//   hardfail            any one pixel over it fails the images (-hardfail)
//   warn, warnpercent,  the same for a warning (-warn, -warnpercent,
//   hardwarn            -hardwarn): the images pass, with a warning
//
// Antialiasing-aware mode (the idea of pixelmatch, Mapbox's image
// comparison: a pixel on an antialiased edge may differ by more): a
// differing pixel is forgiven when each image's value lies within the range
// of values the other image has in the pixel's 3 x 3 neighbourhood (per
// channel, up to the threshold): an edge that moved by less than a pixel,
// or was sampled or filtered otherwise, changes the mix of the colours on
// both sides but brings no colour from elsewhere. Within two pixels of an
// edge, a value may also lie outside that range by `aa_ring` times the
// edge's contrast (the ringing of a wider filter such as the cardinal
// cubic). A change of antialiasing filter, sample count or seed, or an edge
// moved by a pixel at most, then passes; a shape that moved further, grew,
// vanished or changed colour does not.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace mpvg::image_compare {

// A w x h image of `channels` values a pixel in [0, 1], interleaved: for
// colour, premultiplied RGBA (sRGB-encoded colour, alpha last); else ink
// amounts (CMYK and spot colours of a print preview, 0: no ink), alpha
// last where there is one (`names` says which: "C", "M", "Y", "K",
// "PANTONE 185 C", "A"). Images compare when they have the same kind of
// channels.
struct Picture {
  int width = 0, height = 0, channels = 4;
  bool colour = true;
  std::vector<std::string> names;  // inks only
  std::vector<float> values;
};

// The most channels a picture may have (CMYK, spot colours, alpha).
constexpr int kMaxChannels = 16;

// From straight-alpha RGBA at 8 or 16 bits (`channels` 1 grey, 2 grey and
// alpha, 3 RGB, 4 RGBA per pixel).
Picture from_straight8(const uint8_t* pixels, int width, int height, int channels);
Picture from_straight16(const uint16_t* pixels, int width, int height, int channels);

struct Options {
  double fail = 1e-6, failpercent = 0, hardfail = std::numeric_limits<double>::infinity();
  double warn = 1e-6, warnpercent = 0, hardwarn = std::numeric_limits<double>::infinity();
  bool antialiasing = false;
  double aa_ring = 0.3;  // beside an edge, times its contrast
};

enum class Verdict { Pass, Warn, Fail };

struct Result {
  Verdict verdict = Verdict::Pass;
  bool same_size = true;
  // The channels differ in kind or number (RGBA against CMYK inks): the
  // images fail, nothing else measured.
  bool same_channels = true;
  int width = 0, height = 0;  // a's
  int width_b = 0, height_b = 0;
  int channels = 4, channels_b = 4;
  size_t pixels = 0;
  size_t differing = 0;    // difference > 0
  size_t failed = 0;       // over `fail`, not forgiven
  size_t warned = 0;       // over `warn`, not forgiven
  size_t antialiased = 0;  // over `fail` or `warn`, forgiven as antialiasing
  double max_difference = 0;
  int max_x = 0, max_y = 0;
  double mean_difference = 0, rms_difference = 0;
  // Percentiles of each pixel's largest channel difference (the noise
  // between two renders: a seed's, a sample count's).
  double p99_difference = 0, p999_difference = 0;
  double psnr = std::numeric_limits<double>::infinity();  // dB, over the four channels
};

// Compares a with b. With `diff`, fills it with a's width x height straight
// RGBA8 diff image: a faded grey copy of a, pixels that fail red, warn
// orange, forgiven as antialiasing yellow. Images of different sizes or
// channels fail (same_size or same_channels false, nothing else measured).
Result compare(const Picture& a, const Picture& b, const Options& options, std::vector<uint8_t>* diff = nullptr);

// "PASS", "WARNING", "FAILURE".
const char* verdict_name(Verdict v);

// The result as one JSON object (no newline).
std::string to_json(const Result& r, const Options& options);

}  // namespace mpvg::image_compare
