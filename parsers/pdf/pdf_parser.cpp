// Documents and pages through MuPDF (see pdf_parser.h). Every MuPDF call
// runs inside fz_try; only plain values cross it, so no C++ object with a
// destructor is ever jumped over.
#include "parsers/pdf/pdf_parser.h"

#include <mupdf/fitz.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "parsers/pdf/pdf_device.h"

namespace mpvg::pdf {

struct Document::Impl {
  fz_context* ctx = nullptr;
  fz_document* doc = nullptr;
  int pages = 0;
  std::vector<unsigned char> input;  // the document read from stdin ("-"), which MuPDF reads in place
  ~Impl() {
    if (ctx) {
      fz_drop_document(ctx, doc);
      fz_drop_context(ctx);
    }
  }
};

Document::Document(const std::string& path, const std::string& password) : impl_(std::make_unique<Impl>()) {
  fz_context* ctx = fz_new_context(nullptr, nullptr, FZ_STORE_DEFAULT);
  if (!ctx) throw Error("cannot start MuPDF");
  impl_->ctx = ctx;
  // MuPDF prints its errors and warnings on stderr itself; errors reach the
  // user through mpvg::Error instead. Its warnings (repairs and the like)
  // are dropped for now.
  fz_set_error_callback(ctx, [](void*, const char*) {}, nullptr);
  fz_set_warning_callback(ctx, [](void*, const char*) {}, nullptr);
  // Set inside fz_try and read after it: volatile, as setjmp requires.
  const char* volatile failure = nullptr;
  char message[256] = "";
  fz_document* volatile doc = nullptr;
  volatile int pages = 0;
  if (path == "-") {
    unsigned char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, stdin)) > 0) impl_->input.insert(impl_->input.end(), buf, buf + n);
  }
  const unsigned char* data = impl_->input.data();
  const size_t size = impl_->input.size();
  fz_stream* volatile stream = nullptr;
  fz_try(ctx) {
    fz_register_document_handlers(ctx);
    if (path == "-") {
      stream = fz_open_memory(ctx, data, size);
      doc = fz_open_document_with_stream(ctx, "application/pdf", stream);
    } else {
      doc = fz_open_document(ctx, path.c_str());
    }
    if (fz_needs_password(ctx, doc) && !fz_authenticate_password(ctx, doc, password.c_str()))
      failure = password.empty() ? "the document is encrypted: give its password with --password"
                                 : "wrong password";
    else
      pages = fz_count_pages(ctx, doc);
  }
  fz_always(ctx) { fz_drop_stream(ctx, stream); }
  fz_catch(ctx) {
    fz_strlcpy(message, fz_caught_message(ctx), sizeof message);
  }
  impl_->doc = doc;
  impl_->pages = pages;
  if (message[0]) throw Error("cannot open '" + path + "': " + message);
  if (failure) throw Error("cannot open '" + path + "': " + failure);
}

Document::~Document() = default;

int Document::page_count() const { return impl_->pages; }

namespace {

// Loads page `index` and its box; throws mpvg::Error with MuPDF's message.
fz_page* load_page(fz_context* ctx, fz_document* doc, int index, fz_rect* box) {
  fz_page* volatile page = nullptr;
  char message[256] = "";
  fz_try(ctx) {
    page = fz_load_page(ctx, doc, index);
    const fz_rect bounds = fz_bound_page(ctx, page);
    memcpy(box, &bounds, sizeof bounds);
  }
  fz_catch(ctx) {
    fz_strlcpy(message, fz_caught_message(ctx), sizeof message);
  }
  if (message[0]) {
    fz_drop_page(ctx, page);
    throw Error("page " + std::to_string(index + 1) + ": " + message);
  }
  return page;
}

}  // namespace

PageResult Document::page(int index, double pixels_per_point) const {
  return page(index, [pixels_per_point](double, double) { return pixels_per_point; });
}

PageResult Document::page(int index, const std::function<double(double, double)>& pixels_per_point) const {
  fz_context* ctx = impl_->ctx;
  fz_rect box{};
  fz_page* page = load_page(ctx, impl_->doc, index, &box);
  PageResult out;
  const double w = box.x1 - box.x0, h = box.y1 - box.y0;
  out.pixels_per_point = pixels_per_point(w, h);
  SceneBuilder b(w, h);
  try {
    out.warnings = detail::lower_page(ctx, page, fz_translate(-box.x0, -box.y0),
                                      Affine::scale(out.pixels_per_point, out.pixels_per_point), w, h, b);
  } catch (const Error& e) {
    fz_drop_page(ctx, page);
    throw Error("page " + std::to_string(index + 1) + ": " + e.what());
  }
  fz_drop_page(ctx, page);
  out.scene = b.finish();
  return out;
}

}  // namespace mpvg::pdf
