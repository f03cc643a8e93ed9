// External resources: hrefs to bytes under the read policy of
// svg_resources.h, gzip inflation, and image signatures. Decoding lives in
// svg_image_decode_oiio.cpp or svg_image_decode_png.cpp, whichever the
// build chose (MPVG_IMAGE_IO).
#include "parsers/svg/svg_resources.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

namespace fs = std::filesystem;

namespace {

std::optional<Resource> refuse(std::string* why, std::string msg) {
  if (why) *why = std::move(msg);
  return std::nullopt;
}

std::string lowered(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), ascii_lower);
  return out;
}

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

// %XX escapes decoded (RFC 3986 §2.1); a '%' not followed by two hex
// digits stays as it is, as browsers keep it.
std::string percent_decode(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); i++) {
    if (s[i] == '%' && i + 2 < s.size() && hex_value(s[i + 1]) >= 0 && hex_value(s[i + 2]) >= 0) {
      out.push_back(static_cast<char>(hex_value(s[i + 1]) * 16 + hex_value(s[i + 2])));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// Base64 (RFC 4648 §4, and the URL-safe alphabet of §5) with white space
// anywhere, as SVG files wrap long data: URIs over lines; padding optional.
bool base64_decode(std::string_view s, std::vector<uint8_t>& out, size_t max_bytes) {
  uint32_t acc = 0;
  int bits = 0;
  bool padding = false;
  for (char c : s) {
    if (is_ws(c)) continue;
    if (c == '=') {
      padding = true;
      continue;
    }
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+' || c == '-') v = 62;
    else if (c == '/' || c == '_') v = 63;
    else return false;
    if (padding) return false;  // data after the padding
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      if (out.size() >= max_bytes) return false;
      out.push_back(static_cast<uint8_t>(acc >> bits));
      acc &= (1u << bits) - 1;
    }
  }
  // A lone final character carries 6 bits, not a byte.
  return bits < 6;
}

// data:[<mediatype>][;base64],<data> (RFC 2397).
std::optional<Resource> data_uri(std::string_view href, std::string* why, size_t max_bytes) {
  const std::string_view rest = href.substr(5);
  const size_t comma = rest.find(',');
  if (comma == std::string_view::npos) return refuse(why, "malformed data: URI (no ',')");
  const std::string_view meta = rest.substr(0, comma);
  const std::string_view data = rest.substr(comma + 1);
  Resource r;
  bool base64 = false;
  size_t start = 0;
  for (int field = 0; start <= meta.size(); field++) {
    const size_t end = std::min(meta.find(';', start), meta.size());
    const std::string_view part = trim(meta.substr(start, end - start));
    // The media type comes first; the rest are parameters, and base64 the
    // last of them (taken anywhere, as readers do).
    if (field == 0 && part.find('/') != std::string_view::npos && part.find('=') == std::string_view::npos)
      r.mime = lowered(part);
    else if (iequals(part, "base64"))
      base64 = true;
    start = end + 1;
  }
  if (base64) {
    // Percent escapes are allowed in base64 data too (RFC 2397 §3).
    const std::string text = data.find('%') == std::string_view::npos ? std::string(data) : percent_decode(data);
    if (text.size() / 4 * 3 > max_bytes + 3)
      return refuse(why, "data: URI larger than " + std::to_string(max_bytes) + " bytes");
    if (!base64_decode(text, r.bytes, max_bytes)) return refuse(why, "invalid base64 data in a data: URI");
  } else {
    const std::string text = percent_decode(data);
    if (text.size() > max_bytes) return refuse(why, "data: URI larger than " + std::to_string(max_bytes) + " bytes");
    r.bytes.assign(text.begin(), text.end());
  }
  return r;
}

// The scheme of an absolute URL (RFC 3986 §3.1), lower case; "" for a
// relative reference.
std::string url_scheme(std::string_view s) {
  if (s.empty() || !((s[0] >= 'a' && s[0] <= 'z') || (s[0] >= 'A' && s[0] <= 'Z'))) return {};
  for (size_t i = 1; i < s.size(); i++) {
    const char c = s[i];
    if (c == ':') return lowered(s.substr(0, i));
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '+' ||
                    c == '-' || c == '.';
    if (!ok) return {};
  }
  return {};
}

std::string mime_of_extension(const fs::path& p) {
  const std::string ext = lowered(p.extension().string());
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg" || ext == ".jpe") return "image/jpeg";
  if (ext == ".gif") return "image/gif";
  if (ext == ".webp") return "image/webp";
  if (ext == ".svg" || ext == ".svgz") return "image/svg+xml";
  return {};
}

// Whether `p` lies in the tree of `dir`, comparing whole path components
// (both canonical): /a/bc is not inside /a/b.
bool inside(const fs::path& p, const fs::path& dir) {
  auto d = dir.begin(), q = p.begin();
  for (; d != dir.end(); ++d, ++q) {
    // A trailing separator shows up as an empty last component.
    if (d->empty() && std::next(d) == dir.end()) return true;
    if (q == p.end() || *d != *q) return false;
  }
  return true;
}

bool inside_any(const fs::path& p, const std::vector<fs::path>& dirs) {
  return std::any_of(dirs.begin(), dirs.end(), [&](const fs::path& d) { return inside(p, d); });
}

std::optional<Resource> local_file(const std::string& href, std::string_view path_part, const std::string& base_dir,
                                   const std::vector<std::string>& allowed_dirs, std::string* why, size_t max_bytes) {
  // A fragment (an SVG view) or a query means nothing to a file.
  path_part = path_part.substr(0, std::min(path_part.find('#'), path_part.find('?')));
  const std::string decoded = percent_decode(path_part);
  if (decoded.empty()) return refuse(why, "'" + href + "' names no file");
  if (decoded.find('\0') != std::string::npos) return refuse(why, "'" + href + "' is not a valid file name");
  fs::path p(decoded);
  if (p.is_relative()) p = fs::path(base_dir.empty() ? "." : base_dir) / p;

  std::vector<fs::path> dirs;
  for (const std::string& d : allowed_dirs) {
    std::error_code ec;
    fs::path c = fs::canonical(d.empty() ? "." : d, ec);
    if (!ec) dirs.push_back(std::move(c));
  }
  // The lexical and existing-prefix resolution first, so that a refusal
  // does not depend on (and does not reveal) whether the file exists; then
  // the full real path, whose symbolic links may lead elsewhere.
  std::error_code ec;
  const fs::path weak = fs::weakly_canonical(p, ec);
  const std::string outside = "'" + href + "' lies outside the folders the document may read";
  if (ec || !inside_any(weak, dirs)) return refuse(why, outside);
  const fs::path real = fs::canonical(weak, ec);
  if (ec) return refuse(why, "cannot read '" + href + "': " + ec.message());
  if (!inside_any(real, dirs)) return refuse(why, outside);
  // Only regular files: a FIFO or a device could block or never end.
  if (!fs::is_regular_file(real, ec)) return refuse(why, "cannot read '" + href + "': not a regular file");
  const uintmax_t size = fs::file_size(real, ec);
  if (ec) return refuse(why, "cannot read '" + href + "': " + ec.message());
  if (size > max_bytes) return refuse(why, "'" + href + "' is larger than " + std::to_string(max_bytes) + " bytes");

  Resource r;
  FILE* f = std::fopen(real.c_str(), "rb");
  if (!f) return refuse(why, "cannot read '" + href + "': " + std::strerror(errno));
  r.bytes.resize(static_cast<size_t>(size));
  const size_t n = std::fread(r.bytes.data(), 1, r.bytes.size(), f);
  const bool failed = std::ferror(f);
  std::fclose(f);
  if (failed) return refuse(why, "cannot read '" + href + "': read error");
  r.bytes.resize(n);  // the file may have shrunk meanwhile
  r.mime = mime_of_extension(real);
  r.path = real.string();
  return r;
}

}  // namespace

std::optional<Resource> fetch_resource(std::string_view href_in, const std::string& base_dir,
                                       const std::vector<std::string>& allowed_dirs, std::string* why,
                                       size_t max_bytes) {
  const std::string_view href = trim(href_in);
  const std::string shown(href.substr(0, std::min<size_t>(href.size(), 80)));
  if (href.empty()) return refuse(why, "empty href");
  if (starts_with_nocase(href, "data:")) return data_uri(href, why, max_bytes);
  const std::string scheme = url_scheme(href);
  if (scheme == "file") {
    // file:///path, file://localhost/path, file:/path (RFC 8089); a
    // relative path is taken relative to the document as for plain paths.
    std::string_view rest = href.substr(5);
    if (rest.substr(0, 2) == "//") {
      rest = rest.substr(2);
      const size_t slash = rest.find('/');
      const std::string_view host = rest.substr(0, slash);
      if (!host.empty() && !iequals(host, "localhost"))
        return refuse(why, "'" + shown + "': file: URLs naming a host are not read");
      if (slash == std::string_view::npos) return refuse(why, "'" + shown + "' names no file");
      rest = rest.substr(slash);
    }
    return local_file(shown, rest, base_dir, allowed_dirs, why, max_bytes);
  }
  if (!scheme.empty())
    return refuse(why, "'" + shown + "': " + scheme + ": URLs are not loaded (only data: URIs and local files)");
  // A network-path reference (RFC 3986 §4.2) names a host.
  if (href.substr(0, 2) == "//") return refuse(why, "'" + shown + "': network references are not loaded");
  return local_file(shown, href, base_dir, allowed_dirs, why, max_bytes);
}

std::optional<std::string> gunzip(const std::vector<uint8_t>& bytes, std::string* why, size_t max_bytes) {
  auto fail = [&](std::string msg) -> std::optional<std::string> {
    if (why) *why = std::move(msg);
    return std::nullopt;
  };
  z_stream zs{};
  // 16 + MAX_WBITS: a gzip header and trailer around the deflate stream.
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) return fail("cannot initialise zlib");
  struct End {
    z_stream* z;
    ~End() { inflateEnd(z); }
  } end{&zs};
  std::string out;
  std::vector<unsigned char> buf(size_t(1) << 16);
  size_t pos = 0;
  for (;;) {
    // avail_in is 32 bits: feed large inputs in pieces.
    if (zs.avail_in == 0 && pos < bytes.size()) {
      const size_t n = std::min<size_t>(bytes.size() - pos, size_t(1) << 30);
      zs.next_in = const_cast<Bytef*>(bytes.data() + pos);
      zs.avail_in = static_cast<uInt>(n);
      pos += n;
    }
    zs.next_out = buf.data();
    zs.avail_out = static_cast<uInt>(buf.size());
    const int rc = inflate(&zs, Z_NO_FLUSH);
    const size_t produced = buf.size() - zs.avail_out;
    if (out.size() + produced > max_bytes)
      return fail("gzip data inflates to more than " + std::to_string(max_bytes) + " bytes");
    out.append(reinterpret_cast<const char*>(buf.data()), produced);
    if (rc == Z_STREAM_END) {
      // Another gzip member may follow (RFC 1952 §2.2); anything else
      // (padding) is ignored.
      const size_t left = zs.avail_in + (bytes.size() - pos);
      const uint8_t* next = bytes.data() + (bytes.size() - left);
      if (left >= 2 && next[0] == 0x1f && next[1] == 0x8b) {
        if (inflateReset(&zs) != Z_OK) return fail("corrupt gzip data");
        continue;
      }
      return out;
    }
    if (rc == Z_BUF_ERROR && zs.avail_in == 0 && pos >= bytes.size()) return fail("truncated gzip data");
    if (rc != Z_OK && rc != Z_BUF_ERROR)
      return fail(std::string("corrupt gzip data") + (zs.msg ? std::string(": ") + zs.msg : std::string()));
  }
}

ImageKind sniff_image(const std::vector<uint8_t>& b, std::string_view mime) {
  auto starts = [&](const char* sig, size_t n, size_t at = 0) {
    return b.size() >= at + n && std::memcmp(b.data() + at, sig, n) == 0;
  };
  if (starts("\x89PNG\r\n\x1a\n", 8)) return ImageKind::Png;
  if (starts("\xff\xd8\xff", 3)) return ImageKind::Jpeg;
  if (starts("GIF87a", 6) || starts("GIF89a", 6)) return ImageKind::Gif;
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return ImageKind::Webp;
  if (starts("\x1f\x8b", 2)) return ImageKind::Svgz;
  // Markup: '<' after an optional UTF-8 byte order mark and white space.
  size_t i = starts("\xef\xbb\xbf", 3) ? 3 : 0;
  while (i < b.size() && is_ws(static_cast<char>(b[i]))) i++;
  if (i < b.size() && b[i] == '<') return ImageKind::Svg;
  const std::string m = lowered(trim(mime));
  if (m == "image/png") return ImageKind::Png;
  if (m == "image/jpeg" || m == "image/jpg") return ImageKind::Jpeg;
  if (m == "image/gif") return ImageKind::Gif;
  if (m == "image/webp") return ImageKind::Webp;
  if (m == "image/svg+xml") return ImageKind::Svg;
  return ImageKind::Unknown;
}

}  // namespace mpvg::svg::detail
