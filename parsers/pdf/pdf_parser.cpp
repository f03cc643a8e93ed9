// Documents and pages through MuPDF (see pdf_parser.h). Every MuPDF call
// runs inside fz_try; only plain values cross it, so no C++ object with a
// destructor is ever jumped over.
#include "parsers/pdf/pdf_parser.h"

#include <mupdf/fitz.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.h"
#include "parsers/pdf/pdf_device.h"

namespace mpvg::pdf {

// MuPDF's locks for contexts shared between threads (fz_clone_context):
// one mutex per lock MuPDF names.
struct Locks {
  std::mutex m[FZ_LOCK_MAX];
  fz_locks_context ctx{this, [](void* u, int i) { static_cast<Locks*>(u)->m[i].lock(); },
                       [](void* u, int i) { static_cast<Locks*>(u)->m[i].unlock(); }};
};

struct Document::Impl {
  std::shared_ptr<Locks> locks;  // outlives every context that uses it
  fz_context* ctx = nullptr;
  fz_document* doc = nullptr;
  int pages = 0;
  std::string path, password;
  // The document read from stdin ("-"), which MuPDF reads in place; shared
  // with the clones.
  std::shared_ptr<const std::vector<unsigned char>> input;
  std::unique_ptr<detail::GlyphCache> glyphs;  // this context's, made on first use
  ~Impl() {
    if (ctx) {
      glyphs.reset();
      fz_drop_document(ctx, doc);
      fz_drop_context(ctx);
    }
  }

  // Opens path (or input) in ctx; throws mpvg::Error.
  void open() {
    // Set inside fz_try and read after it: volatile, as setjmp requires.
    const char* volatile failure = nullptr;
    char message[256] = "";
    fz_document* volatile d = nullptr;
    volatile int n = 0;
    const unsigned char* data = input ? input->data() : nullptr;
    const size_t size = input ? input->size() : 0;
    const char* name = path.c_str();
    const char* pw = password.c_str();
    const bool from_memory = input != nullptr;
    fz_stream* volatile stream = nullptr;
    fz_try(ctx) {
      fz_register_document_handlers(ctx);
      if (from_memory) {
        stream = fz_open_memory(ctx, data, size);
        d = fz_open_document_with_stream(ctx, "application/pdf", stream);
      } else {
        d = fz_open_document(ctx, name);
      }
      if (fz_needs_password(ctx, d) && !fz_authenticate_password(ctx, d, pw))
        failure = pw[0] ? "wrong password" : "the document is encrypted: give its password with --password";
      else
        n = fz_count_pages(ctx, d);
    }
    fz_always(ctx) { fz_drop_stream(ctx, stream); }
    fz_catch(ctx) {
      fz_strlcpy(message, fz_caught_message(ctx), sizeof message);
    }
    doc = d;
    pages = n;
    if (message[0]) throw Error("cannot open '" + path + "': " + message);
    if (failure) throw Error("cannot open '" + path + "': " + failure);
  }
};

namespace {

// MuPDF prints its errors and warnings on stderr itself; errors reach the
// user through mpvg::Error instead. Its warnings (repairs and the like) are
// dropped for now.
void silence(fz_context* ctx) {
  fz_set_error_callback(ctx, [](void*, const char*) {}, nullptr);
  fz_set_warning_callback(ctx, [](void*, const char*) {}, nullptr);
}

}  // namespace

Document::Document(const std::string& path, const std::string& password) : impl_(std::make_unique<Impl>()) {
  impl_->locks = std::make_shared<Locks>();
  fz_context* ctx = fz_new_context(nullptr, &impl_->locks->ctx, FZ_STORE_DEFAULT);
  if (!ctx) throw Error("cannot start MuPDF");
  impl_->ctx = ctx;
  silence(ctx);
  impl_->path = path;
  impl_->password = password;
  if (path == "-") {
    auto input = std::make_shared<std::vector<unsigned char>>();
    unsigned char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, stdin)) > 0) input->insert(input->end(), buf, buf + n);
    impl_->input = std::move(input);
  }
  impl_->open();
}

Document::Document(const Document& other, Context context) : impl_(std::make_unique<Impl>()) {
  if (context == Context::Shared) {
    impl_->locks = other.impl_->locks;
    impl_->ctx = fz_clone_context(other.impl_->ctx);
  } else {
    impl_->locks = std::make_shared<Locks>();
    impl_->ctx = fz_new_context(nullptr, &impl_->locks->ctx, FZ_STORE_DEFAULT);
  }
  if (!impl_->ctx) throw Error("cannot start MuPDF");
  silence(impl_->ctx);
  impl_->path = other.impl_->path;
  impl_->password = other.impl_->password;
  impl_->input = other.impl_->input;
  impl_->open();
}

std::unique_ptr<Document> Document::clone(Context context) const {
  return std::unique_ptr<Document>(new Document(*this, context));
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
  const auto t_load = std::chrono::steady_clock::now();
  fz_page* page = load_page(ctx, impl_->doc, index, &box);
  PageResult out;
  out.interpret_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_load).count();
  const double w = box.x1 - box.x0, h = box.y1 - box.y0;
  out.pixels_per_point = pixels_per_point(w, h);
  SceneBuilder b(w, h);
  try {
    if (!impl_->glyphs) impl_->glyphs = std::make_unique<detail::GlyphCache>(ctx);
    detail::Lowered l = detail::lower_page(ctx, page, fz_translate(-box.x0, -box.y0),
                                           Affine::scale(out.pixels_per_point, out.pixels_per_point), w, h, b,
                                           *impl_->glyphs);
    out.warnings = std::move(l.warnings);
    out.interpret_ms += l.run_ms - l.lower_ms;
    out.lower_ms = l.lower_ms;
  } catch (const Error& e) {
    fz_drop_page(ctx, page);
    throw Error("page " + std::to_string(index + 1) + ": " + e.what());
  }
  fz_drop_page(ctx, page);
  const auto t0 = std::chrono::steady_clock::now();
  out.scene = b.finish();
  out.lower_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace mpvg::pdf
