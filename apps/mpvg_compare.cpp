// mpvg-compare: compares two images, as a golden-image test in CI does, with
// OpenImageIO idiff's thresholds and an antialiasing-aware mode
// (lib/compare/image_compare.h). Exit status: 0 equal within the thresholds (a
// warning included), 1 different, 2 an error (unreadable file, bad
// option).
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "lib/compare/image_compare.h"
#include "lib/output/image_io.h"
#include "lib/output/image_writer.h"
#include "core/error.h"
#include "core/scene.h"
#include "parsers/svg/svg_parser.h"
#include "parsers/svg/svg_resources.h"

namespace {

using namespace mpvg;

const char* kUsage =
    "Usage: mpvg-compare A B [options]\n"
    "Compares images A and B (PNG: 8 or 16 bits, grey, RGB, palette, with or without alpha;\n"
    "TIFF: 8 or 16 bits, grey, RGB, CMYK and spot inks, as pdf2png writes them; JPEG) pixel\n"
    "by pixel, premultiplied, channels in [0, 1]; inks are compared as ink amounts. Exit\n"
    "status 0: equal within the thresholds (with a warning or not), 1: different (or of\n"
    "different sizes or channels), 2: an error.\n"
    "\n"
    "  --fail T          a pixel fails when a channel differs by more than T (default 1e-6)\n"
    "  --failpercent P   the images fail when more than P % of the pixels fail (default 0)\n"
    "  --hardfail T      ... or when any pixel differs by more than T\n"
    "  --warn T, --warnpercent P, --hardwarn T\n"
    "                    the same for a warning (default 1e-6, 0, none)\n"
    "  --aa              antialiasing-aware: a pixel is forgiven where each image's value lies\n"
    "                    within the range the other has around it (an edge moved by less than\n"
    "                    a pixel, or sampled otherwise: a change of filter, sample count or\n"
    "                    seed passes; a shape that moved further or changed colour does not)\n"
    "  --aa-ring F       within two pixels of an edge, also outside that range by up to F times\n"
    "                    the edge's contrast (a wider filter's ringing; default 0.3)\n"
    "  --diff D.png      writes a diff image: A faded to grey, failing pixels red, warning\n"
    "                    orange, forgiven antialiasing yellow\n"
    "  --json            the result as one JSON object on standard output\n"
    "  -q, --quiet       no report, only the exit status\n"
    "  --version         mpvg's version\n"
    "  (idiff's spellings -fail, -failpercent, -hardfail, -warn, -warnpercent, -hardwarn,\n"
    "  -o D.png are accepted too)\n";

struct UsageError {
  std::string message;
};

// TIFF's two byte orders: "II*\0" and "MM\0*".
bool is_tiff(const std::string& d) {
  return d.size() >= 4 && ((d.compare(0, 4, std::string("II*\0", 4)) == 0) || d.compare(0, 4, std::string("MM\0*", 4)) == 0);
}

// A TIFF through OpenImageIO's module: grey, grey and alpha, RGB, RGBA as
// colour; CMYK and more inks as ink amounts, compared channel by channel
// (alpha, where there is one, last and multiplied in).
image_compare::Picture tiff_picture(const std::vector<uint8_t>& bytes, size_t max_pixels) {
  const image::Decoded d = image::decode(bytes, max_pixels);
  image_compare::Picture p;
  p.width = d.width;
  p.height = d.height;
  const size_t n = size_t(d.width) * size_t(d.height);
  if (!d.cmyk) {
    if (d.channels > 4) throw Error("a TIFF of " + std::to_string(d.channels) + " channels that are not inks");
    p.values.resize(n * 4);
    for (size_t i = 0; i < n; i++) {
      const float* s = &d.samples[i * size_t(d.channels)];
      const bool grey = d.channels <= 2;
      const float a = d.channels == 2 || d.channels == 4 ? s[d.channels - 1] : 1.0f;
      float* q = &p.values[i * 4];
      q[0] = s[0] * a;
      q[1] = (grey ? s[0] : s[1]) * a;
      q[2] = (grey ? s[0] : s[2]) * a;
      q[3] = a;
    }
    return p;
  }
  if (d.channels > image_compare::kMaxChannels)
    throw Error("a TIFF of " + std::to_string(d.channels) + " channels (at most " +
                std::to_string(image_compare::kMaxChannels) + ")");
  p.colour = false;
  p.channels = d.channels;
  for (int c = 0; c < d.channels; c++) {
    const std::string name = c < int(d.names.size()) ? d.names[c] : "channel " + std::to_string(c);
    p.names.push_back(c == d.alpha ? "A" : name);
  }
  // Alpha last, multiplied into the inks.
  std::vector<int> order;
  for (int c = 0; c < d.channels; c++)
    if (c != d.alpha) order.push_back(c);
  if (d.alpha >= 0) order.push_back(d.alpha);
  std::vector<std::string> names;
  for (int c : order) names.push_back(p.names[c]);
  p.names = names;
  p.values.resize(n * size_t(d.channels));
  for (size_t i = 0; i < n; i++) {
    const float* s = &d.samples[i * size_t(d.channels)];
    const float a = d.alpha >= 0 ? s[d.alpha] : 1.0f;
    for (int k = 0; k < d.channels; k++)
      p.values[i * size_t(d.channels) + k] = order[k] == d.alpha ? a : s[order[k]] * a;
  }
  return p;
}

image_compare::Picture read_picture(const std::string& path) {
  // The file's bytes, at most 1 GiB (mpvg's bounded reader; "-" is standard input).
  const std::string data = svg::read_svg_file(path, size_t(1) << 30);
  const std::vector<uint8_t> bytes(data.begin(), data.end());
  // At most 2^26 pixels (an 8192 x 8192 image): the comparison holds each
  // image as 16 bytes a pixel (more with inks), and twice that with --aa.
  const size_t max_pixels = size_t(1) << 26;
  if (is_tiff(data)) {
    try {
      return tiff_picture(bytes, max_pixels);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
  }
  std::string why;
  svg::detail::DecodeRequest limits;
  limits.max_pixels = limits.max_whole_pixels = max_pixels;
  const std::shared_ptr<Image> image = svg::detail::decode_raster(bytes, &why, limits);
  if (!image) throw Error(path + ": " + (why.empty() ? "not an image mpvg can read" : why));
  return image->bits == 16 ? image_compare::from_straight16(image->rgba16.data(), image->width, image->height, 4)
                           : image_compare::from_straight8(image->rgba8.data(), image->width, image->height, 4);
}

// "RGBA" or the inks' names: "C M Y K", "C M Y K PANTONE 185 C".
std::string describe(const image_compare::Picture& p) {
  if (p.colour) return "RGBA";
  std::string s;
  for (const std::string& n : p.names) s += (s.empty() ? "" : ", ") + n;
  return "inks " + s;
}

double number(const std::string& option, const char* text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (errno || end == text || *end || !(v >= 0)) throw UsageError{"invalid value '" + std::string(text) + "' for " + option};
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  image_compare::Options o;
  std::string diff_path;
  bool json = false, quiet = false;
  try {
    for (int i = 1; i < argc; i++) {
      std::string a = argv[i];
      if (a.size() > 2 && a[0] == '-' && a[1] != '-') a = "-" + a;  // idiff's -fail
      auto value = [&]() -> const char* {
        if (i + 1 >= argc) throw UsageError{a + " needs a value"};
        return argv[++i];
      };
      if (a == "-h" || a == "--help") {
        std::fputs(kUsage, stdout);
        return 0;
      } else if (a == "--version" || a == "-V") {
        std::printf("mpvg-compare (mpvg) %s\n", MPVG_VERSION);
        return 0;
      } else if (a == "--fail") o.fail = number(a, value());
      else if (a == "--failpercent") o.failpercent = number(a, value());
      else if (a == "--hardfail") o.hardfail = number(a, value());
      else if (a == "--warn") o.warn = number(a, value());
      else if (a == "--warnpercent") o.warnpercent = number(a, value());
      else if (a == "--hardwarn") o.hardwarn = number(a, value());
      else if (a == "--aa") o.antialiasing = true;
      else if (a == "--aa-ring") o.aa_ring = number(a, value());
      else if (a == "--diff" || a == "-o") diff_path = value();
      else if (a == "--json") json = true;
      else if (a == "-q" || a == "--quiet") quiet = true;
      else if (a.size() > 1 && a[0] == '-') throw UsageError{"unknown option '" + std::string(argv[i]) + "'"};
      else files.push_back(argv[i]);
    }
    if (files.size() != 2) throw UsageError{"two images to compare, A and B"};
  } catch (const UsageError& e) {
    std::fprintf(stderr, "mpvg-compare: %s (mpvg-compare --help for the options)\n", e.message.c_str());
    return 2;
  }
  try {
    const image_compare::Picture a = read_picture(files[0]), b = read_picture(files[1]);
    std::vector<uint8_t> diff;
    const image_compare::Result r = image_compare::compare(a, b, o, diff_path.empty() ? nullptr : &diff);
    if (!diff_path.empty() && r.same_size) write_png_rgba8(diff_path, a.width, a.height, diff);
    if (json) {
      std::printf("%s\n", image_compare::to_json(r, o).c_str());
    } else if (!quiet) {
      std::printf("Comparing \"%s\" and \"%s\"\n", files[0].c_str(), files[1].c_str());
      if (!r.same_size) {
        std::printf("  Images differ in size: %dx%d and %dx%d\n", a.width, a.height, b.width, b.height);
      } else if (!r.same_channels) {
        std::printf("  Images differ in their channels: %s and %s\n", describe(a).c_str(), describe(b).c_str());
      } else {
        const double pct = r.pixels ? 100.0 / double(r.pixels) : 0;
        std::printf("  Mean error = %.6g\n  RMS error = %.6g\n", r.mean_difference, r.rms_difference);
        std::printf("  99%% of pixels within %.6g (%.1f/255), 99.9%% within %.6g (%.1f/255)\n", r.p99_difference,
                    r.p99_difference * 255, r.p999_difference, r.p999_difference * 255);
        if (r.rms_difference > 0) std::printf("  Peak SNR = %.4g\n", r.psnr);
        else std::printf("  Peak SNR = inf\n");
        std::printf("  Max error  = %.6g @ (%d, %d)\n", r.max_difference, r.max_x, r.max_y);
        std::printf("  %zu pixels (%.4g%%) differ\n", r.differing, double(r.differing) * pct);
        std::printf("  %zu pixels (%.4g%%) over %g\n", r.failed, double(r.failed) * pct, o.fail);
        if (o.warn != o.fail) std::printf("  %zu pixels (%.4g%%) over warning threshold %g\n", r.warned,
                                          double(r.warned) * pct, o.warn);
        if (o.antialiasing)
          std::printf("  %zu pixels (%.4g%%) forgiven as antialiasing\n", r.antialiased, double(r.antialiased) * pct);
      }
      std::printf("%s\n", image_compare::verdict_name(r.verdict));
    }
    return r.verdict == image_compare::Verdict::Fail ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mpvg-compare: %s\n", e.what());
    return 2;
  }
}
