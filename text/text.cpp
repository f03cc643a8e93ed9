// FontDb, shaping, outlines and metrics (text.h). Every FreeType and
// HarfBuzz call runs under the db's mutex: an FT_Library and its faces are
// not thread-safe, and HarfBuzz reads the tables through FreeType (hb-ft).
#include "text/text.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_GZIP_H
#include FT_COLOR_H
#include FT_MULTIPLE_MASTERS_H
#include FT_OUTLINE_H
#include FT_SFNT_NAMES_H
#include FT_TRUETYPE_IDS_H
#include FT_TRUETYPE_TABLES_H

#include <hb-ft.h>
#include <hb-ot.h>
#include <hb.h>

#include <fribidi.h>

#ifdef MPVG_HAVE_FONTCONFIG
#include <fontconfig/fontconfig.h>
#endif

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <tuple>

namespace mpvg::text {

namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

void append_utf8(std::string& out, uint32_t c) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (c >> 18));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

// A name-table string: UTF-16BE on the Unicode and Windows platforms, one
// byte per character (read as Latin-1, exact for ASCII) on the Mac platform.
std::string sfnt_string(const FT_SfntName& n) {
  std::string out;
  if (n.platform_id == TT_PLATFORM_MICROSOFT || n.platform_id == TT_PLATFORM_APPLE_UNICODE) {
    for (FT_UInt i = 0; i + 1 < n.string_len; i += 2) {
      uint32_t c = (uint32_t(n.string[i]) << 8) | n.string[i + 1];
      if (c >= 0xD800 && c < 0xDC00 && i + 3 < n.string_len) {
        const uint32_t lo = (uint32_t(n.string[i + 2]) << 8) | n.string[i + 3];
        if (lo >= 0xDC00 && lo < 0xE000) {
          c = 0x10000 + ((c - 0xD800) << 10) + (lo - 0xDC00);
          i += 2;
        }
      }
      append_utf8(out, c);
    }
  } else {
    for (FT_UInt i = 0; i < n.string_len; ++i) append_utf8(out, n.string[i]);
  }
  return out;
}

// The typographic family (name ID 16), English (Windows, US) preferred,
// else any language; empty when the font has none.
std::string typographic_family(FT_Face f) {
  std::string best;
  int best_rank = -1;
  const FT_UInt count = FT_Get_Sfnt_Name_Count(f);
  for (FT_UInt i = 0; i < count; ++i) {
    FT_SfntName n;
    if (FT_Get_Sfnt_Name(f, i, &n) != 0 || n.name_id != TT_NAME_ID_TYPOGRAPHIC_FAMILY) continue;
    int rank = 0;
    if (n.platform_id == TT_PLATFORM_MICROSOFT) rank = n.language_id == 0x409 ? 3 : 2;
    else if (n.platform_id == TT_PLATFORM_MACINTOSH && n.encoding_id == TT_MAC_ID_ROMAN) rank = n.language_id == 0 ? 1 : 0;
    else if (n.platform_id != TT_PLATFORM_APPLE_UNICODE) continue;
    if (rank > best_rank) {
      std::string s = sfnt_string(n);
      if (!s.empty()) best = std::move(s), best_rank = rank;
    }
  }
  return best;
}

FaceInfo read_info(FT_Face f, const std::string& path, int index) {
  FaceInfo info;
  info.path = path;
  info.index = index;
  info.family = typographic_family(f);
  if (info.family.empty() && f->family_name) info.family = f->family_name;
  info.sfnt = FT_IS_SFNT(f);
  info.italic = (f->style_flags & FT_STYLE_FLAG_ITALIC) != 0;
  info.weight = (f->style_flags & FT_STYLE_FLAG_BOLD) ? 700 : 400;
  if (const auto* os2 = static_cast<const TT_OS2*>(FT_Get_Sfnt_Table(f, FT_SFNT_OS2));
      os2 && os2->version != 0xFFFF) {
    int w = os2->usWeightClass;
    if (w >= 1 && w <= 9) w *= 100;  // some old fonts store 1..9
    if (w >= 1 && w <= 1000) info.weight = w;
    if (os2->usWidthClass >= 1 && os2->usWidthClass <= 9) info.stretch = os2->usWidthClass;
    // fsSelection bit 0: italic, bit 9: oblique (CSS matches oblique to italic).
    if (os2->fsSelection & ((1u << 0) | (1u << 9))) info.italic = true;
  }
  return info;
}

// CSS Fonts 4 §5.2 step 4.c, font-weight: the weight among `available`
// nearest to `desired` in the order the specification searches.
int nearest_weight(const std::vector<int>& available, int desired) {
  auto below = [&](int limit, bool inclusive) {  // the largest weight < (<=) limit
    int best = -1;
    for (int w : available)
      if ((inclusive ? w <= limit : w < limit) && w > best) best = w;
    return best;
  };
  auto above = [&](int from, int to, bool inclusive) {  // the smallest weight > (>=) from, <= to
    int best = -1;
    for (int w : available)
      if ((inclusive ? w >= from : w > from) && w <= to && (best < 0 || w < best)) best = w;
    return best;
  };
  int w = -1;
  if (desired >= 400 && desired <= 500) {
    // Weights from desired up to 500 ascending, then below desired
    // descending, then above 500 ascending.
    if ((w = above(desired, 500, true)) >= 0) return w;
    if ((w = below(desired, false)) >= 0) return w;
    return above(500, 100000, false);
  }
  if (desired < 400) {
    if ((w = below(desired, true)) >= 0) return w;
    return above(desired, 100000, false);
  }
  if ((w = above(desired, 100000, true)) >= 0) return w;
  return below(desired, false);
}

// CSS Fonts 4 §5.2 step 4.a, font-stretch: at or below normal, narrower
// widths are checked first (nearest first), then wider ones; above normal
// the other way round.
int nearest_stretch(const std::vector<int>& available, int desired) {
  int narrower = -1, wider = -1;  // nearest <= desired, nearest >= desired
  for (int s : available) {
    if (s <= desired && s > narrower) narrower = s;
    if (s >= desired && (wider < 0 || s < wider)) wider = s;
  }
  if (desired <= 5) return narrower >= 0 ? narrower : wider;
  return wider >= 0 ? wider : narrower;
}

bool is_font_file(const std::filesystem::path& p) {
  const std::string ext = lower(p.extension().string());
  return ext == ".ttf" || ext == ".otf" || ext == ".ttc" || ext == ".otc";
}

// One CSS font-feature-settings item, or HarfBuzz's "-kern" / "aalt=2".
bool parse_feature(std::string_view s, hb_feature_t& out) {
  auto trim = [](std::string_view v) {
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front()))) v.remove_prefix(1);
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.remove_suffix(1);
    return v;
  };
  s = trim(s);
  uint32_t value = 1;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    value = s[0] == '-' ? 0 : 1;
    s.remove_prefix(1);
  }
  std::string_view tag;
  if (!s.empty() && (s[0] == '"' || s[0] == '\'')) {
    const size_t end = s.find(s[0], 1);
    if (end == std::string_view::npos) return false;
    tag = s.substr(1, end - 1);
    s.remove_prefix(end + 1);
  } else {
    size_t end = 0;
    while (end < s.size() && (std::isalnum(static_cast<unsigned char>(s[end])) || s[end] == '_' || s[end] == ' ') &&
           end < 4)
      ++end;
    tag = s.substr(0, end);
    s.remove_prefix(end);
  }
  if (tag.empty() || tag.size() > 4) return false;
  s = trim(s);
  if (!s.empty() && s[0] == '=') s = trim(s.substr(1));
  if (!s.empty()) {
    const std::string v = lower(s);
    if (v == "on") {
      value = 1;
    } else if (v == "off") {
      value = 0;
    } else {
      char* end = nullptr;
      const unsigned long n = std::strtoul(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0') return false;
      value = static_cast<uint32_t>(n);
    }
  }
  out.tag = hb_tag_from_string(tag.data(), static_cast<int>(tag.size()));
  out.value = value;
  out.start = HB_FEATURE_GLOBAL_START;
  out.end = HB_FEATURE_GLOBAL_END;
  return true;
}

}  // namespace

struct FontDb::Impl {
  mutable std::mutex mu;
  FT_Library lib = nullptr;
  std::vector<FaceInfo> faces;
  // Opened on first use, one per face (nullptr until then, or when the file
  // went away since it was scanned).
  mutable std::vector<FT_Face> ft;
  mutable std::vector<hb_font_t*> hb;
  mutable std::vector<bool> open_failed;
  std::set<std::pair<std::string, int>> known;
  std::map<std::string, std::string> generic = {
      {"serif", "Noto Serif"},         {"sans-serif", "Noto Sans"},
      {"cursive", "Yellowtail"},       {"fantasy", "Sedgwick Ave Display"},
      {"monospace", "Noto Mono"},
  };
#ifdef MPVG_HAVE_FONTCONFIG
  FcConfig* fc = nullptr;  // the system's configuration, once add_system_fonts ran
#endif
  // fontconfig's substitutes of a family (lower-case name), cached.
  mutable std::map<std::string, std::vector<std::string>> substitutes;

  // Under mu. The families fontconfig's configuration substitutes for
  // `name`, in its order (FcConfigSubstitute, FcDefaultSubstitute). For a
  // family name, only its aliases: what the rules put ahead of the default
  // list every unknown name gets (the common tail of the two lists is
  // cut). For a generic name, the whole list: that is its resolution.
  const std::vector<std::string>& fontconfig_families(const std::string& name, bool generic_name) const {
    const std::string key = (generic_name ? "g:" : "f:") + name;
    if (auto it = substitutes.find(key); it != substitutes.end()) return it->second;
    std::vector<std::string>& out = substitutes[key];
#ifdef MPVG_HAVE_FONTCONFIG
    if (!fc) return out;
    auto families = [this](const std::string& n) {
      std::vector<std::string> list;
      FcPattern* p = FcPatternCreate();
      FcPatternAddString(p, FC_FAMILY, reinterpret_cast<const FcChar8*>(n.c_str()));
      FcConfigSubstitute(fc, p, FcMatchPattern);
      FcDefaultSubstitute(p);
      FcChar8* f = nullptr;
      for (int i = 0; FcPatternGetString(p, FC_FAMILY, i, &f) == FcResultMatch; ++i)
        list.push_back(lower(reinterpret_cast<const char*>(f)));
      FcPatternDestroy(p);
      return list;
    };
    std::vector<std::string> list = families(name);
    if (!generic_name) {
      const std::vector<std::string> unknown = families("mpvg-no-such-family-7f3a");
      size_t common = 0;
      while (common < list.size() && common + 1 < unknown.size() &&
             list[list.size() - 1 - common] == unknown[unknown.size() - 1 - common])
        ++common;
      list.resize(list.size() - common);
      if (!list.empty() && list[0] == name) list.erase(list.begin());
    }
    out = std::move(list);
#else
    (void)generic_name;
#endif
    return out;
  }

  // Under mu. The first family fontconfig substitutes for `name` that the
  // db has (empty: none).
  std::vector<int> fontconfig_faces(const std::string& name, bool generic_name) const {
    for (const std::string& f : fontconfig_families(name, generic_name))
      if (std::vector<int> c = family_faces(f); !c.empty()) return c;
    return {};
  }

  // Under mu.
  FT_Face face(int i) const {
    if (i < 0 || static_cast<size_t>(i) >= faces.size()) return nullptr;
    if (!ft[i] && !open_failed[i]) {
      FT_Face f = nullptr;
      if (FT_New_Face(lib, faces[i].path.c_str(), faces[i].index, &f) == 0) ft[i] = f;
      else open_failed[i] = true;
    }
    return ft[i];
  }

  // Under mu. HarfBuzz reads the tables through FreeType (hb-ft) and
  // positions with its own OpenType functions at a scale of 64 per font
  // unit: unhinted, with HVAR/gvar variations, exact to 1/64 unit.
  hb_font_t* font(int i) const {
    FT_Face f = face(i);
    if (!f) return nullptr;
    if (!hb[i] && !FT_IS_SFNT(f)) {
      // No OpenType tables (Type 1, bare CFF): HarfBuzz takes the cmap and
      // advances from FreeType, unhinted, at a size of one pixel per font
      // unit: the same scale of 64 per unit.
      FT_Set_Char_Size(f, 0, static_cast<FT_F26Dot6>(f->units_per_EM) * 64, 72, 72);
      hb_font_t* font = hb_ft_font_create_referenced(f);
      hb_ft_font_set_load_flags(font, FT_LOAD_NO_HINTING);
      const int upem = static_cast<int>(f->units_per_EM);
      hb_font_set_scale(font, upem * 64, upem * 64);
      hb[i] = font;
    }
    if (!hb[i]) {
      hb_face_t* hf = hb_ft_face_create_referenced(f);
      hb_font_t* font = hb_font_create(hf);
      hb_face_destroy(hf);
      hb_ot_font_set_funcs(font);
      const int upem = static_cast<int>(hb_face_get_upem(hb_font_get_face(font)));
      hb_font_set_scale(font, upem * 64, upem * 64);
      hb[i] = font;
    }
    return hb[i];
  }

  std::vector<int> family_faces(const std::string& name_lower) const {
    std::vector<int> r;
    for (size_t i = 0; i < faces.size(); ++i)
      if (lower(faces[i].family) == name_lower) r.push_back(static_cast<int>(i));
    return r;
  }

  // A family for `generic` when its mapping is absent: names that say the
  // class, else a sans face, else the first face's family.
  std::vector<int> heuristic_family(const std::string& generic) const {
    auto find = [&](auto pred) -> std::vector<int> {
      for (const FaceInfo& f : faces)
        if (pred(lower(f.family))) return family_faces(lower(f.family));
      return {};
    };
    auto has = [](const std::string& s, const char* w) { return s.find(w) != std::string::npos; };
    std::vector<int> r;
    if (generic == "monospace") r = find([&](const std::string& s) { return has(s, "mono") || has(s, "courier"); });
    else if (generic == "serif") r = find([&](const std::string& s) { return has(s, "serif") && !has(s, "sans"); });
    else if (generic == "cursive") r = find([&](const std::string& s) { return has(s, "script") || has(s, "hand"); });
    if (r.empty())
      r = find([&](const std::string& s) { return has(s, "sans") && !has(s, "mono") && !has(s, "serif"); });
    if (r.empty() && !faces.empty()) r = family_faces(lower(faces[0].family));
    return r;
  }

  int select(const std::vector<int>& candidates, int weight, bool italic, int stretch) const {
    std::vector<int> stretches;
    for (int i : candidates) stretches.push_back(faces[i].stretch);
    const int s = nearest_stretch(stretches, stretch);
    std::vector<int> c;
    for (int i : candidates)
      if (faces[i].stretch == s) c.push_back(i);
    // Style: the requested one, else the other (oblique faces count as
    // italic: FaceInfo does not tell them apart).
    std::vector<int> styled;
    for (int i : c)
      if (faces[i].italic == italic) styled.push_back(i);
    if (styled.empty()) styled = c;
    std::vector<int> weights;
    for (int i : styled) weights.push_back(faces[i].weight);
    const int w = nearest_weight(weights, weight);
    // The same face as OpenType and Type 1 (URW's base 35 ship both):
    // the OpenType one, whose tables HarfBuzz shapes with.
    int first = -1;
    for (int i : styled)
      if (faces[i].weight == w) {
        if (faces[i].sfnt) return i;
        if (first < 0) first = i;
      }
    if (first >= 0) return first;
    return styled.empty() ? -1 : styled[0];
  }
};

FontDb::FontDb() : impl_(std::make_unique<Impl>()) {
  if (FT_Init_FreeType(&impl_->lib) != 0) impl_->lib = nullptr;
}

FontDb::~FontDb() {
  for (hb_font_t* f : impl_->hb)
    if (f) hb_font_destroy(f);
  for (FT_Face f : impl_->ft)
    if (f) FT_Done_Face(f);
  if (impl_->lib) FT_Done_FreeType(impl_->lib);
#ifdef MPVG_HAVE_FONTCONFIG
  if (impl_->fc) FcConfigDestroy(impl_->fc);
#endif
}

size_t FontDb::add_file(const std::string& path, std::vector<std::string>* warnings) {
  Impl& m = *impl_;
  std::lock_guard<std::mutex> lock(m.mu);
  auto warn = [&](const std::string& w) {
    if (warnings) warnings->push_back(path + ": " + w);
  };
  if (!m.lib) {
    warn("FreeType could not be initialised");
    return 0;
  }
  FT_Face f = nullptr;
  if (FT_Error e = FT_New_Face(m.lib, path.c_str(), 0, &f); e != 0) {
    warn("not a readable font (FreeType error " + std::to_string(e) + "), skipped");
    return 0;
  }
  const long count = f->num_faces;
  size_t added = 0;
  for (long i = 0; i < count; ++i) {
    if (i > 0) {
      f = nullptr;
      if (FT_New_Face(m.lib, path.c_str(), i, &f) != 0) {
        warn("face " + std::to_string(i) + " of the collection is broken, skipped");
        continue;
      }
    }
    const int index = static_cast<int>(i);
    if (m.known.insert({path, index}).second) {
      m.faces.push_back(read_info(f, path, index));
      m.ft.push_back(nullptr);
      m.hb.push_back(nullptr);
      m.open_failed.push_back(false);
      ++added;
    }
    // Closed until first use: a system's fonts would hold thousands open.
    FT_Done_Face(f);
  }
  return added;
}

size_t FontDb::add_dir(const std::string& dir, std::vector<std::string>* warnings) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> files;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  if (ec) {
    if (warnings) warnings->push_back(dir + ": cannot read the folder (" + ec.message() + ")");
    return 0;
  }
  for (const fs::recursive_directory_iterator end; it != end; it.increment(ec)) {
    if (ec) break;
    std::error_code fe;
    if (it->is_regular_file(fe) && is_font_file(it->path())) files.push_back(it->path().string());
  }
  std::sort(files.begin(), files.end());
  size_t added = 0;
  for (const std::string& f : files) added += add_file(f, warnings);
  return added;
}

size_t FontDb::add_system_fonts() {
#ifdef MPVG_HAVE_FONTCONFIG
  // No fontconfig configuration on this machine (a bare container): no
  // system fonts, and no "Cannot load default config file" on stderr.
  // (FcConfigFilename would print that error itself: the file is checked
  // here, FONTCONFIG_FILE's or the usual /etc/fonts/fonts.conf.)
  {
    const char* env = std::getenv("FONTCONFIG_FILE");
    const std::string file = env && *env ? env : "/etc/fonts/fonts.conf";
    std::error_code ec;
    if (!file.empty() && file[0] == '/' && !std::filesystem::exists(file, ec) && !std::getenv("FONTCONFIG_PATH"))
      return 0;
  }
  Impl& m = *impl_;
  {
    std::lock_guard<std::mutex> lock(m.mu);
    if (m.fc) return 0;  // already added
    m.fc = FcInitLoadConfigAndFonts();
    if (!m.fc) return 0;
    m.substitutes.clear();
  }
  // The faces as fontconfig's cache describes them: a text file costs no
  // scan of the system's fonts. Variable fonts are read by FreeType (their
  // default instance's weight and width are not in the cache as numbers).
  FcPattern* pattern = FcPatternCreate();
  FcObjectSet* objects = FcObjectSetBuild(FC_FILE, FC_INDEX, FC_FAMILY, FC_WEIGHT, FC_SLANT, FC_WIDTH,
                                          FC_FONTFORMAT, FC_VARIABLE, FC_OUTLINE, FC_COLOR, nullptr);
  FcFontSet* set = FcFontList(m.fc, pattern, objects);
  struct Listed {
    FaceInfo info;
    bool variable = false;
  };
  std::vector<Listed> listed;
  if (set) {
    for (int i = 0; i < set->nfont; ++i) {
      const FcPattern* p = set->fonts[i];
      FcChar8* file = nullptr;
      FcChar8* family = nullptr;
      FcChar8* format = nullptr;
      int index = 0, slant = 0;
      double weight = 80, width = 100;
      FcBool variable = FcFalse, outline = FcTrue, color = FcFalse;
      if (FcPatternGetString(p, FC_FILE, 0, &file) != FcResultMatch || !file) continue;
      FcPatternGetInteger(p, FC_INDEX, 0, &index);
      if (index < 0 || index >= 0x10000) continue;  // named instances of a variable font: its face is listed
      FcPatternGetBool(p, FC_VARIABLE, 0, &variable);
      FcPatternGetBool(p, FC_OUTLINE, 0, &outline);
      FcPatternGetBool(p, FC_COLOR, 0, &color);
      if (!outline && !color) continue;  // bitmap-only faces give no outlines
      Listed l;
      l.variable = variable;
      l.info.path = reinterpret_cast<const char*>(file);
      l.info.index = index;
      if (FcPatternGetString(p, FC_FAMILY, 0, &family) == FcResultMatch && family)
        l.info.family = reinterpret_cast<const char*>(family);
      FcPatternGetDouble(p, FC_WEIGHT, 0, &weight);
      FcPatternGetInteger(p, FC_SLANT, 0, &slant);
      FcPatternGetDouble(p, FC_WIDTH, 0, &width);
      l.info.weight = std::clamp(static_cast<int>(std::lround(FcWeightToOpenTypeDouble(weight))), 1, 1000);
      l.info.italic = slant >= FC_SLANT_ITALIC;
      // CSS font-stretch keywords 1..9 from fontconfig's percentages.
      static const double widths[9] = {50, 62.5, 75, 87.5, 100, 112.5, 125, 150, 200};
      int nearest = 0;
      for (int k = 1; k < 9; ++k)
        if (std::abs(widths[k] - width) < std::abs(widths[nearest] - width)) nearest = k;
      l.info.stretch = nearest + 1;
      l.info.sfnt = true;
      if (FcPatternGetString(p, FC_FONTFORMAT, 0, &format) == FcResultMatch && format) {
        const std::string f = reinterpret_cast<const char*>(format);
        l.info.sfnt = f == "TrueType" || (f == "CFF" && l.info.path.size() > 4 &&
                                           lower(l.info.path.substr(l.info.path.size() - 4)) == ".otf");
      }
      listed.push_back(std::move(l));
    }
    FcFontSetDestroy(set);
  }
  FcObjectSetDestroy(objects);
  FcPatternDestroy(pattern);
  std::sort(listed.begin(), listed.end(), [](const Listed& a, const Listed& b) {
    return std::tie(a.info.path, a.info.index) < std::tie(b.info.path, b.info.index);
  });
  size_t added = 0;
  for (Listed& l : listed) {
    if (l.variable) {
      added += add_file(l.info.path, nullptr);
      continue;
    }
    std::lock_guard<std::mutex> lock(m.mu);
    if (!m.known.insert({l.info.path, l.info.index}).second) continue;
    m.faces.push_back(std::move(l.info));
    m.ft.push_back(nullptr);
    m.hb.push_back(nullptr);
    m.open_failed.push_back(false);
    ++added;
  }
  return added;
#else
  return 0;
#endif
}

void FontDb::set_generic(const std::string& generic, const std::string& family) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->generic[lower(generic)] = family;
}

const std::vector<FaceInfo>& FontDb::faces() const { return impl_->faces; }

int FontDb::match(const std::vector<std::string>& families, int weight, bool italic, int stretch) const {
  const Impl& m = *impl_;
  std::lock_guard<std::mutex> lock(m.mu);
  if (m.faces.empty()) return -1;
  std::string first_generic;
  for (const std::string& name : families) {
    const std::string key = lower(name);
    if (auto g = m.generic.find(key); g != m.generic.end()) {
      if (first_generic.empty()) first_generic = key;
      std::vector<int> c = m.family_faces(lower(g->second));
      if (c.empty()) c = m.fontconfig_faces(key, true);
      if (!c.empty()) return m.select(c, weight, italic, stretch);
      continue;
    }
    std::vector<int> c = m.family_faces(key);
    if (c.empty()) c = m.fontconfig_faces(key, false);
    if (!c.empty()) return m.select(c, weight, italic, stretch);
  }
  std::vector<int> c;
  if (auto g = m.generic.find("serif"); g != m.generic.end()) c = m.family_faces(lower(g->second));
  if (c.empty()) c = m.fontconfig_faces(first_generic.empty() ? "serif" : first_generic, true);
  if (c.empty()) c = m.heuristic_family(first_generic.empty() ? "serif" : first_generic);
  return m.select(c, weight, italic, stretch);
}

bool FontDb::is_alias(const std::string& family, const std::string& substitute) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  const std::vector<std::string>& list = impl_->fontconfig_families(lower(family), false);
  return std::find(list.begin(), list.end(), lower(substitute)) != list.end();
}

bool FontDb::has_glyph(int face, char32_t c) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  FT_Face f = impl_->face(face);
  return f && FT_Get_Char_Index(f, c) != 0;
}

bool FontDb::has_color_bitmaps(int face) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  FT_Face f = impl_->face(face);
  return f && FT_HAS_COLOR(f) && FT_HAS_FIXED_SIZES(f);
}

int FontDb::fallback(char32_t c, int weight, bool italic) const {
  const Impl& m = *impl_;
  std::lock_guard<std::mutex> lock(m.mu);
  int best = -1;
  long best_cost = 0;
  for (size_t i = 0; i < m.faces.size(); ++i) {
    const long cost = (m.faces[i].italic != italic ? 10000 : 0) + std::abs(m.faces[i].weight - weight) * 10 +
                      std::abs(m.faces[i].stretch - 5);
    if (best >= 0 && cost >= best_cost) continue;
    FT_Face f = m.face(static_cast<int>(i));
    if (f && FT_Get_Char_Index(f, c) != 0) best = static_cast<int>(i), best_cost = cost;
  }
  return best;
}

namespace {

// Sets (or, with an empty list, resets) the variation coordinates of an
// FT_Face from (tag, value) pairs; axes not named keep their defaults.
void set_ft_variations(FT_Library lib, FT_Face f, const std::vector<std::pair<std::string, double>>& v) {
  if (!FT_HAS_MULTIPLE_MASTERS(f)) return;
  if (v.empty()) {
    FT_Set_Var_Design_Coordinates(f, 0, nullptr);
    return;
  }
  FT_MM_Var* mm = nullptr;
  if (FT_Get_MM_Var(f, &mm) != 0) return;
  std::vector<FT_Fixed> coords(mm->num_axis);
  for (FT_UInt a = 0; a < mm->num_axis; ++a) {
    coords[a] = mm->axis[a].def;
    for (const auto& [tag, value] : v) {
      if (tag.size() == 4 && FT_MAKE_TAG(tag[0], tag[1], tag[2], tag[3]) == mm->axis[a].tag) {
        const double lo = mm->axis[a].minimum / 65536.0, hi = mm->axis[a].maximum / 65536.0;
        coords[a] = static_cast<FT_Fixed>(std::lround(std::clamp(value, lo, hi) * 65536.0));
      }
    }
  }
  FT_Set_Var_Design_Coordinates(f, mm->num_axis, coords.data());
  FT_Done_MM_Var(lib, mm);
}

struct OutlineSink {
  Path path;
  double scale = 1;
  bool open = false;
  Vec2 pt(const FT_Vector* v) const { return {v->x * scale, -v->y * scale}; }
};

int sink_move(const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  if (s->open) s->path.close();
  s->path.move_to(s->pt(to));
  s->open = true;
  return 0;
}
int sink_line(const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->path.line_to(s->pt(to));
  return 0;
}
int sink_conic(const FT_Vector* c, const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->path.quad_to(s->pt(c), s->pt(to));
  return 0;
}
int sink_cubic(const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->path.cubic_to(s->pt(c1), s->pt(c2), s->pt(to));
  return 0;
}

}  // namespace

namespace {

// One run of one direction, shaped; glyphs appended to out in visual order
// with clusters as byte offsets into the whole input (run_start added).
void shape_run(hb_font_t* font, std::string_view utf8, size_t run_start, size_t run_len, bool rtl, double size,
               const ShapeOptions& o, const std::vector<hb_feature_t>& features, std::vector<ShapedGlyph>& out) {
  hb_buffer_t* buf = hb_buffer_create();
  // The whole text as context, the run as the part shaped: joining (Arabic)
  // across a run boundary sees its neighbours.
  hb_buffer_add_utf8(buf, utf8.data(), static_cast<int>(utf8.size()), static_cast<unsigned>(run_start),
                     static_cast<int>(run_len));
  hb_buffer_set_direction(buf, o.vertical ? HB_DIRECTION_TTB : rtl ? HB_DIRECTION_RTL : HB_DIRECTION_LTR);
  if (!o.language.empty())
    hb_buffer_set_language(buf, hb_language_from_string(o.language.data(), static_cast<int>(o.language.size())));
  hb_buffer_guess_segment_properties(buf);
  hb_shape(font, buf, features.data(), static_cast<unsigned>(features.size()));

  unsigned n = 0;
  const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(buf, &n);
  const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(buf, nullptr);
  int x_scale = 0, y_scale = 0;
  hb_font_get_scale(font, &x_scale, &y_scale);
  const double kx = size / x_scale, ky = size / y_scale;
  for (unsigned i = 0; i < n; ++i) {
    ShapedGlyph g;
    g.glyph = info[i].codepoint;
    g.cluster = info[i].cluster;  // already an offset into the whole buffer text
    // HarfBuzz's y points up.
    g.x_advance = pos[i].x_advance * kx;
    g.y_advance = -pos[i].y_advance * ky;
    g.x_offset = pos[i].x_offset * kx;
    g.y_offset = -pos[i].y_offset * ky;
    out.push_back(g);
  }
  hb_buffer_destroy(buf);
}

// The input's level runs in visual order (Unicode bidi algorithm, UAX #9,
// through FriBiDi; paragraph level left-to-right): byte start, byte length,
// right-to-left.
struct LevelRun {
  size_t start, len;  // bytes
  bool rtl;
  size_t a = 0, b = 0;  // code points
};

// The level runs of code points cps (offs: each one's byte offset, then the
// text's length) in visual order.
std::vector<LevelRun> visual_runs(const std::vector<char32_t>& code_points, const std::vector<size_t>& offs) {
  std::vector<LevelRun> runs;
  const std::vector<FriBidiChar> cps(code_points.begin(), code_points.end());
  const FriBidiStrIndex len = static_cast<FriBidiStrIndex>(cps.size());
  std::vector<FriBidiCharType> types(cps.size());
  std::vector<FriBidiBracketType> brackets(cps.size());
  std::vector<FriBidiLevel> levels(cps.size(), 0);
  fribidi_get_bidi_types(cps.data(), len, types.data());
  fribidi_get_bracket_types(cps.data(), len, types.data(), brackets.data());
  FriBidiParType base = FRIBIDI_PAR_LTR;
  if (len > 0 && !fribidi_get_par_embedding_levels_ex(types.data(), brackets.data(), len, &base, levels.data()))
    std::fill(levels.begin(), levels.end(), 0);
  struct R {
    size_t a, b;  // code point range
    int level;
  };
  std::vector<R> rs;
  for (size_t i = 0; i < cps.size(); i++) {
    if (rs.empty() || rs.back().level != levels[i]) rs.push_back({i, i + 1, levels[i]});
    else rs.back().b = i + 1;
  }
  // UAX #9 L2: from the highest level down to the lowest odd one, reverse
  // every sequence of runs at that level or above.
  int hi = 0, lo_odd = 1 << 30;
  for (const R& r : rs) {
    hi = std::max(hi, r.level);
    if (r.level % 2) lo_odd = std::min(lo_odd, r.level);
  }
  for (int lvl = hi; lvl >= lo_odd && lvl > 0; lvl--)
    for (size_t i = 0; i < rs.size();) {
      if (rs[i].level < lvl) {
        i++;
        continue;
      }
      size_t j = i;
      while (j < rs.size() && rs[j].level >= lvl) j++;
      std::reverse(rs.begin() + static_cast<long>(i), rs.begin() + static_cast<long>(j));
      i = j;
    }
  for (const R& r : rs) runs.push_back({offs[r.a], offs[r.b] - offs[r.a], (r.level % 2) != 0, r.a, r.b});
  return runs;
}

}  // namespace

std::vector<ShapedGlyph> shape(const FontDb& db, int face, std::string_view utf8, double size,
                               const ShapeOptions& o) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  hb_font_t* font = m.font(face);
  std::vector<ShapedGlyph> out;
  if (!font || utf8.empty()) return out;

  std::vector<hb_variation_t> vars;
  for (const auto& [tag, value] : o.variations)
    if (tag.size() == 4)
      vars.push_back({hb_tag_from_string(tag.data(), 4), static_cast<float>(value)});
  hb_font_set_variations(font, vars.data(), static_cast<unsigned>(vars.size()));

  std::vector<hb_feature_t> features;
  for (const std::string& s : o.features) {
    hb_feature_t f;
    if (parse_feature(s, f)) features.push_back(f);
  }
  std::vector<char32_t> cps;
  std::vector<size_t> offs;
  decode_utf8(utf8, cps, &offs);
  std::vector<LevelRun> runs;
  if (o.bidi && !o.vertical) runs = visual_runs(cps, offs);
  else runs.push_back({0, utf8.size(), o.rtl, 0, cps.size()});
  // Each run cut where the script changes (HarfBuzz shapes one script per
  // buffer: "Text हिन्दी" needs Devanagari's reordering for its second word);
  // characters of no script (spaces, punctuation, marks) go with the run
  // they are in. A right-to-left run's pieces go in reverse order.
  for (const LevelRun& r : runs) {
    std::vector<LevelRun> pieces;
    hb_script_t current = HB_SCRIPT_INVALID;
    for (size_t k = r.a; k < r.b; k++) {
      const hb_script_t sc = hb_unicode_script(hb_unicode_funcs_get_default(), cps[k]);
      const bool neutral = sc == HB_SCRIPT_COMMON || sc == HB_SCRIPT_INHERITED || sc == HB_SCRIPT_UNKNOWN;
      if (pieces.empty() || (!neutral && current != HB_SCRIPT_INVALID && sc != current))
        pieces.push_back({offs[k], 0, r.rtl, k, k});
      if (!neutral) current = sc;
      pieces.back().len = offs[k + 1] - pieces.back().start;
    }
    if (r.rtl) std::reverse(pieces.begin(), pieces.end());
    for (const LevelRun& p : pieces) shape_run(font, utf8, p.start, p.len, p.rtl, size, o, features, out);
  }
  if (!vars.empty()) hb_font_set_variations(font, nullptr, 0);
  return out;
}

void decode_utf8(std::string_view s, std::vector<char32_t>& cps, std::vector<size_t>* offsets) {
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    char32_t cp = n == 1 ? c : n == 2 ? (c & 0x1f) : n == 3 ? (c & 0x0f) : (c & 0x07);
    bool ok = n > 0 && i + n <= s.size();
    for (int k = 1; ok && k < n; k++) {
      const unsigned char d = static_cast<unsigned char>(s[i + k]);
      ok = (d >> 6) == 2;
      cp = (cp << 6) | (d & 0x3f);
    }
    cps.push_back(ok ? cp : 0xfffd);
    if (offsets) offsets->push_back(i);
    i += ok ? n : 1;
  }
  if (offsets) offsets->push_back(s.size());
}

bool letter_spacing_applies(char32_t c) {
  // CSS Text 3 §8.2 (cursive tracking): scripts whose letters join are not
  // spaced apart.
  switch (hb_unicode_script(hb_unicode_funcs_get_default(), c)) {
    case HB_SCRIPT_ARABIC:
    case HB_SCRIPT_SYRIAC:
    case HB_SCRIPT_NKO:
    case HB_SCRIPT_MANICHAEAN:
    case HB_SCRIPT_PSALTER_PAHLAVI:
    case HB_SCRIPT_MANDAIC:
    case HB_SCRIPT_MONGOLIAN:
    case HB_SCRIPT_PHAGS_PA:
    case HB_SCRIPT_DEVANAGARI:
    case HB_SCRIPT_BENGALI:
    case HB_SCRIPT_GURMUKHI:
    case HB_SCRIPT_MODI:
    case HB_SCRIPT_SHARADA:
    case HB_SCRIPT_SYLOTI_NAGRI:
    case HB_SCRIPT_TIRHUTA:
    case HB_SCRIPT_OGHAM: return false;
    default: return true;
  }
}

bool upright_in_vertical(char32_t c) {
  // Unicode's Vertical_Orientation (UAX #50) value U, by ranges: CJK,
  // Hangul, kana, their symbols and punctuation, fullwidth forms, emoji.
  // Brackets, dashes and the prolonged sound mark (Tr) and small kana and
  // full stops (Tu) are not U and turn with the line.
  struct Range {
    char32_t a, b;
  };
  static const Range not_upright[] = {
      {0x3001, 0x3002}, {0x3008, 0x3011}, {0x3014, 0x301F}, {0x3030, 0x3030}, {0x3041, 0x3041},
      {0x3043, 0x3043}, {0x3045, 0x3045}, {0x3047, 0x3047}, {0x3049, 0x3049}, {0x3063, 0x3063},
      {0x3083, 0x3083}, {0x3085, 0x3085}, {0x3087, 0x3087}, {0x308E, 0x308E}, {0x3095, 0x3096},
      {0x309B, 0x309C}, {0x30A0, 0x30A1}, {0x30A3, 0x30A3}, {0x30A5, 0x30A5}, {0x30A7, 0x30A7},
      {0x30A9, 0x30A9}, {0x30C3, 0x30C3}, {0x30E3, 0x30E3}, {0x30E5, 0x30E5}, {0x30E7, 0x30E7},
      {0x30EE, 0x30EE}, {0x30F5, 0x30F6}, {0x30FC, 0x30FC}, {0xFF08, 0xFF09}, {0xFF0C, 0xFF0E},
      {0xFF1A, 0xFF1E}, {0xFF3B, 0xFF3B}, {0xFF3D, 0xFF3F}, {0xFF5B, 0xFF60}, {0xFF61, 0xFFDF},
  };
  static const Range upright[] = {
      {0x00A7, 0x00A7}, {0x00A9, 0x00A9}, {0x00AE, 0x00AE}, {0x00B1, 0x00B1}, {0x00BC, 0x00BE},
      {0x00D7, 0x00D7}, {0x00F7, 0x00F7}, {0x1100, 0x11FF}, {0x1401, 0x167F}, {0x18B0, 0x18FF},
      {0x2E80, 0x2FFF}, {0x3000, 0x31FF}, {0x3200, 0x4DBF}, {0x4E00, 0xA4CF}, {0xA960, 0xA97F},
      {0xAC00, 0xD7FF}, {0xE000, 0xFAFF}, {0xFE10, 0xFE1F}, {0xFE30, 0xFE4F}, {0xFF00, 0xFFEF},
      {0x1F000, 0x1FAFF}, {0x20000, 0x3FFFD},
  };
  for (const Range& r : not_upright)
    if (c >= r.a && c <= r.b) return false;
  for (const Range& r : upright)
    if (c >= r.a && c <= r.b) return true;
  return false;
}

bool has_axis(const FontDb& db, int face, const char* tag) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  FT_Face f = m.face(face);
  if (!f || !FT_HAS_MULTIPLE_MASTERS(f)) return false;
  FT_MM_Var* mm = nullptr;
  if (FT_Get_MM_Var(f, &mm) != 0) return false;
  bool found = false;
  for (FT_UInt a = 0; a < mm->num_axis; ++a)
    found = found || mm->axis[a].tag == FT_MAKE_TAG(tag[0], tag[1], tag[2], tag[3]);
  FT_Done_MM_Var(m.lib, mm);
  return found;
}

Path glyph_outline(const FontDb& db, int face, uint32_t glyph, double size,
                   const std::vector<std::pair<std::string, double>>& variations, double embolden) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  OutlineSink sink;
  FT_Face f = m.face(face);
  if (!f) return sink.path;
  if (!variations.empty()) set_ft_variations(m.lib, f, variations);
  if (FT_Load_Glyph(f, glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP) == 0 &&
      f->glyph->format == FT_GLYPH_FORMAT_OUTLINE && f->glyph->outline.n_contours > 0) {
    sink.scale = size / (f->units_per_EM ? f->units_per_EM : 1000);
    if (embolden > 0) {
      const FT_Pos strength = static_cast<FT_Pos>(std::lround(embolden * (f->units_per_EM ? f->units_per_EM : 1000)));
      FT_Outline_EmboldenXY(&f->glyph->outline, strength, strength);
    }
    FT_Outline_Funcs funcs{};
    funcs.move_to = sink_move;
    funcs.line_to = sink_line;
    funcs.conic_to = sink_conic;
    funcs.cubic_to = sink_cubic;
    funcs.shift = 0;
    funcs.delta = 0;
    if (FT_Outline_Decompose(&f->glyph->outline, &funcs, &sink) == 0) {
      if (sink.open) sink.path.close();
    } else {
      sink.path = Path();
    }
  }
  if (!variations.empty()) set_ft_variations(m.lib, f, {});
  return sink.path;
}

void with_ft_face(const FontDb& db, int face, const std::vector<std::pair<std::string, double>>& variations,
                  const std::function<void(void* ft_face)>& fn) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  FT_Face f = m.face(face);
  const bool vary = f && !variations.empty();
  if (vary) set_ft_variations(m.lib, f, variations);
  struct Reset {  // also when fn throws
    FT_Library lib;
    FT_Face f;
    ~Reset() {
      if (f) set_ft_variations(lib, f, {});
    }
  } reset{m.lib, vary ? f : nullptr};
  fn(f);
}

std::vector<ColorLayer> color_layers(const FontDb& db, int face, uint32_t glyph) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  std::vector<ColorLayer> out;
  FT_Face f = m.face(face);
  if (!f || !FT_HAS_COLOR(f)) return out;
  FT_Color* palette = nullptr;
  FT_Palette_Data pd;
  if (FT_Palette_Data_Get(f, &pd) == 0 && pd.num_palettes > 0) FT_Palette_Select(f, 0, &palette);
  FT_LayerIterator it;
  it.p = nullptr;
  FT_UInt layer_glyph = 0, color_index = 0;
  while (FT_Get_Color_Glyph_Layer(f, glyph, &layer_glyph, &color_index, &it)) {
    ColorLayer l;
    l.glyph = layer_glyph;
    if (color_index == 0xFFFF || !palette || color_index >= pd.num_palette_entries) {
      l.foreground = true;
    } else {
      const FT_Color& c = palette[color_index];
      l.color = {c.red / 255.0f, c.green / 255.0f, c.blue / 255.0f, c.alpha / 255.0f};
    }
    out.push_back(l);
  }
  return out;
}

GlyphBitmap glyph_bitmap(const FontDb& db, int face, uint32_t glyph, double size) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  GlyphBitmap out;
  FT_Face f = m.face(face);
  if (!f || !FT_HAS_COLOR(f) || !FT_HAS_FIXED_SIZES(f) || f->num_fixed_sizes <= 0) return out;
  // The largest strike (as resvg; the texture filter scales it down).
  int best = 0;
  for (int i = 1; i < f->num_fixed_sizes; i++)
    if (f->available_sizes[i].y_ppem > f->available_sizes[best].y_ppem) best = i;
  (void)size;
  // sbix (Apple): the image's lower left corner at the glyph's origin
  // offset plus, where it has an outline, the outline box's lower left
  // corner, as Skia and resvg place it; FreeType's own placement rounds to
  // whole strike pixels and ignores CFF outlines, so it is done here.
  std::optional<Vec2> sbix_corner;  // font units, y up
  FT_ULong sbix_length = 0;
  if (FT_Load_Sfnt_Table(f, FT_MAKE_TAG('s', 'b', 'i', 'x'), 0, nullptr, &sbix_length) == 0 && sbix_length >= 8) {
    std::vector<unsigned char> t(sbix_length);
    FT_Load_Sfnt_Table(f, FT_MAKE_TAG('s', 'b', 'i', 'x'), 0, t.data(), &sbix_length);
    auto u16 = [&](size_t o) { return o + 2 <= t.size() ? unsigned(t[o] << 8 | t[o + 1]) : 0u; };
    auto u32 = [&](size_t o) {
      return o + 4 <= t.size() ? (uint32_t(t[o]) << 24 | uint32_t(t[o + 1]) << 16 | uint32_t(t[o + 2]) << 8 | t[o + 3])
                               : 0u;
    };
    const int want = f->available_sizes[best].y_ppem / 64;
    for (uint32_t i = 0, n = u32(4); i < n && !sbix_corner; i++) {
      const size_t strike = u32(8 + 4 * size_t(i));
      if (int(u16(strike)) != want) continue;
      const size_t data = strike + u32(strike + 4 + 4 * size_t(glyph));
      if (data + 4 > t.size()) break;
      Vec2 corner{double(int16_t(u16(data))), double(int16_t(u16(data + 2)))};
      if (FT_Load_Glyph(f, glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP) == 0 &&
          f->glyph->format == FT_GLYPH_FORMAT_OUTLINE && f->glyph->outline.n_points > 0) {
        FT_BBox box;
        FT_Outline_Get_CBox(&f->glyph->outline, &box);
        corner.x += box.xMin;
        corner.y += box.yMin;
      }
      sbix_corner = corner;
    }
  }
  if (FT_Select_Size(f, best) != 0) return out;
  const bool loaded = FT_Load_Glyph(f, glyph, FT_LOAD_COLOR) == 0;
  const FT_Bitmap& b = f->glyph->bitmap;
  if (loaded && f->glyph->format == FT_GLYPH_FORMAT_BITMAP && b.pixel_mode == FT_PIXEL_MODE_BGRA && b.width > 0 &&
      b.rows > 0) {
    auto im = std::make_shared<Image>();
    im->width = static_cast<int>(b.width);
    im->height = static_cast<int>(b.rows);
    im->rgba8.resize(size_t(b.width) * b.rows * 4);
    for (unsigned y = 0; y < b.rows; y++) {
      const unsigned char* row = b.buffer + static_cast<ptrdiff_t>(y) * b.pitch;
      for (unsigned x = 0; x < b.width; x++) {
        // FreeType's BGRA is premultiplied; Image is straight.
        const unsigned bl = row[4 * x], g = row[4 * x + 1], r = row[4 * x + 2], a = row[4 * x + 3];
        uint8_t* q = &im->rgba8[(size_t(y) * b.width + x) * 4];
        q[0] = static_cast<uint8_t>(a ? std::min(255u, (r * 255 + a / 2) / a) : 0);
        q[1] = static_cast<uint8_t>(a ? std::min(255u, (g * 255 + a / 2) / a) : 0);
        q[2] = static_cast<uint8_t>(a ? std::min(255u, (bl * 255 + a / 2) / a) : 0);
        q[3] = static_cast<uint8_t>(a);
      }
    }
    const double ppem = f->size->metrics.y_ppem > 0 ? f->size->metrics.y_ppem : f->available_sizes[best].y_ppem / 64.0;
    out.scale = size / ppem;
    out.x = f->glyph->bitmap_left * out.scale;
    out.y = -f->glyph->bitmap_top * out.scale;
    if (sbix_corner) {
      const double k = size / (f->units_per_EM ? f->units_per_EM : 1000);
      out.x = sbix_corner->x * k;
      out.y = -sbix_corner->y * k - b.rows * out.scale;
    }
    out.image = std::move(im);
  }
  return out;  // (outlines load unscaled: the strike chosen does not matter to them)
}

std::optional<SvgDocument> svg_document(const FontDb& db, int face, uint32_t glyph) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  FT_Face f = m.face(face);
  const FT_ULong tag = FT_MAKE_TAG('S', 'V', 'G', ' ');
  FT_ULong size = 0;
  if (!f || glyph > 0xFFFF || FT_Load_Sfnt_Table(f, tag, 0, nullptr, &size) != 0) return std::nullopt;
  // Pieces of the table, not all of it: Twitter Color Emoji's is 10 MB
  // and a glyph needs its record and its document.
  std::vector<unsigned char> b;
  auto read = [&](FT_ULong at, FT_ULong n) {
    if (at > size || n > size - at) return false;
    b.resize(n);
    FT_ULong length = n;
    return n == 0 || FT_Load_Sfnt_Table(f, tag, at, b.data(), &length) == 0;
  };
  auto u16 = [&](size_t o) { return uint32_t(b[o]) << 8 | b[o + 1]; };
  auto u32 = [&](size_t o) { return u16(o) << 16 | u16(o + 2); };
  // Header: version, svgDocumentListOffset, reserved. The list: numEntries,
  // then records {startGlyphID, endGlyphID, svgDocOffset (from the list),
  // svgDocLength}, sorted by glyph and not overlapping.
  if (!read(0, 10)) return std::nullopt;
  const FT_ULong list = u32(2);
  if (!read(list, 2)) return std::nullopt;
  const size_t entries = u16(0);
  if (!read(list + 2, 12 * entries)) return std::nullopt;
  // The first record that ends at or after the glyph: the glyph's, if it
  // starts at or before it.
  size_t lo = 0, hi = entries;
  while (lo < hi) {
    const size_t mid = (lo + hi) / 2;
    if (u16(12 * mid + 2) < glyph) lo = mid + 1;
    else hi = mid;
  }
  if (lo == entries || glyph < u16(12 * lo)) return std::nullopt;
  SvgDocument out;
  out.first_glyph = u16(12 * lo);
  out.last_glyph = u16(12 * lo + 2);
  // A document for one glyph is kilobytes; the cap keeps a broken length
  // or gzip size field (ISIZE) from asking for gigabytes.
  constexpr size_t kMaxDocument = size_t(64) << 20;
  const size_t length = u32(12 * lo + 8);
  if (length > kMaxDocument || !read(list + u32(12 * lo + 4), length)) return std::nullopt;
  if (b.size() >= 18 && b[0] == 0x1F && b[1] == 0x8B) {
    // gzip (RFC 1952): ISIZE, the last four bytes, little-endian, is the
    // inflated size modulo 2^32; FreeType's inflate detects the header.
    const size_t n = b.size();
    const size_t inflated = uint32_t(b[n - 4]) | uint32_t(b[n - 3]) << 8 | uint32_t(b[n - 2]) << 16 |
                            uint32_t(b[n - 1]) << 24;
    if (inflated == 0 || inflated > kMaxDocument) return std::nullopt;
    out.text.resize(inflated);
    FT_ULong length = inflated;
    if (FT_Gzip_Uncompress(f->memory, reinterpret_cast<FT_Byte*>(out.text.data()), &length, b.data(), n) != 0 ||
        length != inflated)
      return std::nullopt;
  } else {
    out.text.assign(b.begin(), b.end());
  }
  return out;
}

Metrics metrics(const FontDb& db, int face, double size) {
  FontDb::Impl& m = db.impl();
  std::lock_guard<std::mutex> lock(m.mu);
  Metrics r;
  FT_Face f = m.face(face);
  if (!f) return r;
  const double upem = f->units_per_EM ? f->units_per_EM : 1000;
  const double k = size / upem;
  r.units_per_em = upem;
  const auto* os2 = static_cast<const TT_OS2*>(FT_Get_Sfnt_Table(f, FT_SFNT_OS2));
  if (os2 && os2->version == 0xFFFF) os2 = nullptr;

  // FreeType's ascender/descender come from hhea (OS/2 typo values when hhea
  // has none); USE_TYPO_METRICS (fsSelection bit 7) asks for the typo ones.
  double asc = f->ascender, desc = -f->descender;
  if (os2 && (os2->fsSelection & (1u << 7)) && os2->sTypoAscender != 0) {
    asc = os2->sTypoAscender;
    desc = -os2->sTypoDescender;
  }
  if (asc == 0 && desc == 0) asc = 0.8 * upem, desc = 0.2 * upem;
  r.ascent = asc * k;
  r.descent = desc * k;

  // The top of a glyph's unscaled outline, or 0 when the font lacks it.
  auto glyph_top = [&](char32_t c) -> double {
    const FT_UInt g = FT_Get_Char_Index(f, c);
    if (!g || FT_Load_Glyph(f, g, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP) != 0) return 0;
    if (f->glyph->format != FT_GLYPH_FORMAT_OUTLINE) return 0;
    FT_BBox box;
    FT_Outline_Get_CBox(&f->glyph->outline, &box);
    return static_cast<double>(box.yMax);
  };
  double xh = os2 && os2->version >= 2 ? os2->sxHeight : 0;
  double caph = os2 && os2->version >= 2 ? os2->sCapHeight : 0;
  if (xh <= 0) xh = glyph_top(U'x');
  if (caph <= 0) caph = glyph_top(U'H');
  if (xh <= 0) xh = 0.5 * upem;
  if (caph <= 0) caph = 0.7 * upem;
  r.x_height = xh * k;
  r.cap_height = caph * k;

  // post: underlinePosition is the top of the line, y up (negative below).
  double ut = f->underline_thickness > 0 ? f->underline_thickness : upem / 14.0;
  double up = f->underline_position != 0 ? f->underline_position : -0.1 * upem;
  r.underline_thickness = ut * k;
  r.underline_position = -up * k;
  double st = os2 && os2->yStrikeoutSize > 0 ? os2->yStrikeoutSize : ut;
  double sp = os2 && os2->yStrikeoutPosition > 0 ? os2->yStrikeoutPosition : xh / 2;
  r.strikeout_thickness = st * k;
  r.strikeout_position = -sp * k;
  r.subscript_offset = (os2 && os2->ySubscriptYOffset != 0 ? os2->ySubscriptYOffset : upem / 5.0) * k;
  r.superscript_offset = (os2 && os2->ySuperscriptYOffset != 0 ? os2->ySuperscriptYOffset : upem / 3.0) * k;
  return r;
}

}  // namespace mpvg::text
