// Colour management of print preview (PDF 32000-1 §14.11.5 output
// intents, §8.6.5.5 ICC-based spaces): the CMYK profile of the press a page
// is previewed for, and conversions into its CMYK through Little CMS 2.
//
// Debian 12's MuPDF is built without ICC support, so its own conversions
// to DeviceCMYK are PDF's device formulas (§10.4.2: from RGB, c = 1 - r
// with black generation k = min(c, m, y) and undercolour removal, RGB
// black becoming K alone). A press profile instead maps RGB through its
// characterisation (RGB black becomes a rich black, colours land in the
// press's gamut), as Ghostscript and an ICC-enabled MuPDF do. With a
// profile, the PDF frontend converts RGB-based colours (DeviceRGB and
// CalRGB, Lab, and ICC-based spaces through MuPDF's RGB) and images
// through it; DeviceGray goes to K alone (§10.4.2.3), DeviceCMYK, Separation
// and DeviceN colorants are inks already.
//
// Where the profile comes from: the document's output intent (its first
// /OutputIntents entry with a four-channel DestOutputProfile, as a PDF/X
// names its press), else the one pdf2png --cmyk-profile names; without
// either, MuPDF's formulas and one warning.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mpvg::pdf {

class OutputProfile {
 public:
  // An ICC profile's bytes; `name` says where it came from in messages.
  // Throws mpvg::Error (one line) unless it is a valid CMYK output profile.
  OutputProfile(const std::vector<uint8_t>& icc, std::string name);
  ~OutputProfile();
  OutputProfile(const OutputProfile&) = delete;
  OutputProfile& operator=(const OutputProfile&) = delete;

  // Reads an ICC file (pdf2png --cmyk-profile). Throws mpvg::Error.
  static std::shared_ptr<const OutputProfile> from_file(const std::string& path);

  // sRGB colours (3 floats each, [0, 1]) to the profile's CMYK (4 floats
  // each, ink amounts in [0, 1]), with PDF's rendering intent `intent`
  // (0 perceptual, 1 relative colorimetric, 2 saturation, 3 absolute).
  // Safe to call from several threads at once.
  void rgb_to_cmyk(const float* rgb, float* cmyk, size_t count, int intent) const;

  const std::string& name() const { return name_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string name_;
};

}  // namespace mpvg::pdf
