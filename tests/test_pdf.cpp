// The PDF frontend (parsers/pdf/) on small PDFs written here, one feature
// each, rendered on the CPU: colours at pixels inside and outside the
// shapes, and the errors of broken and encrypted documents.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "frame/frame.h"
#include "parsers/pdf/pdf_device.h"
#include "parsers/pdf/pdf_parser.h"
#include "tests/catch.h"
#include "cpu/cpu_frame.h"

using namespace mpvg;

namespace {

// A one-page PDF of size w x h points whose page content is `content`,
// with a correct cross-reference table; `resources` goes into the page's
// /Resources dictionary.
// Further objects (`extra`) are numbered from 5 on.
std::string one_page_pdf(const std::string& content, int w = 100, int h = 100, const std::string& resources = "",
                         const std::vector<std::string>& extra = {}) {
  std::vector<std::string> objects = {
      "<< /Type /Catalog /Pages 2 0 R >>",
      "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
      "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + std::to_string(w) + " " + std::to_string(h) +
          "] /Contents 4 0 R /Resources << " + resources + " >> >>",
      "<< /Length " + std::to_string(content.size()) + " >>\nstream\n" + content + "\nendstream",
  };
  objects.insert(objects.end(), extra.begin(), extra.end());
  std::string pdf = "%PDF-1.4\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < objects.size(); i++) {
    offsets.push_back(pdf.size());
    pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = pdf.size();
  pdf += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (size_t o : offsets) {
    char line[32];
    std::snprintf(line, sizeof line, "%010zu 00000 n \n", o);
    pdf += line;
  }
  pdf += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root 1 0 R >>\nstartxref\n" +
         std::to_string(xref) + "\n%%EOF\n";
  return pdf;
}

std::string write_temp(const std::string& name, const std::string& bytes) {
  const std::string path = (std::filesystem::temp_directory_path() / ("mpvg_test_pdf_" + name)).string();
  FILE* f = std::fopen(path.c_str(), "wb");
  REQUIRE(f);
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  return path;
}

// Page 1 rendered at 1 pixel per point on white, one sample per pixel.
struct Page {
  ImageF im;
  int w = 0;
  explicit Page(const std::string& path, const std::string& password = "") {
    const pdf::Document doc(path, password);
    const pdf::PageResult page = doc.page(0, 1.0);
    RenderOptions o;
    o.width = w = static_cast<int>(page.scene.width);
    o.height = static_cast<int>(page.scene.height);
    o.samples = 1;
    o.background = RGBA{1, 1, 1, 1};
    o.gamma = Gamma::Srgb;
    o.backend = Backend::Cpu;
    im = render_cpu(page.scene, o);
  }
  // Straight colour at pixel (x, y), y down from the page's top.
  std::array<float, 3> at(int x, int y) const {
    const float* p = &im.rgba[(size_t(y) * w + x) * 4];
    return {p[0], p[1], p[2]};
  }
};

void check(const Page& p, int x, int y, std::array<float, 3> want, float margin = 1e-3f) {
  const auto got = p.at(x, y);
  INFO("pixel (" << x << ", " << y << "): " << got[0] << " " << got[1] << " " << got[2]);
  for (int k = 0; k < 3; k++) CHECK(got[k] == Approx(want[k]).margin(margin));
}

}  // namespace

TEST_CASE("pdf: fills with both rules, in PDF's coordinates (y up)", "[pdf]") {
  // A red square in the lower left (y up: the bottom of the page), and an
  // even-odd blue ring: two nested squares.
  const Page p(write_temp("fill.pdf", one_page_pdf("1 0 0 rg 0 0 40 40 re f\n"
                                                   "0 0 1 rg 50 50 50 50 re 60 60 30 30 re f*\n")));
  check(p, 10, 90, {1, 0, 0});    // bottom left (pixel rows run down)
  check(p, 10, 10, {1, 1, 1});    // top left: nothing
  check(p, 55, 45, {0, 0, 1});    // the ring
  check(p, 75, 25, {1, 1, 1});    // its hole
}

TEST_CASE("pdf: clips, strokes and constant alpha", "[pdf]") {
  // Clip to the left half, then fill the page green; a 10 pt black stroke
  // across the right half; a half-transparent red square (ExtGState /ca).
  const Page p(write_temp("clip.pdf",
                          one_page_pdf("q 0 0 50 100 re W n 0 1 0 rg 0 0 100 100 re f Q\n"
                                       "0 G 10 w 60 50 m 100 50 l S\n"
                                       "/half gs 1 0 0 rg 70 70 20 20 re f\n",
                                       100, 100, "/ExtGState << /half << /ca 0.5 >> >>")));
  check(p, 25, 50, {0, 1, 0});
  check(p, 75, 10, {1, 0.5f, 0.5f});  // red at 50 % over white
  check(p, 80, 50, {0, 0, 0});        // the stroke
  check(p, 80, 40, {1, 1, 1});        // outside it, between stroke and square
}

TEST_CASE("pdf: broken and encrypted documents give one clear error", "[pdf]") {
  CHECK_THROWS_WITH(pdf::Document(write_temp("garbage.pdf", "this is not a PDF")), Catch::Contains("cannot open"));
  CHECK_THROWS_AS(pdf::Document(write_temp("garbage.pdf", "this is not a PDF")), ParseError);
  // A file that cannot be read is said so as the SVG parser says it, a
  // resource error rather than a malformed document.
  CHECK_THROWS_WITH(pdf::Document("/nonexistent/mpvg.pdf"),
                    Catch::Contains("cannot read '/nonexistent/mpvg.pdf': No such file or directory"));
  CHECK_THROWS_AS(pdf::Document("/nonexistent/mpvg.pdf"), ResourceError);
  // A page whose content stream fails to parse still yields what came before.
  const std::string truncated = one_page_pdf("1 0 0 rg 0 0 40 40 re f\n0 0 1 rg 50 50 50");
  const pdf::Document doc(write_temp("truncated.pdf", truncated));
  CHECK(doc.page_count() == 1);
  CHECK_NOTHROW(doc.page(0, 1.0));
}

TEST_CASE("pdf: text as glyph outlines, invisible text, text as a clip", "[pdf]") {
  const std::string font = "/Font << /F1 << /Type /Font /Subtype /Type1 /BaseFont /Helvetica >> >>";
  // A 40 pt Helvetica 'I' at x = 10 (its stem about 3.8 to 7.4 pt right of
  // the origin, 0 to 28.7 pt up from the baseline at y = 30); the same 'I'
  // invisible (mode 3) at x = 50; and at x = 70 an 'I' in clip mode (7)
  // clipping a red page-wide fill.
  const Page p(write_temp("text.pdf", one_page_pdf("BT /F1 40 Tf 10 30 Td (I) Tj ET\n"
                                                   "BT 3 Tr /F1 40 Tf 50 30 Td (I) Tj ET\n"
                                                   "q BT 7 Tr /F1 40 Tf 70 30 Td (I) Tj ET 1 0 0 rg 0 0 100 100 re f Q\n",
                                                   100, 100, font)));
  check(p, 15, 55, {0, 0, 0});   // in the stem
  check(p, 25, 55, {1, 1, 1});   // right of it
  check(p, 55, 55, {1, 1, 1});   // invisible text
  check(p, 75, 55, {1, 0, 0});   // the red fill, through the glyph clip
  check(p, 90, 55, {1, 1, 1});   // clipped away
}

TEST_CASE("pdf: images as textures, their top row at the top", "[pdf]") {
  // An inline 2 x 2 RGB image over [10, 30] x [10, 30]: red, blue on its
  // first (top) row, green, white on the second.
  const std::string pixels("\xff\x00\x00\x00\x00\xff\x00\xff\x00\xff\xff\xff", 12);
  const Page p(write_temp("image.pdf", one_page_pdf("q 20 0 0 20 10 10 cm BI /W 2 /H 2 /CS /RGB /BPC 8 /I false ID " +
                                                    pixels + "\nEI Q\n")));
  check(p, 14, 74, {1, 0, 0});  // top left (pixel rows run down: y 70..80 is the image's top half)
  check(p, 26, 74, {0, 0, 1});
  check(p, 14, 86, {0, 1, 0});
  check(p, 26, 86, {1, 1, 1});
  check(p, 50, 50, {1, 1, 1});  // outside
}

TEST_CASE("pdf: stencil image masks paint the fill colour", "[pdf]") {
  // A 2 x 1 one-bit stencil (0 paints): its left pixel painted red.
  const Page p(write_temp("stencil.pdf", one_page_pdf("1 0 0 rg q 20 0 0 20 10 10 cm BI /W 2 /H 1 /IM true /BPC 1 ID " +
                                                      std::string("\x40", 1) + "\nEI Q\n")));
  check(p, 14, 80, {1, 0, 0});
  check(p, 26, 80, {1, 1, 1});
}

// A stream object: `dict` entries and the data.
std::string stream_object(const std::string& dict, const std::string& data) {
  return "<< " + dict + " /Length " + std::to_string(data.size()) + " >>\nstream\n" + data + "\nendstream";
}

// Mesh shading data with 8-bit flags, coordinates (0..255 for 0..100 pt)
// and components.
std::string bytes(std::initializer_list<int> v) {
  std::string s;
  for (int b : v) s.push_back(static_cast<char>(b));
  return s;
}

TEST_CASE("pdf: mesh and function-based shadings are interpolated per sample", "[pdf]") {
  // One sample per pixel, somewhere inside it: colours that change by up to
  // 1/60 per point are checked within 0.02.
  const float m = 0.02f;
  const std::string mesh8 = "/BitsPerCoordinate 8 /BitsPerComponent 8 /BitsPerFlag 8 ";
  SECTION("free-form triangles (type 4) with colours at the corners") {
    // Corners (10, 10) red, (90, 10) green, (10, 90) blue, in PDF units (y up).
    const std::string data = bytes({0, 25, 25, 255, 0, 0, 0, 230, 25, 0, 255, 0, 0, 25, 230, 0, 0, 255});
    const Page p(write_temp("type4.pdf", one_page_pdf("/Sh sh", 100, 100, "/Shading << /Sh 5 0 R >>",
                                                      {stream_object("/ShadingType 4 /ColorSpace /DeviceRGB " + mesh8 +
                                                                         "/Decode [0 100 0 100 0 1 0 1 0 1]",
                                                                     data)})));
    check(p, 11, 88, {0.96f, 0.02f, 0.02f}, m);  // near the red corner (1.7 pt from it in x and y): red
    check(p, 36, 63, {1 / 3.0f, 1 / 3.0f, 1 / 3.0f}, m);  // the centroid: the mean
    check(p, 80, 20, {1, 1, 1}, m);  // beyond the hypotenuse: nothing
  }
  SECTION("a triangle whose corners carry t of a Function") {
    // t = 0, 1, 0.5 through a function from red (t = 0) to blue (t = 1).
    const std::string data = bytes({0, 25, 25, 0, 0, 230, 25, 255, 0, 25, 230, 128});
    const Page p(write_temp("type4f.pdf",
                            one_page_pdf("/Sh sh", 100, 100, "/Shading << /Sh 5 0 R >>",
                                         {stream_object("/ShadingType 4 /ColorSpace /DeviceRGB " + mesh8 +
                                                            "/Decode [0 100 0 100 0 1] /Function << /FunctionType 2 "
                                                            "/Domain [0 1] /C0 [1 0 0] /C1 [0 0 1] /N 1 >>",
                                                        data)})));
    check(p, 36, 63, {0.5f, 0, 0.5f}, m);  // t = 0.5 at the centroid
  }
  SECTION("a Coons patch (type 6) with straight sides: bilinear colours") {
    // The square (20, 20)-(80, 80), sides as cubics with points at thirds;
    // corners red, green, blue, white counter-clockwise from the bottom
    // left, so the centre is their mean.
    const std::string data = bytes({0, 51, 51, 51, 102, 51, 153, 51, 204, 102, 204, 153, 204, 204, 204, 204, 153, 204,
                                    102, 204, 51, 153, 51, 102, 51, 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255});
    const Page p(write_temp("type6.pdf", one_page_pdf("/Sh sh", 100, 100, "/Shading << /Sh 5 0 R >>",
                                                      {stream_object("/ShadingType 6 /ColorSpace /DeviceRGB " + mesh8 +
                                                                         "/Decode [0 100 0 100 0 1 0 1 0 1]",
                                                                     data)})));
    check(p, 50, 50, {0.5f, 0.5f, 0.5f}, m);
    check(p, 10, 50, {1, 1, 1}, m);  // outside the patch
  }
  SECTION("a function-based shading (type 1) over its domain") {
    // f(x, y) = (x, y, 0) on [0, 1]^2 mapped to (20, 20)-(80, 80).
    const std::string fn = "{ 0 }";
    const Page p(write_temp("type1.pdf",
                            one_page_pdf("/Sh sh", 100, 100, "/Shading << /Sh 5 0 R >>",
                                         {"<< /ShadingType 1 /ColorSpace /DeviceRGB /Domain [0 1 0 1] "
                                          "/Matrix [60 0 0 60 20 20] /Function 6 0 R >>",
                                          stream_object("/FunctionType 4 /Domain [0 1 0 1] /Range [0 1 0 1 0 1]", fn)})));
    check(p, 50, 50, {0.5f, 0.5f, 0}, m);
    check(p, 25, 75, {0.09f, 0.09f, 0}, m);  // near (0, 0) of the domain: dark
    check(p, 90, 50, {1, 1, 1}, m);            // outside the domain
  }
}

TEST_CASE("pdf: an encrypted document needs its password", "[pdf]") {
  const std::string path = std::string(MPVG_SOURCE_DIR) + "/testdata/pdf/encrypted-password-secret.pdf";
  CHECK_THROWS_WITH(pdf::Document(path), Catch::Contains("encrypted: it needs a password"));
  CHECK_THROWS_WITH(pdf::Document(path, "wrong"), Catch::Contains("wrong password"));
  const pdf::Document doc(path, "secret");
  REQUIRE(doc.page_count() == 1);
  const Page p(path, "secret");
  check(p, 10, 90, {1, 0, 0});
}

// The glyph cache outlines in glyph space and applies the text matrix
// itself: the points must be MuPDF's own outline at that matrix (float
// rounding apart), for fonts of both outline kinds (quadratic TrueType,
// cubic CFF), rotated and sheared matrices included.
TEST_CASE("glyph cache: outlines equal MuPDF's at the text matrix", "[pdf]") {
  fz_context* ctx = fz_new_context(nullptr, nullptr, FZ_STORE_DEFAULT);
  REQUIRE(ctx);
  fz_font* fonts[2] = {fz_new_base14_font(ctx, "Times-Roman"), fz_new_base14_font(ctx, "Courier-Bold")};
  {
    pdf::detail::GlyphCache cache(ctx);
    const fz_matrix matrices[] = {{12, 0, 0, 12, 100.25f, 700.5f}, {0, 9, -9, 0, 33, 44}, {10, 0, 3, 8, -5, 1000}};
    int compared = 0;
    for (fz_font* font : fonts)
      for (int gid = 1; gid < 60; gid++)
        for (const fz_matrix& m : matrices) {
          const Path* cached = cache.outline(font, gid);
          fz_path* ref = fz_outline_glyph(ctx, font, gid, m);
          REQUIRE((cached != nullptr) == (ref != nullptr));
          if (!ref) continue;
          std::vector<Vec2> pts;
          const fz_path_walker walker = {
              [](fz_context*, void* a, float x, float y) { static_cast<std::vector<Vec2>*>(a)->push_back({x, y}); },
              [](fz_context*, void* a, float x, float y) { static_cast<std::vector<Vec2>*>(a)->push_back({x, y}); },
              [](fz_context*, void* a, float x1, float y1, float x2, float y2, float x3, float y3) {
                auto* v = static_cast<std::vector<Vec2>*>(a);
                v->insert(v->end(), {{x1, y1}, {x2, y2}, {x3, y3}});
              },
              [](fz_context*, void*) {},
              [](fz_context*, void* a, float x1, float y1, float x2, float y2) {
                auto* v = static_cast<std::vector<Vec2>*>(a);
                v->insert(v->end(), {{x1, y1}, {x2, y2}});
              },
              nullptr, nullptr, nullptr};
          fz_walk_path(ctx, ref, &walker, &pts);
          fz_drop_path(ctx, ref);
          const Path mine = cached->transformed(Affine{m.a, m.b, m.c, m.d, m.e, m.f});
          REQUIRE(mine.points().size() == pts.size());
          for (size_t k = 0; k < pts.size(); k++) {
            CHECK(std::fabs(mine.points()[k].x - pts[k].x) < 1e-3);
            CHECK(std::fabs(mine.points()[k].y - pts[k].y) < 1e-3);
          }
          compared++;
        }
    CHECK(compared > 300);
  }
  for (fz_font* font : fonts) fz_drop_font(ctx, font);
  fz_drop_context(ctx);
}

// Page boxes (PDF 32000-1 §14.11.2) in points, from the page tree and the
// page (scripts/make_pdf_features.py page_boxes): the MediaBox and CropBox
// inherited, the ArtBox cut by the MediaBox, page 2 turned by /Rotate 90
// and without boxes of its own (Bleed, Trim, Art = CropBox).
TEST_CASE("pdf page boxes: sizes per box, inherited, intersected, rotated") {
  const pdf::Document doc(std::string(MPVG_SOURCE_DIR) + "/testdata/pdf/page-boxes.pdf");
  struct Want {
    pdf::PageBox box;
    double w, h;
  };
  for (const Want& want : {Want{pdf::PageBox::Media, 300, 200}, Want{pdf::PageBox::Crop, 260, 180},
                           Want{pdf::PageBox::Bleed, 240, 160}, Want{pdf::PageBox::Trim, 220, 140},
                           Want{pdf::PageBox::Art, 250, 120}}) {
    const pdf::PageResult p1 = doc.page(0, 1.0, want.box);
    CHECK(p1.scene.width == Approx(want.w));
    CHECK(p1.scene.height == Approx(want.h));
  }
  CHECK(doc.page(1, 1.0, pdf::PageBox::Media).scene.width == Approx(200));
  CHECK(doc.page(1, 1.0, pdf::PageBox::Media).scene.height == Approx(300));
  for (pdf::PageBox b : {pdf::PageBox::Crop, pdf::PageBox::Bleed, pdf::PageBox::Trim, pdf::PageBox::Art}) {
    const pdf::PageResult p2 = doc.page(1, 1.0, b);
    CHECK(p2.scene.width == Approx(180));
    CHECK(p2.scene.height == Approx(260));
  }
}

// /UserUnit scales every box as it scales the page (a real: MuPDF 1.21
// reads it only as one).
TEST_CASE("pdf page boxes: /UserUnit scales them") {
  // The page dictionary's keys after its resources: /Dummy takes the
  // dictionary one_page_pdf closes them with.
  const std::string path =
      write_temp("userunit.pdf", one_page_pdf("0 g 0 0 10 10 re f", 100, 80,
                                              ">> /TrimBox [10 10 60 50] /UserUnit 2.0 /Dummy <<"));
  const pdf::Document doc(path);
  const pdf::PageResult media = doc.page(0, 1.0, pdf::PageBox::Media);
  const pdf::PageResult trim = doc.page(0, 1.0, pdf::PageBox::Trim);
  CHECK(media.scene.width == Approx(200));
  CHECK(media.scene.height == Approx(160));
  CHECK(trim.scene.width == Approx(100));
  CHECK(trim.scene.height == Approx(80));
}
