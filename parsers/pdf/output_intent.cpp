// Print preview's output profile through Little CMS 2
// (parsers/pdf/output_intent.h).
#include "parsers/pdf/output_intent.h"

#include <lcms2.h>

#include <fstream>
#include <iterator>
#include <mutex>

#include "core/error.h"

namespace mpvg::pdf {

struct OutputProfile::Impl {
  cmsHPROFILE cmyk = nullptr;
  cmsHPROFILE srgb = nullptr;
  // One transform per rendering intent, made on first use. cmsFLAGS_NOCACHE
  // keeps cmsDoTransform free of shared state: several workers convert at
  // once.
  std::mutex lock;
  cmsHTRANSFORM transforms[4] = {nullptr, nullptr, nullptr, nullptr};

  ~Impl() {
    for (cmsHTRANSFORM t : transforms)
      if (t) cmsDeleteTransform(t);
    if (cmyk) cmsCloseProfile(cmyk);
    if (srgb) cmsCloseProfile(srgb);
  }

  cmsHTRANSFORM transform(int intent) {
    intent = intent < 0 || intent > 3 ? INTENT_RELATIVE_COLORIMETRIC : intent;
    std::lock_guard<std::mutex> g(lock);
    if (!transforms[intent])
      transforms[intent] = cmsCreateTransform(srgb, TYPE_RGB_FLT, cmyk, TYPE_CMYK_FLT,
                                              static_cast<cmsUInt32Number>(intent), cmsFLAGS_NOCACHE);
    return transforms[intent];
  }
};

OutputProfile::OutputProfile(const std::vector<uint8_t>& icc, std::string name)
    : impl_(std::make_unique<Impl>()), name_(std::move(name)) {
  impl_->cmyk = cmsOpenProfileFromMem(icc.data(), static_cast<cmsUInt32Number>(icc.size()));
  if (!impl_->cmyk) throw Error(name_ + " is not an ICC profile");
  if (cmsGetColorSpace(impl_->cmyk) != cmsSigCmykData)
    throw Error(name_ + " is not a CMYK profile");
  impl_->srgb = cmsCreate_sRGBProfile();
  // (A profile with perceptual tables alone serves every intent.)
  if (!impl_->transform(INTENT_RELATIVE_COLORIMETRIC)) throw Error(name_ + " cannot be used for output");
}

OutputProfile::~OutputProfile() = default;

std::shared_ptr<const OutputProfile> OutputProfile::from_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "'");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() > (64u << 20)) throw Error("'" + path + "' is larger than an ICC profile can be (64 MB)");
  return std::make_shared<const OutputProfile>(bytes, "'" + path + "'");
}

void OutputProfile::rgb_to_cmyk(const float* rgb, float* cmyk, size_t count, int intent) const {
  // lcms's float CMYK is in percent (0-100).
  cmsDoTransform(impl_->transform(intent), rgb, cmyk, static_cast<cmsUInt32Number>(count));
  for (size_t i = 0; i < count * 4; i++) {
    const float v = cmyk[i] / 100.0f;
    cmyk[i] = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
  }
}

}  // namespace mpvg::pdf
