// Font engine tests (text/text.h) on the DejaVu fonts of Debian's
// fonts-dejavu-core (scripts/setup-debian.sh installs it). Each test copies
// the files it needs into a scratch folder, so the face counts do not depend
// on what else /usr/share/fonts holds; without the fonts every test says so
// and passes without checking anything.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/catch.h"
#include "text/text.h"

namespace fs = std::filesystem;
namespace tx = mpvg::text;

namespace {

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/";
const std::vector<std::string> kFiles = {"DejaVuSans.ttf", "DejaVuSans-Bold.ttf", "DejaVuSerif.ttf"};

bool have_fonts() {
  for (const std::string& f : kFiles)
    if (!fs::exists(kDejaVu + f)) {
      WARN("SKIPPED: " << kDejaVu << f << " is absent (Debian package fonts-dejavu-core)");
      return false;
    }
  return true;
}

// A scratch folder with the three DejaVu files, one in a subfolder.
struct FontDir {
  fs::path dir;
  FontDir() {
    std::random_device rd;
    dir = fs::temp_directory_path() / ("mpvg_text_" + std::to_string(rd()));
    fs::create_directories(dir / "sub");
    fs::copy_file(kDejaVu + kFiles[0], dir / kFiles[0]);
    fs::copy_file(kDejaVu + kFiles[1], dir / "sub" / kFiles[1]);
    fs::copy_file(kDejaVu + kFiles[2], dir / kFiles[2]);
    std::ofstream(dir / "README.txt") << "not a font";
  }
  ~FontDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

int find_face(const tx::FontDb& db, const std::string& family, int weight) {
  for (size_t i = 0; i < db.faces().size(); ++i)
    if (db.faces()[i].family == family && db.faces()[i].weight == weight) return static_cast<int>(i);
  return -1;
}

double advance_sum(const std::vector<tx::ShapedGlyph>& g) {
  double s = 0;
  for (const auto& x : g) s += x.x_advance;
  return s;
}

struct Box {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
};
Box bounds(const mpvg::Path& p) {
  Box b;
  for (const mpvg::Vec2& v : p.points()) {
    b.x0 = std::min(b.x0, v.x), b.y0 = std::min(b.y0, v.y);
    b.x1 = std::max(b.x1, v.x), b.y1 = std::max(b.y1, v.y);
  }
  return b;
}

uint32_t glyph_of(const tx::FontDb& db, int face, const char* utf8) {
  const auto g = tx::shape(db, face, utf8, 1000);
  REQUIRE(g.size() == 1);
  return g[0].glyph;
}

std::vector<unsigned char> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint32_t be32(const std::vector<unsigned char>& b, size_t at) {
  return (uint32_t(b[at]) << 24) | (uint32_t(b[at + 1]) << 16) | (uint32_t(b[at + 2]) << 8) | b[at + 3];
}
void put32(std::vector<unsigned char>& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<unsigned char>(v >> s));
}
void set32(std::vector<unsigned char>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}

// A TrueType collection of whole TrueType files (OpenType spec, "TTC
// header" version 1.0): each font's table directory, copied, then its
// tables, with the directory's offsets made absolute in the new file.
std::vector<unsigned char> make_ttc(const std::vector<std::vector<unsigned char>>& fonts) {
  std::vector<unsigned char> out = {'t', 't', 'c', 'f', 0, 1, 0, 0};
  put32(out, static_cast<uint32_t>(fonts.size()));
  const size_t offsets_at = out.size();
  for (size_t i = 0; i < fonts.size(); ++i) put32(out, 0);
  for (size_t i = 0; i < fonts.size(); ++i) {
    const auto& f = fonts[i];
    const size_t tables = (size_t(f[4]) << 8) | f[5];
    const size_t dir_at = out.size();
    set32(out, offsets_at + 4 * i, static_cast<uint32_t>(dir_at));
    out.insert(out.end(), f.begin(), f.begin() + 12 + 16 * tables);
    for (size_t t = 0; t < tables; ++t) {
      const size_t rec = 12 + 16 * t;
      const uint32_t off = be32(f, rec + 8), len = be32(f, rec + 12);
      while (out.size() % 4) out.push_back(0);
      set32(out, dir_at + rec + 8, static_cast<uint32_t>(out.size()));
      out.insert(out.end(), f.begin() + off, f.begin() + off + len);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("add_dir finds every face under the folder and reads family, weight, style", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  std::vector<std::string> warnings;
  CHECK(db.add_dir(d.dir.string(), &warnings) == 3);
  CHECK(warnings.empty());
  REQUIRE(db.faces().size() == 3);
  // Sorted path order: DejaVuSans.ttf, DejaVuSerif.ttf, sub/DejaVuSans-Bold.ttf.
  CHECK(db.faces()[0].family == "DejaVu Sans");
  CHECK(db.faces()[0].weight == 400);
  CHECK(db.faces()[1].family == "DejaVu Serif");
  CHECK(db.faces()[2].family == "DejaVu Sans");
  CHECK(db.faces()[2].weight == 700);
  for (const auto& f : db.faces()) {
    CHECK_FALSE(f.italic);
    CHECK(f.stretch == 5);
    CHECK(f.index == 0);
  }
  // The same files again add nothing.
  CHECK(db.add_dir(d.dir.string()) == 0);
  CHECK(db.faces().size() == 3);
  // An oblique face, where the system has it, reads as italic.
  const std::string oblique = std::string(kDejaVu) + "DejaVuSans-Oblique.ttf";
  if (fs::exists(oblique)) {
    REQUIRE(db.add_file(oblique) == 1);
    CHECK(db.faces().back().italic);
  }
}

TEST_CASE("every face of a collection", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  const auto ttc = make_ttc({read_bytes(std::string(kDejaVu) + kFiles[2]), read_bytes(std::string(kDejaVu) + kFiles[1])});
  const fs::path dir = d.dir / "collection";
  fs::create_directories(dir);
  {
    std::ofstream out(dir / "Pair.TTC", std::ios::binary);
    out.write(reinterpret_cast<const char*>(ttc.data()), static_cast<std::streamsize>(ttc.size()));
  }
  tx::FontDb db;
  std::vector<std::string> warnings;
  REQUIRE(db.add_dir(dir.string(), &warnings) == 2);
  CHECK(warnings.empty());
  CHECK(db.faces()[0].family == "DejaVu Serif");
  CHECK(db.faces()[0].index == 0);
  CHECK(db.faces()[1].family == "DejaVu Sans");
  CHECK(db.faces()[1].weight == 700);
  CHECK(db.faces()[1].index == 1);
  CHECK(db.match({"DejaVu Sans"}, 400, false) == 1);
  // The second face really is the bold one: its 'l' is wider than the
  // regular face's.
  REQUIRE(db.add_file(std::string(kDejaVu) + kFiles[0]) == 1);
  const auto l1 = tx::shape(db, 1, "l", 100), l2 = tx::shape(db, 2, "l", 100);
  REQUIRE(l1.size() == 1);
  REQUIRE(l2.size() == 1);
  CHECK(l1[0].x_advance > l2[0].x_advance);
  CHECK(tx::glyph_outline(db, 1, l1[0].glyph, 100).contours().size() == 1);
  CHECK(db.has_glyph(1, U'A'));
}

TEST_CASE("a broken font file is skipped with one warning", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  {
    std::ofstream out(d.dir / "broken.ttf", std::ios::binary);
    std::mt19937 rng(13);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>(rng()));
  }
  std::ofstream(d.dir / "empty.otf").close();
  tx::FontDb db;
  std::vector<std::string> warnings;
  CHECK(db.add_dir(d.dir.string(), &warnings) == 3);
  REQUIRE(warnings.size() == 2);
  CHECK(warnings[0].find("broken.ttf") != std::string::npos);
  CHECK(warnings[1].find("empty.otf") != std::string::npos);
  warnings.clear();
  CHECK(db.add_file((d.dir / "missing.ttf").string(), &warnings) == 0);
  CHECK(warnings.size() == 1);
  warnings.clear();
  CHECK(db.add_dir((d.dir / "nothing-here").string(), &warnings) == 0);
  CHECK(warnings.size() == 1);
}

TEST_CASE("match follows CSS font matching", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  CHECK(db.match({"DejaVu Sans"}, 400, false) == -1);  // empty db
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);
  const int bold = find_face(db, "DejaVu Sans", 700);
  const int serif = find_face(db, "DejaVu Serif", 400);
  REQUIRE(sans >= 0);
  REQUIRE(bold >= 0);
  REQUIRE(serif >= 0);

  CHECK(db.match({"DejaVu Sans"}, 400, false) == sans);
  CHECK(db.match({"DejaVu Sans"}, 700, false) == bold);
  CHECK(db.match({"dejavu sans"}, 700, false) == bold);  // names are case-insensitive
  // Weights between: 500 looks at 400..500 then down; 600 looks up first;
  // 300 looks down, then up.
  CHECK(db.match({"DejaVu Sans"}, 500, false) == sans);
  CHECK(db.match({"DejaVu Sans"}, 600, false) == bold);
  CHECK(db.match({"DejaVu Sans"}, 900, false) == bold);
  CHECK(db.match({"DejaVu Sans"}, 300, false) == sans);
  CHECK(db.match({"DejaVu Serif"}, 700, false) == serif);  // the only face of the family
  // No italic face: the normal one.
  CHECK(db.match({"DejaVu Sans"}, 700, true) == bold);
  // The first family of the list that exists.
  CHECK(db.match({"No Such Font", "DejaVu Serif", "DejaVu Sans"}, 400, false) == serif);
  // Generic families through their mapping.
  db.set_generic("serif", "DejaVu Serif");
  db.set_generic("sans-serif", "DejaVu Sans");
  CHECK(db.match({"Missing", "sans-serif"}, 700, false) == bold);
  CHECK(db.match({"SERIF"}, 400, false) == serif);
  // Nothing found: the serif mapping.
  CHECK(db.match({"Missing"}, 400, false) == serif);
  // Nothing found and no serif mapping present: still a face of the db.
  db.set_generic("serif", "Noto Serif");
  const int any = db.match({"Missing"}, 400, false);
  CHECK(any >= 0);
  CHECK(any < static_cast<int>(db.faces().size()));
}

TEST_CASE("match: stretch before style before weight", "[text]") {
  if (!have_fonts()) return;
  const std::string cond = std::string(kDejaVu) + "DejaVuSansCondensed.ttf";
  if (!fs::exists(cond)) {
    WARN("SKIPPED: " << cond << " is absent (fonts-dejavu-extra)");
    return;
  }
  tx::FontDb db;
  db.add_file(std::string(kDejaVu) + "DejaVuSans-Bold.ttf");
  db.add_file(cond);
  REQUIRE(db.faces()[1].stretch < 5);
  REQUIRE(db.faces()[1].family == "DejaVu Sans");
  // Normal width asked: the bold normal-width face beats the regular
  // condensed one; condensed asked: the condensed face whatever the weight.
  CHECK(db.match({"DejaVu Sans"}, 400, false, 5) == 0);
  CHECK(db.match({"DejaVu Sans"}, 700, false, 3) == 1);
}

TEST_CASE("has_glyph and per-character fallback", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  CHECK(db.fallback(U'A', 400, false) == -1);
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);
  const int bold = find_face(db, "DejaVu Sans", 700);
  const int serif = find_face(db, "DejaVu Serif", 400);
  CHECK(db.has_glyph(sans, U'A'));
  CHECK(db.has_glyph(sans, U'\u03A9'));         // Greek capital omega
  CHECK_FALSE(db.has_glyph(sans, U'\u4E00'));   // CJK: not in DejaVu
  CHECK_FALSE(db.has_glyph(sans, U'\U0010FFFD'));
  CHECK_FALSE(db.has_glyph(99, U'A'));          // no such face
  // Same weight preferred.
  CHECK(db.fallback(U'A', 700, false) == bold);
  const int a400 = db.fallback(U'A', 400, false);
  CHECK((a400 == sans || a400 == serif));
  CHECK(db.fallback(U'\u4E00', 400, false) == -1);
  // A character only DejaVu Sans has, among these three: the Braille block.
  if (db.has_glyph(sans, U'\u2801') && !db.has_glyph(serif, U'\u2801')) {
    const int f = db.fallback(U'\u2801', 400, false);
    CHECK((f == sans || f == bold));
  }
}

TEST_CASE("shape: kerning, ligatures, clusters", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);

  const auto av = tx::shape(db, sans, "AV", 100);
  tx::ShapeOptions nokern;
  nokern.features = {"-kern"};
  const auto av_plain = tx::shape(db, sans, "AV", 100, nokern);
  REQUIRE(av.size() == 2);
  REQUIRE(av_plain.size() == 2);
  CHECK(advance_sum(av) < advance_sum(av_plain) - 1);
  // The CSS spelling of the same.
  nokern.features = {"\"kern\" off"};
  CHECK(advance_sum(tx::shape(db, sans, "AV", 100, nokern)) == Approx(advance_sum(av_plain)));
  // Advances scale with size, and are exact (no hinting).
  CHECK(advance_sum(tx::shape(db, sans, "AV", 200, nokern)) == Approx(2 * advance_sum(av_plain)));
  CHECK(av[0].cluster == 0);
  CHECK(av[1].cluster == 1);

  // DejaVu Sans has an "fi" ligature (uniFB01) reached through liga.
  const bool has_fi = db.has_glyph(sans, U'\uFB01');
  const char* lig_text = has_fi ? "fi" : "ffl";
  const auto lig = tx::shape(db, sans, lig_text, 100);
  tx::ShapeOptions noliga;
  noliga.features = {"\"liga\" 0"};
  const auto split = tx::shape(db, sans, lig_text, 100, noliga);
  INFO("ligature text " << lig_text);
  CHECK(lig.size() == 1);
  CHECK(split.size() == std::string(lig_text).size());
  CHECK(lig[0].cluster == 0);
  for (size_t i = 0; i < split.size(); ++i) CHECK(split[i].cluster == i);

  // Clusters are byte offsets in the UTF-8 input: "é" takes two bytes.
  const auto e = tx::shape(db, sans, "\xC3\xA9" "a", 100);
  REQUIRE(e.size() == 2);
  CHECK(e[0].cluster == 0);
  CHECK(e[1].cluster == 2);

  // Right to left: glyphs in visual order, clusters descending.
  tx::ShapeOptions rtl;
  rtl.rtl = true;
  const auto r = tx::shape(db, sans, "ab", 100, rtl);
  REQUIRE(r.size() == 2);
  CHECK(r[0].cluster == 1);
  CHECK(r[1].cluster == 0);

  // Vertical: advances go down (y down is positive).
  tx::ShapeOptions vert;
  vert.vertical = true;
  const auto v = tx::shape(db, sans, "ab", 100, vert);
  REQUIRE(v.size() == 2);
  CHECK(v[0].y_advance > 0);
  CHECK(v[0].x_advance == 0);

  CHECK(tx::shape(db, sans, "", 100).empty());
  CHECK(tx::shape(db, 42, "AV", 100).empty());
}

TEST_CASE("shape with bidi: level runs shaped in their direction, in visual order", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);
  // "ab " then three Hebrew letters (2 bytes each, at bytes 3, 5, 7), then
  // " cd": the paragraph is left to right, the Hebrew run right to left.
  const std::string text = "ab \u05D0\u05D1\u05D2 cd";
  tx::ShapeOptions o;
  o.bidi = true;
  const auto g = tx::shape(db, sans, text, 100, o);
  std::vector<uint32_t> clusters;
  for (const auto& x : g) clusters.push_back(x.cluster);
  CHECK(clusters == std::vector<uint32_t>{0, 1, 2, 7, 5, 3, 9, 10, 11});
  // Without bidi the buffer is one left-to-right run, in logical order.
  const auto plain = tx::shape(db, sans, text, 100);
  std::vector<uint32_t> logical;
  for (const auto& x : plain) logical.push_back(x.cluster);
  CHECK(std::is_sorted(logical.begin(), logical.end()));
  // An all-Arabic word is one right-to-left run: clusters descend, and the
  // letters take their joining forms (other glyphs than isolated ones).
  const auto word = tx::shape(db, sans, "\u0628\u064A\u062A", 100, o);
  REQUIRE(word.size() == 3);
  CHECK(word[0].cluster == 4);
  CHECK(word[2].cluster == 0);
  const auto isolated = tx::shape(db, sans, "\u0628", 100, o);
  REQUIRE(isolated.size() == 1);
  CHECK(word[2].glyph != isolated[0].glyph);
}

TEST_CASE("shape: one script per HarfBuzz buffer", "[text]") {
  // Latin then Devanagari in one call: the Devanagari word is shaped as
  // Devanagari (its vowel sign i drawn before the consonant), not as Latin.
  const char* lohit = "/usr/share/fonts/truetype/lohit-devanagari/Lohit-Devanagari.ttf";
  if (!fs::exists(lohit)) {
    WARN("SKIPPED: " << lohit << " is absent (Debian package fonts-lohit-deva)");
    return;
  }
  tx::FontDb db;
  REQUIRE(db.add_file(lohit) == 1);
  tx::ShapeOptions o;
  o.bidi = true;
  const auto alone = tx::shape(db, 0, "\u0939\u093F", 100, o);  // हि
  const auto mixed = tx::shape(db, 0, "Te \u0939\u093F", 100, o);
  REQUIRE(alone.size() == 2);
  REQUIRE(mixed.size() == 5);
  CHECK(mixed[3].glyph == alone[0].glyph);
  CHECK(mixed[4].glyph == alone[1].glyph);
  // The sign comes first: reordered.
  CHECK(alone[0].glyph != tx::shape(db, 0, "\u0939", 100, o)[0].glyph);
}

TEST_CASE("letter_spacing_applies and upright_in_vertical", "[text]") {
  CHECK(tx::letter_spacing_applies(U'a'));
  CHECK(tx::letter_spacing_applies(U'\u05D0'));   // Hebrew does not join
  CHECK(!tx::letter_spacing_applies(U'\u0628'));  // Arabic does
  CHECK(!tx::letter_spacing_applies(U'\u0915'));  // Devanagari
  CHECK(tx::upright_in_vertical(U'\u65E5'));      // 日
  CHECK(tx::upright_in_vertical(U'\u30C6'));      // テ
  CHECK(!tx::upright_in_vertical(U'\u30FC'));     // ー turns with the line
  CHECK(!tx::upright_in_vertical(U'A'));
  CHECK(!tx::upright_in_vertical(U'\u3002'));     // 。
}

TEST_CASE("glyph_outline: contours, scale, y down", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);

  const uint32_t o = glyph_of(db, sans, "O");
  const mpvg::Path p100 = tx::glyph_outline(db, sans, o, 100);
  const mpvg::Path p300 = tx::glyph_outline(db, sans, o, 300);
  REQUIRE(p100.contours().size() == 2);
  for (const auto& c : p100.contours()) CHECK(c.closed);
  // TrueType: quadratic curves, no cubics.
  size_t quads = 0;
  for (const auto& s : p100.segments()) {
    CHECK(s.type != mpvg::SegmentType::Cubic);
    quads += s.type == mpvg::SegmentType::Quad;
  }
  CHECK(quads > 4);
  const Box b1 = bounds(p100), b3 = bounds(p300);
  CHECK(b3.x0 == Approx(3 * b1.x0));
  CHECK(b3.x1 == Approx(3 * b1.x1));
  CHECK(b3.y0 == Approx(3 * b1.y0));
  CHECK(b3.y1 == Approx(3 * b1.y1));
  CHECK(b1.x1 - b1.x0 > 50);

  // 'H' stands on the baseline and rises to the cap height: negative y.
  const uint32_t h = glyph_of(db, sans, "H");
  const Box bh = bounds(tx::glyph_outline(db, sans, h, 1000));
  const tx::Metrics m = tx::metrics(db, sans, 1000);
  CHECK(bh.y1 == Approx(0).margin(1e-9));
  CHECK(bh.y0 == Approx(-m.cap_height).margin(1));
  CHECK(bh.y0 < -600);

  // The space has no outline.
  CHECK(tx::glyph_outline(db, sans, glyph_of(db, sans, " "), 100).empty());
  CHECK(tx::glyph_outline(db, 42, o, 100).empty());
}

TEST_CASE("metrics from the font's tables", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  db.add_dir(d.dir.string());
  const int sans = find_face(db, "DejaVu Sans", 400);
  const tx::Metrics m = tx::metrics(db, sans, 2048);
  CHECK(m.units_per_em == 2048);
  // DejaVu Sans: hhea ascender 1901, descender -483 (font units, 2048/em).
  CHECK(m.ascent == Approx(1901));
  CHECK(m.descent == Approx(483));
  CHECK(m.x_height > 1000);
  CHECK(m.x_height < m.cap_height);
  CHECK(m.cap_height < m.ascent);
  CHECK(m.underline_position > 0);
  CHECK(m.underline_thickness > 0);
  CHECK(m.strikeout_position < 0);
  CHECK(-m.strikeout_position < m.x_height);
  CHECK(m.strikeout_thickness > 0);
  const tx::Metrics half = tx::metrics(db, sans, 1024);
  CHECK(half.ascent == Approx(m.ascent / 2));
  CHECK(half.underline_position == Approx(m.underline_position / 2));
}

TEST_CASE("one db shared by threads gives the single-threaded results", "[text]") {
  if (!have_fonts()) return;
  FontDir d;
  tx::FontDb db;
  db.add_dir(d.dir.string());
  const std::string text = "Waffle AV fi Typography";
  auto work = [&](int face) {
    double sum = 0;
    for (const auto& g : tx::shape(db, face, text, 37))
      sum += g.x_advance + static_cast<double>(tx::glyph_outline(db, face, g.glyph, 37).points().size());
    return sum + tx::metrics(db, face, 37).ascent + (db.has_glyph(face, U'W') ? 1 : 0);
  };
  std::vector<double> expected;
  for (int f = 0; f < 3; ++f) expected.push_back(work(f));
  std::vector<double> got(12);
  {
    std::vector<std::thread> threads;
    for (int t = 0; t < 12; ++t)
      threads.emplace_back([&, t] {
        for (int k = 0; k < 20; ++k) got[t] = work(t % 3);
      });
    for (auto& t : threads) t.join();
  }
  for (int t = 0; t < 12; ++t) CHECK(got[t] == expected[t % 3]);
}

// URW's base 35 (Debian's fonts-urw-base35, installed by
// scripts/setup-debian.sh) ships each face as OpenType CFF (.otf) and as
// Type 1 (.t1): the two must shape and draw alike, Type 1 through
// FreeType's cmap and advances.
TEST_CASE("Type 1 faces shape and draw as their OpenType twins", "[text]") {
  const std::string otf = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";
  const std::string t1 = "/usr/share/fonts/type1/urw-base35/NimbusSans-Regular.t1";
  if (!fs::exists(otf) || !fs::exists(t1)) {
    WARN("SKIPPED: URW base 35 fonts are absent (Debian package fonts-urw-base35)");
    return;
  }
  tx::FontDb db;
  REQUIRE(db.add_file(otf) == 1);
  REQUIRE(db.add_file(t1) == 1);
  REQUIRE(db.faces().size() == 2);
  CHECK(db.faces()[0].sfnt);
  CHECK_FALSE(db.faces()[1].sfnt);
  CHECK(db.faces()[0].family == db.faces()[1].family);
  // Same family and style: the OpenType face is the match.
  CHECK(db.match({"Nimbus Sans"}, 400, false) == 0);
  // Letter by letter: the OpenType face also kerns pairs (GPOS), which a
  // Type 1 file without its AFM cannot.
  for (char c : std::string("Label Ag 0123")) {
    INFO("'" << c << "'");
    const std::vector<tx::ShapedGlyph> a = tx::shape(db, 0, std::string(1, c), 100);
    const std::vector<tx::ShapedGlyph> b = tx::shape(db, 1, std::string(1, c), 100);
    REQUIRE(a.size() == 1);
    REQUIRE(b.size() == 1);
    CHECK(b[0].glyph != 0);
    CHECK(std::abs(b[0].x_advance - a[0].x_advance) < 0.05);
    const mpvg::Path pa = tx::glyph_outline(db, 0, a[0].glyph, 100), pb = tx::glyph_outline(db, 1, b[0].glyph, 100);
    CHECK(pa.empty() == pb.empty());
    if (pa.empty()) continue;
    // The boxes of the control points (both are the same cubic design).
    auto box = [](const mpvg::Path& p) {
      std::vector<double> b = {1e9, 1e9, -1e9, -1e9};
      for (const mpvg::Vec2& q : p.points())
        b = {std::min(b[0], q.x), std::min(b[1], q.y), std::max(b[2], q.x), std::max(b[3], q.y)};
      return b;
    };
    const std::vector<double> ba = box(pa), bb = box(pb);
    for (int k = 0; k < 4; k++) CHECK(std::abs(ba[k] - bb[k]) < 0.2);
  }
}

// fontconfig as the oracle: a family the system lacks resolves to the
// family fontconfig's own match gives (its aliases: Helvetica to Nimbus
// Sans, Arial to Liberation Sans, ...), and the system's fonts come from
// its cache with the faces' own family, weight and style.
TEST_CASE("system fonts: families resolved as fontconfig resolves them", "[text]") {
  tx::FontDb db;
  if (db.add_system_fonts() == 0) {
    WARN("SKIPPED: no fontconfig, or no system fonts");
    return;
  }
  bool urw = false, liberation = false;
  for (const tx::FaceInfo& f : db.faces()) {
    urw = urw || f.family == "Nimbus Sans";
    liberation = liberation || f.family == "Liberation Sans";
  }
  if (!urw || !liberation) {
    WARN("SKIPPED: URW base 35 or Liberation fonts are absent (fonts-urw-base35, fonts-liberation)");
    return;
  }
  // fc-match's answer for each name, through the library.
  auto fc_match = [](const std::string& name) {
    std::string out;
    std::string cmd = "fc-match -f '%{family[0]}' '" + name + "' 2>/dev/null";
    if (FILE* p = popen(cmd.c_str(), "r")) {
      char buf[256];
      while (fgets(buf, sizeof buf, p)) out += buf;
      pclose(p);
    }
    return out;
  };
  for (const char* name : {"Helvetica", "Arial", "Times New Roman", "Times", "Courier", "Courier New",
                           "Bitstream Vera Sans"}) {
    const std::string want = fc_match(name);
    if (want.empty()) {
      WARN("SKIPPED: fc-match is absent");
      return;
    }
    const int face = db.match({name}, 400, false);
    REQUIRE(face >= 0);
    INFO(name << ": fontconfig " << want << ", matched " << db.faces()[face].family);
    CHECK(db.faces()[face].family == want);
    CHECK(db.is_alias(name, want));
    // Matched and drawn: the face has the letters.
    CHECK(db.has_glyph(face, U'L'));
    CHECK_FALSE(tx::shape(db, face, "Label", 20).empty());
  }
  // A family the document's list names first, when present, wins over
  // the aliases of an earlier absent one only in list order.
  const int f = db.match({"No Such Family 7f3a", "Liberation Sans"}, 400, false);
  CHECK(db.faces()[f].family == "Liberation Sans");
  CHECK_FALSE(db.is_alias("No Such Family 7f3a", "DejaVu Sans"));
  // The cache's description of a face agrees with the face itself.
  const int bold = db.match({"Nimbus Sans"}, 700, true);
  CHECK(db.faces()[bold].weight == 700);
  CHECK(db.faces()[bold].italic);
  CHECK(db.faces()[bold].sfnt);
}
