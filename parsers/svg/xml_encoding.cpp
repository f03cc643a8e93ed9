#include "parsers/svg/xml_encoding.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

#include "core/error.h"

namespace mpvg::svg::detail {

namespace {

// UTF-16 code units to UTF-8; an unpaired surrogate becomes U+FFFD, an odd
// last byte is dropped.
std::string utf16_to_utf8(std::string_view b, bool big_endian) {
  std::string out;
  out.reserve(b.size() / 2 * 3 / 2);
  auto unit = [&](size_t i) {
    const uint32_t hi = uint8_t(b[i]), lo = uint8_t(b[i + 1]);
    return big_endian ? (hi << 8 | lo) : (lo << 8 | hi);
  };
  for (size_t i = 0; i + 1 < b.size(); i += 2) {
    uint32_t c = unit(i);
    if (c >= 0xD800 && c < 0xDC00 && i + 3 < b.size()) {
      const uint32_t d = unit(i + 2);
      if (d >= 0xDC00 && d < 0xE000) {
        c = 0x10000 + ((c - 0xD800) << 10) + (d - 0xDC00);
        i += 2;
      } else {
        c = 0xFFFD;
      }
    } else if (c >= 0xD800 && c < 0xE000) {
      c = 0xFFFD;
    }
    append_utf8(out, c);
  }
  return out;
}

bool valid_utf8(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    const uint8_t c = uint8_t(s[i]);
    const size_t n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : 4;
    if (n == 4 || i + n >= s.size()) return false;
    for (size_t k = 1; k <= n; k++)
      if ((uint8_t(s[i + k]) >> 6) != 2) return false;
    i += n + 1;
  }
  return true;
}

// windows-1252's 0x80-0x9F (0: undefined there, taken as ISO-8859-1's C1
// control, as browsers do).
constexpr uint16_t kCp1252[32] = {0x20AC, 0,      0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021,
                                  0x02C6, 0x2030, 0x0160, 0x2039, 0x0152, 0,      0x017D, 0,
                                  0,      0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014,
                                  0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0,      0x017E, 0x0178};

std::string single_byte_to_utf8(std::string_view b, bool cp1252) {
  std::string out;
  out.reserve(b.size() + b.size() / 8);
  for (const char ch : b) {
    uint32_t c = uint8_t(ch);
    if (cp1252 && c >= 0x80 && c < 0xA0 && kCp1252[c - 0x80]) c = kCp1252[c - 0x80];
    append_utf8(out, c);
  }
  return out;
}

// The encoding declared by <?xml ... encoding="NAME"?>, lower-cased; empty
// when there is none.
std::string declared_encoding(std::string_view s) {
  if (s.substr(0, 5) != "<?xml") return {};
  const size_t end = s.find("?>");
  const std::string_view decl = s.substr(0, end);
  const size_t at = decl.find("encoding");
  if (at == std::string_view::npos) return {};
  size_t i = at + 8;
  while (i < decl.size() && (decl[i] == ' ' || decl[i] == '=' || decl[i] == '\t')) i++;
  if (i >= decl.size() || (decl[i] != '"' && decl[i] != '\'')) return {};
  const size_t close = decl.find(decl[i], i + 1);
  if (close == std::string_view::npos) return {};
  std::string name(decl.substr(i + 1, close - i - 1));
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return name;
}

}  // namespace

void append_utf8(std::string& out, uint32_t c) {
  if (c < 0x80) {
    out += char(c);
  } else if (c < 0x800) {
    out += char(0xC0 | (c >> 6));
    out += char(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += char(0xE0 | (c >> 12));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  } else {
    out += char(0xF0 | (c >> 18));
    out += char(0x80 | ((c >> 12) & 0x3F));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  }
}

std::string xml_to_utf8(std::string_view b) {
  std::string storage;
  const std::string_view utf8 = xml_to_utf8(b, storage);
  if (utf8.data() == storage.data()) return storage;
  return std::string(utf8);
}

std::string_view xml_to_utf8(std::string_view b, std::string& storage) {
  auto starts = [&](std::string_view prefix) { return b.substr(0, prefix.size()) == prefix; };
  using namespace std::string_view_literals;
  if (starts("\x00\x00\xFE\xFF"sv) || starts("\xFF\xFE\x00\x00"sv) || starts("\x00\x00\x00\x3C"sv) ||
      starts("\x3C\x00\x00\x00"sv))
    throw Error("UTF-32 documents are not supported");
  if (starts("\xFE\xFF")) return storage = utf16_to_utf8(b.substr(2), true);
  if (starts("\xFF\xFE")) return storage = utf16_to_utf8(b.substr(2), false);
  // No mark: '<' and the character after it, as UTF-16 ("<?" per
  // Appendix F; any ASCII character as well).
  if (b.size() >= 4 && b[0] == 0 && b[1] == '<' && b[2] == 0) return storage = utf16_to_utf8(b, true);
  if (b.size() >= 4 && b[0] == '<' && b[1] == 0 && b[3] == 0) return storage = utf16_to_utf8(b, false);
  if (starts("\xEF\xBB\xBF")) b.remove_prefix(3);
  const std::string enc = declared_encoding(b);
  if (enc == "iso-8859-1" || enc == "latin1" || enc == "iso_8859-1" || enc == "l1")
    return storage = single_byte_to_utf8(b, false);
  // windows-1252 is also what browsers read for US-ASCII (WHATWG Encoding).
  if (enc == "windows-1252" || enc == "cp1252" || enc == "us-ascii" || enc == "ascii")
    return storage = single_byte_to_utf8(b, true);
  if (!enc.empty() && enc != "utf-8" && enc != "utf8" && !valid_utf8(b))
    throw Error("the document's encoding '" + enc + "' is not supported (UTF-8, UTF-16, ISO-8859-1 and windows-1252 are)");
  return b;
}

}  // namespace mpvg::svg::detail
