// TIFF and JPEG files encoded by OpenImageIO, into memory through an
// IOProxy (nothing touches the disk), and image files read back for
// mpvg-compare (TIFFs of any channels). Built as a module of its own,
// mpvg_oiio_encoder.so (MPVG_IMAGE_IO=oiio), that image_writer.cpp opens
// on first need: OpenImageIO's ~260 libraries cost 0.3 s to load, which a
// process writing only PNGs does not pay.
//
// What OpenImageIO 2.4 writes, checked with tiffinfo and its own readers:
//   TIFF: 1 channel MinIsBlack, 2 grey + ExtraSamples unassociated alpha,
//   3 RGB, 4 RGBA (unassociated) or, asked with tiff:ColorSpace=CMYK and
//   channels named C M Y K, Separated with InkSet CMYK; more channels
//   Separated with InkSet multi-ink and InkNames. CMYK comes out 8 bits
//   whatever is asked (its writer's test of the format is always true), so
//   16-bit CMYK is refused rather than quietly cut. jpeg compression only
//   for 8-bit RGB; anything else it deflates.
//   JPEG: grey or RGB only (JFIF; no CMYK writer, no alpha); quality,
//   progressive, the JFIF density; no switch for optimized Huffman tables,
//   which libjpeg makes here by transcoding the coefficients (what
//   jpegtran -optimize does: the pixels stay the same).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include <jpeglib.h>

#include "lib/output/image_writer.h"

namespace {

using mpvg::image::EncodeOptions;
using mpvg::image::Raster;

// OpenImageIO's messages can span lines (one per error met): joined.
bool fail(std::string* why, std::string msg) {
  while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
  for (size_t i; (i = msg.find('\n')) != std::string::npos;) msg.replace(i, 1, "; ");
  if (why) *why = std::move(msg);
  return false;
}

// libjpeg reports errors by calling error_exit, which must not return:
// back to the setjmp in optimize_huffman, with the message.
struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void jpeg_error_exit(j_common_ptr cinfo) {
  JpegError* e = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  std::longjmp(e->jump, 1);
}

// The same JPEG with optimized Huffman tables: its DCT coefficients
// copied losslessly (libjpeg's jpeg_read_coefficients and
// jpeg_write_coefficients) into a new file whose tables are made from
// them. Only C objects live between setjmp and longjmp.
bool optimize_huffman(std::vector<uint8_t>& bytes, std::string* why) {
  jpeg_decompress_struct src{};
  jpeg_compress_struct dst{};
  JpegError err{};
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
  src.err = jpeg_std_error(&err.mgr);
  dst.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpeg_error_exit;
  // volatile: set after setjmp, read after the longjmp.
  volatile bool src_made = false, dst_made = false;
  if (setjmp(err.jump)) {
    if (dst_made) jpeg_destroy_compress(&dst);
    if (src_made) jpeg_destroy_decompress(&src);
    std::free(out);
    return fail(why, std::string("cannot optimize the JPEG's Huffman tables: ") + err.message);
  }
  jpeg_create_decompress(&src);
  src_made = true;
  jpeg_create_compress(&dst);
  dst_made = true;
  jpeg_mem_src(&src, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&src, TRUE);
  jvirt_barray_ptr* coefficients = jpeg_read_coefficients(&src);
  jpeg_copy_critical_parameters(&src, &dst);  // the JFIF density too
  dst.optimize_coding = TRUE;
  jpeg_mem_dest(&dst, &out, &out_size);
  jpeg_write_coefficients(&dst, coefficients);
  jpeg_finish_compress(&dst);
  jpeg_finish_decompress(&src);
  jpeg_destroy_compress(&dst);
  jpeg_destroy_decompress(&src);
  bytes.assign(out, out + out_size);
  std::free(out);
  return true;
}

// Checks what OpenImageIO 2.4 cannot write, or would write otherwise than
// asked; the reason, or empty.
std::string refusal(const std::string& format, const Raster& r, const EncodeOptions& o) {
  if (r.width <= 0 || r.height <= 0 || !r.data) return "empty image";
  if (r.bits != 1 && r.bits != 8 && r.bits != 16) return "bits per channel must be 1, 8 or 16";
  if (r.bits == 1 && (format != "tiff" || r.channels != 1 || r.cmyk)) return "1-bit images are grey TIFFs only";
  if (r.cmyk ? r.channels < 4 : (r.channels < 1 || r.channels > 4))
    return r.cmyk ? "CMYK needs 4 channels or more" : "channels must be 1 to 4";
  if (format == "jpeg") {
    if (r.cmyk) return "OpenImageIO " OIIO_VERSION_STRING " writes no CMYK JPEG (grey and RGB only)";
    if (r.channels == 2 || r.channels == 4) return "JPEG has no alpha channel";
    if (r.bits != 8) return "JPEG holds 8 bits per channel only";
    if (o.jpeg_quality < 1 || o.jpeg_quality > 100) return "JPEG quality must be 1 to 100";
  } else {
    if (r.cmyk && r.bits == 16)
      return "OpenImageIO " OIIO_VERSION_STRING " writes CMYK TIFFs with 8 bits per channel only";
    const std::string& c = o.tiff_compression;
    if (c != "none" && c != "packbits" && c != "lzw" && c != "deflate" && c != "jpeg")
      return "unknown TIFF compression '" + c + "' (none, packbits, lzw, deflate or jpeg)";
  }
  return {};
}

bool encode(const std::string& format, const Raster& r, const EncodeOptions& o, std::vector<uint8_t>* bytes,
            std::string* why) {
  const std::string no = refusal(format, r, o);
  if (!no.empty()) return fail(why, no);
  const OIIO::TypeDesc type = r.bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(r.width, r.height, r.channels, type);
  // Names say what the channels are: the TIFF writer takes C M Y K for
  // CMYK (else multi-ink), and alpha from alpha_channel.
  spec.channelnames.clear();
  spec.alpha_channel = -1;
  static const char* const kNames[2][4] = {{"R", "G", "B", "A"}, {"C", "M", "Y", "K"}};
  for (int c = 0; c < r.channels; c++) {
    if (r.cmyk) spec.channelnames.push_back(c < 4 ? kNames[1][c] : "Spot" + std::to_string(c - 3));
    else if (r.channels <= 2) spec.channelnames.push_back(c == 0 ? "Y" : "A");
    else spec.channelnames.push_back(kNames[0][c]);
  }
  if (!r.cmyk && (r.channels == 2 || r.channels == 4)) {
    spec.alpha_channel = r.channels - 1;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // straight alpha: ExtraSamples 2
  }
  if (o.dpi > 0) {
    spec.attribute("XResolution", static_cast<float>(o.dpi));
    spec.attribute("YResolution", static_cast<float>(o.dpi_y > 0 ? o.dpi_y : o.dpi));
    spec.attribute("ResolutionUnit", "in");
  }
  if (format == "tiff") {
    const std::string& c = o.tiff_compression;
    spec.attribute("Compression",
                   c == "deflate" ? std::string("zip") : c == "jpeg" ? "jpeg:" + std::to_string(o.jpeg_quality) : c);
    if (c == "deflate") spec.attribute("tiff:zipquality", o.deflate_level);
    if (r.cmyk) spec.attribute("tiff:ColorSpace", "CMYK");
    if (r.bits == 1) spec.attribute("oiio:BitsPerSample", 1);
    // No DateTime tag (the writer stamps the current time where the spec
    // has no DateTime string): the same image gives the same bytes.
    spec.attribute("DateTime", 0);
  } else {
    spec.attribute("Compression", "jpeg:" + std::to_string(o.jpeg_quality));
    if (o.progressive) spec.attribute("jpeg:progressive", 1);
  }

  OIIO::Filesystem::IOVecOutput vec;
  OIIO::Filesystem::IOProxy* proxy = &vec;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto out = OIIO::ImageOutput::create(format, proxy);
  if (!out) return fail(why, "no " + format + " writer in OpenImageIO: " + OIIO::geterror());
  if (!out->supports("ioproxy")) return fail(why, "OpenImageIO's " + format + " writer cannot write to memory");
  out->set_ioproxy(proxy);
  // A failure: every message the writer holds is taken, as OpenImageIO
  // prints those left behind when the writer is destroyed.
  auto failed = [&]() {
    std::string msg = out->geterror();
    out->close();
    const std::string more = out->geterror();
    out.reset();
    OIIO::geterror();
    return fail(why, "cannot encode the " + format + " image: " + (msg.empty() ? more : msg));
  };
  // The name only tells the writer what to report; the bytes go to `vec`.
  if (!out->open("image." + format, spec)) return failed();
  if (!out->write_image(type, r.data)) return failed();
  if (!out->close()) return failed();
  out.reset();
  bytes->assign(vec.buffer().begin(), vec.buffer().end());
  // A progressive JPEG's tables are optimized already (libjpeg makes them
  // for every progressive scan).
  if (format == "jpeg" && o.optimize && !o.progressive) return optimize_huffman(*bytes, why);
  return true;
}

}  // namespace

// An image file read back whole (image::decode): the first subimage, its
// channels as stored (CMYK and inks not converted to RGB: oiio:RawColor;
// alpha left straight), samples scaled to [0, 1].
bool read(const std::vector<uint8_t>& bytes, size_t max_pixels, mpvg::image::Decoded* out, std::string* why) {
  OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
  OIIO::Filesystem::IOProxy* proxy = &mem;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  config.attribute("oiio:UnassociatedAlpha", 1);
  config.attribute("oiio:RawColor", 1);
  auto in = OIIO::ImageInput::open("image.tif", &config, proxy);
  if (!in) {
    std::string msg = OIIO::geterror();
    return fail(why, msg.empty() ? "not an image OpenImageIO reads" : msg);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return fail(why, "an image without pixels");
  // (Before its samples are allocated: CMYK, spot inks and alpha fit.)
  if (spec.nchannels > mpvg::image::kMaxDecodedChannels)
    return fail(why, "an image of " + std::to_string(spec.nchannels) + " channels (at most " +
                         std::to_string(mpvg::image::kMaxDecodedChannels) + ")");
  if (size_t(spec.width) * size_t(spec.height) > max_pixels)
    return fail(why, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                         " pixels is over the limit of " + std::to_string(max_pixels) + " pixels");
  out->width = spec.width;
  out->height = spec.height;
  out->channels = spec.nchannels;
  out->bits = spec.format.size() >= 2 ? 16 : 8;
  out->alpha = spec.alpha_channel;
  out->names = spec.channelnames;
  const std::string space = spec.get_string_attribute("tiff:ColorSpace");
  const int photometric = spec.get_int_attribute("tiff:PhotometricInterpretation", -1);
  out->cmyk = space == "CMYK" || photometric == 5 /* Separated */ ||
              (spec.nchannels >= 4 && spec.channelnames.size() >= 4 && spec.channelnames[0] == "C" &&
               spec.channelnames[3] == "K");
  // OpenImageIO 2.4 calls a CMYK TIFF's K its alpha channel (a fourth
  // channel without ExtraSamples): alpha is a channel named so.
  if (out->alpha >= 0 && out->alpha < int(out->names.size()) && out->names[out->alpha] != "A" &&
      out->names[out->alpha] != "Alpha")
    out->alpha = -1;
  out->samples.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out->samples.data())) {
    std::string msg = in->geterror();
    in->close();
    return fail(why, "cannot decode the image: " + msg);
  }
  in->close();
  return true;
}

// The module's entry points, looked up by name by image_writer.cpp, which
// holds their types. `format` is "tiff" or "jpeg". Built by the same
// compiler against the same libstdc++ as the caller, so C++ types cross.
extern "C" __attribute__((visibility("default"))) const char* mpvg_oiio_version() {
  return "OpenImageIO " OIIO_VERSION_STRING;
}

extern "C" __attribute__((visibility("default"))) bool mpvg_oiio_encode(const char* format, const Raster* raster,
                                                                       const EncodeOptions* options,
                                                                       std::vector<uint8_t>* bytes,
                                                                       std::string* why) {
  // No exception may cross into the caller through a C-linkage function.
  try {
    return encode(format, *raster, *options, bytes, why);
  } catch (const std::exception& e) {
    return fail(why, std::string("cannot encode the ") + format + " image: " + e.what());
  }
}

extern "C" __attribute__((visibility("default"))) bool mpvg_oiio_read(const std::vector<uint8_t>* bytes,
                                                                     size_t max_pixels,
                                                                     mpvg::image::Decoded* out, std::string* why) {
  try {
    return read(*bytes, max_pixels, out, why);
  } catch (const std::exception& e) {
    return fail(why, std::string("cannot read the image: ") + e.what());
  }
}
