#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>

#include "apps/image_io.h"
#include "core/error.h"

namespace mpvg {

namespace {

template <class T>
void write_png(const std::string& path, int width, int height, const std::vector<T>& rgba, OIIO::TypeDesc type) {
  const bool to_stdout = path == "-";
  const std::string name = to_stdout ? "stdout.png" : path;
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw Error("cannot create a PNG writer: " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 4, type);
  // Our pixels are straight (unassociated) alpha already, as PNG stores them.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput vec(buffer);
  if (to_stdout) {
    OIIO::Filesystem::IOProxy* proxy = &vec;
    spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  }
  if (!out->open(name, spec)) throw Error("cannot write '" + path + "': " + out->geterror());
  if (!out->write_image(type, rgba.data()) || !out->close())
    throw Error("cannot write '" + path + "': " + out->geterror());
  if (to_stdout) {
    if (std::fwrite(buffer.data(), 1, buffer.size(), stdout) != buffer.size() || std::fflush(stdout) != 0)
      throw Error("cannot write the PNG to standard output");
  }
}

}  // namespace

void write_png_rgba8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  write_png(path, width, height, rgba, OIIO::TypeDesc::UINT8);
}

void write_png_rgba16(const std::string& path, int width, int height, const std::vector<uint16_t>& rgba) {
  write_png(path, width, height, rgba, OIIO::TypeDesc::UINT16);
}

std::string image_io_library() { return "OpenImageIO " OIIO_VERSION_STRING; }

}  // namespace mpvg
