// External resources of an SVG document: hrefs resolved to bytes (data:
// URIs, local files inside the folders the document may read), raster
// images decoded to core Images, gzip (svgz) inflated.
//
// Internal to the SVG frontend. Rendering an untrusted document must not
// read arbitrary files or touch the network: a file is read only when its
// real path (symbolic links and '..' resolved) lies inside one of the
// allowed folders, and every URL with a scheme other than data: (and file:
// inside an allowed folder) is refused.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene.h"
#include "parsers/svg/image_reduction.h"

namespace mpvg::svg::detail {

struct Resource {
  // Media type, lower case, parameters removed: a data: URI's own ("" when
  // it has none), or guessed from a file's extension ("" when unknown).
  std::string mime;
  std::vector<uint8_t> bytes;
  // The file's canonical path; "" for data: URIs. Lets callers detect a
  // document that embeds itself.
  std::string path;
};

// Resolves an href (already trimmed of XML whitespace by the caller or not)
// against `base_dir`, the referencing document's folder:
//   - data: URIs (RFC 2397), base64 or percent-encoded;
//   - relative paths, absolute paths and file: URLs, read only when the real
//     path lies in the tree of one of `allowed_dirs`;
//   - anything else (http:, https:, ftp:, ...) is refused.
// Returns nullopt and sets *why (one line, for a warning) when the resource
// is refused, missing, unreadable or larger than max_bytes.
std::optional<Resource> fetch_resource(std::string_view href, const std::string& base_dir,
                                       const std::vector<std::string>& allowed_dirs, std::string* why,
                                       size_t max_bytes = size_t(256) << 20);

enum class ImageKind { Png, Jpeg, Gif, Webp, Svg, Svgz, Unknown };

// What the bytes are, from their signature; when no signature matches,
// from `mime` (e.g. "image/svg+xml" for SVG text without an XML declaration).
ImageKind sniff_image(const std::vector<uint8_t>& bytes, std::string_view mime);

// Decodes a raster image (PNG at 8 or 16 bits per channel, greyscale,
// palette and alpha variants; JPEG, greyscale and CMYK included; the first
// frame of a GIF; WebP) to straight-alpha RGBA at 8 or 16 bits (16 only for
// 16-bit sources), reduced as request.reduction asks (image_reduction.h);
// *full_w and *full_h get the image's own size. Returns nullptr and sets
// *why on failure, and for images past the request's pixel limits
// (decompression bombs).
std::shared_ptr<Image> decode_raster(const std::vector<uint8_t>& bytes, std::string* why,
                                     const DecodeRequest& request = {}, int* full_w = nullptr,
                                     int* full_h = nullptr);

// Inflates gzip data (svgz). nullopt and *why on corrupt data or when the
// output would exceed max_bytes.
std::optional<std::string> gunzip(const std::vector<uint8_t>& bytes, std::string* why,
                                  size_t max_bytes = size_t(256) << 20);

// The decoders in use: "libpng 1.6.39" for PNG, then "; OpenImageIO 2.4.7
// (module)" once the module for JPEG, GIF and WebP has been loaded, or why
// it cannot be.
std::string image_decoder_library();

// Can JPEG, GIF and WebP be decoded? They are decoded by OpenImageIO in a
// module (mpvg_oiio_decoder.so) opened on first need, so that a process
// that meets no such image never loads OpenImageIO's ~260 libraries (0.3 s).
// False, with *why, in builds without it (MPVG_IMAGE_IO=png) or when the
// module cannot be loaded.
bool oiio_decoder_available(std::string* why = nullptr);

// The parts of decode_raster: PNG by libpng, the rest by the module.
std::shared_ptr<Image> decode_png(const std::vector<uint8_t>& bytes, std::string* why, const DecodeRequest& request,
                                  int* full_w, int* full_h);
std::string png_decoder_library();

}  // namespace mpvg::svg::detail
