// Documents and pages through MuPDF (see pdf_parser.h). Every MuPDF call
// runs inside fz_try; only plain values cross it, so no C++ object with a
// destructor is ever jumped over.
#include "parsers/pdf/pdf_parser.h"

#include <mupdf/fitz.h>
#include <mupdf/pdf.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "core/error.h"
#include "core/memory_budget.h"
#include "parsers/pdf/pdf_device.h"
#include "frame/scene_builder.h"

namespace mpvg::pdf {

// MuPDF's locks for contexts shared between threads (fz_clone_context):
// one mutex per lock MuPDF names.
struct Locks {
  std::mutex m[FZ_LOCK_MAX];
  fz_locks_context ctx{this, [](void* u, int i) { static_cast<Locks*>(u)->m[i].lock(); },
                       [](void* u, int i) { static_cast<Locks*>(u)->m[i].unlock(); }};
};

namespace {

// The pages a PDF's page tree really holds: its leaves, found by walking
// /Kids from the root (each node once, so a cycle ends the walk), capped by
// the root's /Count; a /Pages node below the root with no new kid counts
// as one (broken) page. MuPDF's own count is the root's /Count, which a file
// may set to anything (2e9 made pdf2png try two billion pages, one error
// line each); page lookups also go by the /Count of the nodes on the way,
// so pages past it cannot be found either. Called inside fz_try: MuPDF
// errors (a broken object) throw through it.
struct TreeWalk {
  pdf_obj** stack;
  int stacked, stack_capacity;
  pdf_obj** marked;
  int marks, mark_capacity;
  int leaves;
};

void push(fz_context* ctx, pdf_obj*** array, int* n, int* capacity, pdf_obj* obj) {
  if (*n == *capacity) {
    *capacity = *capacity ? 2 * *capacity : 64;
    *array = fz_realloc_array(ctx, *array, *capacity, pdf_obj*);
  }
  (*array)[(*n)++] = obj;
}

int page_tree_leaves(fz_context* ctx, pdf_document* doc, int claimed) {
  pdf_obj* root = pdf_dict_getp(ctx, pdf_trailer(ctx, doc), "Root/Pages");
  if (!pdf_is_dict(ctx, root)) return 0;
  // The walk's state lives on MuPDF's heap, not in locals: fz_try is
  // setjmp, and what a jump leaves behind must be freed by fz_always.
  TreeWalk* const w = fz_malloc_struct(ctx, TreeWalk);
  volatile int leaves = 0;
  fz_try(ctx) {
    push(ctx, &w->stack, &w->stacked, &w->stack_capacity, root);
    while (w->stacked > 0 && w->leaves < claimed) {
      pdf_obj* node = w->stack[--w->stacked];
      // Each node once: a cycle or a node listed twice ends there.
      if (pdf_mark_obj(ctx, node)) continue;
      push(ctx, &w->marked, &w->marks, &w->mark_capacity, node);
      pdf_obj* kids = pdf_dict_get(ctx, node, PDF_NAME(Kids));
      if (pdf_is_array(ctx, kids) && !pdf_name_eq(ctx, pdf_dict_get(ctx, node, PDF_NAME(Type)), PDF_NAME(Page))) {
        // In reverse, so that pages are met in document order.
        int fresh = 0;
        for (int i = pdf_array_len(ctx, kids) - 1; i >= 0; i--) {
          pdf_obj* kid = pdf_array_get(ctx, kids, i);
          if (!pdf_is_dict(ctx, kid) || pdf_obj_marked(ctx, kid)) continue;
          push(ctx, &w->stack, &w->stacked, &w->stack_capacity, kid);
          fresh++;
        }
        // A node below the root that leads nowhere new (its kids are
        // itself, or none) stands for a page that fails to load, reported
        // as such, as MuPDF's lookup counts it.
        if (fresh == 0 && node != root) w->leaves++;
      } else {
        w->leaves++;
      }
    }
    leaves = w->leaves;
  }
  fz_always(ctx) {
    for (int i = 0; i < w->marks; i++) pdf_unmark_obj(ctx, w->marked[i]);
    fz_free(ctx, w->stack);
    fz_free(ctx, w->marked);
    fz_free(ctx, w);
  }
  fz_catch(ctx) { fz_rethrow(ctx); }
  return leaves;
}

}  // namespace

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
  // The document's output intent as a press profile (print preview), read
  // on first need; why it could not be used, if so.
  bool intent_read = false;
  std::shared_ptr<const OutputProfile> intent;
  std::string intent_problem;
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
        failure = pw[0] ? "wrong password" : "the document is encrypted: it needs a password";
      else {
        n = fz_count_pages(ctx, d);
        if (pdf_document* pdf = pdf_document_from_fz_document(ctx, d)) n = page_tree_leaves(ctx, pdf, n);
      }
    }
    fz_always(ctx) { fz_drop_stream(ctx, stream); }
    fz_catch(ctx) {
      fz_strlcpy(message, fz_caught_message(ctx), sizeof message);
    }
    doc = d;
    pages = n;
    if (message[0]) throw ParseError("cannot open '" + path + "': " + message);
    if (failure) throw PasswordError("cannot open '" + path + "': " + failure);
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

// Does this MuPDF build manage colour with ICC profiles (lcms2)? Without it
// (Debian 12's libmupdf) fz_enable_icc warns, and ICC-based colour spaces
// fall back to their alternates. Asked once a process.
bool icc_available(fz_context* ctx) {
  static const bool available = [ctx] {
    bool warned = false;
    fz_set_warning_callback(
        ctx, [](void* user, const char* message) {
          if (std::strstr(message, "ICC")) *static_cast<bool*>(user) = true;
        },
        &warned);
    fz_enable_icc(ctx);
    fz_flush_warnings(ctx);
    silence(ctx);
    return !warned;
  }();
  return available;
}

// Does the page ask for ICC colour management: an output intent in the
// catalog (with `intents`), or an ICCBased colour space among its
// resources' colour spaces and images (their first level)?
bool page_uses_icc(fz_context* ctx, fz_page* page, bool intents) {
  pdf_page* pp = pdf_page_from_fz_page(ctx, page);
  if (!pp) return false;
  volatile bool found = false;
  fz_try(ctx) {
    pdf_document* doc = pp->doc;
    if (intents && pdf_dict_getp(ctx, pdf_trailer(ctx, doc), "Root/OutputIntents")) found = true;
    pdf_obj* res = pdf_page_resources(ctx, pp);
    auto icc = [&](pdf_obj* cs) {
      return pdf_is_array(ctx, cs) && pdf_name_eq(ctx, pdf_array_get(ctx, cs, 0), PDF_NAME(ICCBased));
    };
    pdf_obj* spaces = pdf_dict_get(ctx, res, PDF_NAME(ColorSpace));
    for (int i = 0; !found && i < pdf_dict_len(ctx, spaces); i++) found = icc(pdf_dict_get_val(ctx, spaces, i));
    pdf_obj* xobjects = pdf_dict_get(ctx, res, PDF_NAME(XObject));
    for (int i = 0; !found && i < pdf_dict_len(ctx, xobjects); i++)
      found = icc(pdf_dict_get(ctx, pdf_dict_get_val(ctx, xobjects, i), PDF_NAME(ColorSpace)));
  }
  fz_catch(ctx) {}
  return found;
}

}  // namespace

Document::Document(const std::string& path, const std::string& password, size_t max_input)
    : impl_(std::make_unique<Impl>()) {
  auto too_large = [&] {
    return ResourceError("'" + path + "' is larger than the input limit of " + byte_size(max_input) + " (--max-input)");
  };
  struct stat st {};
  if (path != "-" && stat(path.c_str(), &st) != 0)
    throw ResourceError("cannot read '" + path + "': " + std::strerror(errno));
  if (path != "-" && S_ISREG(st.st_mode) && uint64_t(st.st_size) > max_input) throw too_large();
  impl_->locks = std::make_shared<Locks>();
  fz_context* ctx = fz_new_context(nullptr, &impl_->locks->ctx, FZ_STORE_DEFAULT);
  if (!ctx) throw Error("cannot start MuPDF");
  impl_->ctx = ctx;
  silence(ctx);
  impl_->path = path;
  impl_->password = password;
  // Standard input, devices and FIFOs are read into memory up to the limit
  // (MuPDF would read /dev/zero for ever); regular files are MuPDF's to read.
  if (path == "-" || !S_ISREG(st.st_mode)) {
    FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
    if (!f) throw ResourceError("cannot read '" + path + "': " + std::strerror(errno));
    struct Close {
      FILE* f;
      ~Close() {
        if (f != stdin) std::fclose(f);
      }
    } close{f};
    auto input = std::make_shared<std::vector<unsigned char>>();
    unsigned char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
      if (input->size() + n > max_input) throw too_large();
      input->insert(input->end(), buf, buf + n);
    }
    if (std::ferror(f)) throw ResourceError("cannot read '" + path + "': " + std::strerror(errno));
    impl_->input = std::move(input);
  }
  impl_->open();
}

Document::Document(std::shared_ptr<const std::vector<unsigned char>> bytes, const std::string& name,
                   const std::string& password)
    : impl_(std::make_unique<Impl>()) {
  if (!bytes) throw Error("no document given");
  impl_->locks = std::make_shared<Locks>();
  impl_->ctx = fz_new_context(nullptr, &impl_->locks->ctx, FZ_STORE_DEFAULT);
  if (!impl_->ctx) throw Error("cannot start MuPDF");
  silence(impl_->ctx);
  impl_->path = name;
  impl_->password = password;
  impl_->input = std::move(bytes);
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
std::shared_ptr<const OutputProfile> output_intent(fz_context* ctx, fz_page* page, std::string* problem);
}  // namespace

bool Document::has_output_intent() const {
  if (!impl_->intent_read && impl_->pages > 0) {
    fz_context* ctx = impl_->ctx;
    fz_page* volatile page = nullptr;
    fz_try(ctx) { page = fz_load_page(ctx, impl_->doc, 0); }
    fz_catch(ctx) { page = nullptr; }
    if (!page) return false;
    impl_->intent_read = true;
    impl_->intent = output_intent(ctx, page, &impl_->intent_problem);
    fz_drop_page(ctx, page);
  }
  return impl_->intent != nullptr;
}

namespace {
fz_page* load_page(fz_context* ctx, fz_document* doc, int index, PageBox which, fz_rect* box);
}  // namespace

std::pair<double, double> Document::page_size(int index, PageBox which) const {
  if (index < 0 || index >= impl_->pages)
    throw Error("page " + std::to_string(index + 1) + " is past the last page (" + std::to_string(impl_->pages) + ")");
  fz_rect box{};
  fz_page* page = load_page(impl_->ctx, impl_->doc, index, which, &box);
  fz_drop_page(impl_->ctx, page);
  return {box.x1 - box.x0, box.y1 - box.y0};
}

namespace {

// Page box `which` of a PDF page in MuPDF's page space (y down, the
// CropBox's corner after /Rotate at the origin, /UserUnit applied), where
// fz_bound_page gives the CropBox. MuPDF 1.21 has no fz_bound_page_box:
// the box is read from the page dictionary and taken through
// pdf_page_transform's matrix, which is made from the CropBox (as
// MuPDF's: an empty MediaBox is US Letter, an empty CropBox none).
fz_rect page_box(fz_context* ctx, fz_page* page, PageBox which, fz_rect crop) {
  pdf_page* pp = pdf_page_from_fz_page(ctx, page);
  if (which == PageBox::Crop || !pp) return crop;
  fz_rect cropped;  // MediaBox and CropBox intersected, in user space
  fz_matrix ctm;
  pdf_page_transform(ctx, pp, &cropped, &ctm);
  fz_rect media = pdf_to_rect(ctx, pdf_dict_get_inheritable(ctx, pp->obj, PDF_NAME(MediaBox)));
  if (fz_is_empty_rect(media)) media = fz_make_rect(0, 0, 612, 792);
  fz_rect box = media;
  if (which != PageBox::Media) {
    pdf_obj* name = which == PageBox::Bleed ? PDF_NAME(BleedBox) : which == PageBox::Trim ? PDF_NAME(TrimBox) : PDF_NAME(ArtBox);
    const fz_rect own = pdf_to_rect(ctx, pdf_dict_get(ctx, pp->obj, name));
    box = fz_is_empty_rect(own) ? cropped : fz_intersect_rect(own, media);
  }
  if (box.x1 - box.x0 < 1 || box.y1 - box.y0 < 1) return crop;
  return fz_transform_rect(box, ctm);
}

// Loads page `index` and its box; throws mpvg::Error with MuPDF's message.
fz_page* load_page(fz_context* ctx, fz_document* doc, int index, PageBox which, fz_rect* box) {
  fz_page* volatile page = nullptr;
  char message[256] = "";
  fz_try(ctx) {
    page = fz_load_page(ctx, doc, index);
    const fz_rect bounds = page_box(ctx, page, which, fz_bound_page(ctx, page));
    memcpy(box, &bounds, sizeof bounds);
  }
  fz_catch(ctx) {
    fz_strlcpy(message, fz_caught_message(ctx), sizeof message);
  }
  if (message[0]) {
    fz_drop_page(ctx, page);
    throw ParseError("page " + std::to_string(index + 1) + ": " + message);
  }
  return page;
}

}  // namespace

namespace {

// The page's spot colours (its Separation and DeviceN colorants other than
// the process ones, All and None), in MuPDF's order, and each one's CMYK
// equivalent. A page whose colorants MuPDF cannot list (more than
// FZ_MAX_SEPARATIONS, 64) is refused: its plates would be missing.
fz_separations* page_separations(fz_context* ctx, fz_page* page, char (&problem)[256]) {
  fz_separations* volatile seps = nullptr;
  fz_try(ctx) { seps = fz_page_separations(ctx, page); }
  fz_catch(ctx) {
    seps = nullptr;
    std::snprintf(problem, sizeof problem, "%s", fz_caught_message(ctx));
  }
  return seps;
}

// Separation i's CMYK equivalent; black where MuPDF cannot tell.
void separation_cmyk(fz_context* ctx, fz_separations* seps, int i, float (&c)[4]) {
  fz_try(ctx) { fz_separation_equivalent(ctx, seps, i, fz_device_cmyk(ctx), c, nullptr, fz_default_color_params); }
  fz_catch(ctx) { c[0] = c[1] = c[2] = 0, c[3] = 1; }
}

void page_spots(fz_context* ctx, fz_page* page, std::vector<std::string>* names, std::vector<float>* cmyk) {
  char problem[256] = "";
  fz_separations* seps = page_separations(ctx, page, problem);
  if (problem[0]) {
    if (std::string(problem).find("too many separations") != std::string::npos)
      throw UnsupportedError("the page has more than " + std::to_string(int(FZ_MAX_SEPARATIONS)) +
                             " spot colours, which --separations cannot print (MuPDF lists at most " +
                             std::to_string(int(FZ_MAX_SEPARATIONS)) + ")");
    throw ParseError(std::string("the page's spot colours cannot be read: ") + problem);
  }
  if (!seps) return;
  const int n = fz_count_separations(ctx, seps);
  for (int i = 0; i < n; i++) {
    const char* name = fz_separation_name(ctx, seps, i);
    const std::string s = name ? name : "";
    if (s.empty() || s == "Cyan" || s == "Magenta" || s == "Yellow" || s == "Black" || s == "All" || s == "None" ||
        std::find(names->begin(), names->end(), s) != names->end())
      continue;
    float c[4] = {0, 0, 0, 0};
    separation_cmyk(ctx, seps, i, c);
    names->push_back(s);
    cmyk->insert(cmyk->end(), c, c + 4);
  }
  fz_drop_separations(ctx, seps);
}

}  // namespace

namespace {

// The document's output intent (PDF 32000-1 §14.11.5): the first
// /OutputIntents entry whose DestOutputProfile is a CMYK profile; null if
// none, with *problem set when one is there but cannot be used.
std::shared_ptr<const OutputProfile> output_intent(fz_context* ctx, fz_page* page, std::string* problem) {
  pdf_page* pp = pdf_page_from_fz_page(ctx, page);
  if (!pp) return nullptr;
  std::vector<std::vector<uint8_t>> profiles;
  fz_buffer* volatile buf = nullptr;
  fz_try(ctx) {
    pdf_obj* intents = pdf_dict_getp(ctx, pdf_trailer(ctx, pp->doc), "Root/OutputIntents");
    for (int i = 0; i < pdf_array_len(ctx, intents); i++) {
      pdf_obj* dest = pdf_dict_gets(ctx, pdf_array_get(ctx, intents, i), "DestOutputProfile");
      if (!pdf_is_stream(ctx, dest)) continue;
      buf = pdf_load_stream(ctx, dest);
      unsigned char* data = nullptr;
      const size_t n = fz_buffer_storage(ctx, buf, &data);
      profiles.emplace_back(data, data + n);
      fz_drop_buffer(ctx, buf);
      buf = nullptr;
    }
  }
  fz_catch(ctx) {
    fz_drop_buffer(ctx, buf);
    *problem = "the output intent could not be read: no press profile from it";
  }
  for (const std::vector<uint8_t>& icc : profiles) {
    try {
      return std::make_shared<const OutputProfile>(icc, "the output intent's profile");
    } catch (const Error& e) {
      *problem = std::string(e.what()) + ": not used";
    }
  }
  return nullptr;
}

}  // namespace

PageResult Document::page(int index, double pixels_per_point, const PageOptions& options) const {
  return page(index, [pixels_per_point](double, double) { return pixels_per_point; }, options);
}

PageResult Document::page(int index, const std::function<double(double, double)>& pixels_per_point,
                          const PageOptions& options) const {
  const PageBox which = options.box;
  fz_context* ctx = impl_->ctx;
  fz_rect box{};
  const auto t_load = std::chrono::steady_clock::now();
  fz_page* page = load_page(ctx, impl_->doc, index, which, &box);
  PageResult out;
  out.interpret_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_load).count();
  const double w = box.x1 - box.x0, h = box.y1 - box.y0;
  out.pixels_per_point = pixels_per_point(w, h);
  SceneBuilder b(w, h);
  b.set_budget(options.budget.get());
  try {
    if (!impl_->glyphs) impl_->glyphs = std::make_unique<detail::GlyphCache>(ctx);
    const Affine device = Affine::scale(out.pixels_per_point, out.pixels_per_point);
    // (Print preview applies the output intent itself: output_intent.h.)
    if (!icc_available(ctx) && page_uses_icc(ctx, page, options.inks == InkModel::Rgb))
      out.warnings.push_back(options.inks == InkModel::Rgb
                                 ? "this MuPDF has no ICC colour management: ICC-based colours and the output "
                                   "intent were drawn through their alternate spaces"
                                 : "this MuPDF has no ICC colour management: ICC-based colours were drawn "
                                   "through their alternate spaces");
    if (options.inks == InkModel::Rgb) {
      detail::Lowered l =
          detail::lower_page(ctx, page, fz_translate(-box.x0, -box.y0), device, w, h, b, *impl_->glyphs, options);
      out.warnings.insert(out.warnings.end(), l.warnings.begin(), l.warnings.end());
      out.interpret_ms += l.run_ms - l.lower_ms;
      out.lower_ms = l.lower_ms;
    } else {
      // Print preview: the page once per pass of its inks (core/inks/inks.h).
      detail::InkTarget target;
      if (!impl_->intent_read) {
        impl_->intent_read = true;
        impl_->intent = output_intent(ctx, page, &impl_->intent_problem);
      }
      if (!impl_->intent_problem.empty()) out.warnings.push_back(impl_->intent_problem);
      // (Without either profile: MuPDF's formulas; the caller says so once.)
      target.profile = options.cmyk_profile ? options.cmyk_profile.get() : impl_->intent.get();
      out.ink_names = {"Cyan", "Magenta", "Yellow", "Black"};
      if (options.inks == InkModel::Separations) page_spots(ctx, page, &target.spots, &out.spot_cmyk);
      out.ink_names.insert(out.ink_names.end(), target.spots.begin(), target.spots.end());
      for (const InkPass& pass : ink_passes(static_cast<int>(out.ink_names.size()))) {
        target.pass = pass;
        SceneBuilder bp(w, h);
        bp.set_budget(options.budget.get());
        detail::Lowered l = detail::lower_page(ctx, page, fz_translate(-box.x0, -box.y0), device, w, h, bp,
                                               *impl_->glyphs, options, &target);
        for (std::string& warning : l.warnings)
          if (std::find(out.warnings.begin(), out.warnings.end(), warning) == out.warnings.end())
            out.warnings.push_back(std::move(warning));
        out.interpret_ms += l.run_ms - l.lower_ms;
        out.lower_ms += l.lower_ms;
        const auto t0 = std::chrono::steady_clock::now();
        out.ink_passes.push_back(bp.finish());
        if (bp.flattened_groups()) out.warnings.push_back(flattened_groups_warning(bp.flattened_groups()));
        out.lower_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      }
    }
  } catch (const Error& e) {
    fz_drop_page(ctx, page);
    throw Error("page " + std::to_string(index + 1) + ": " + e.what());
  }
  fz_drop_page(ctx, page);
  const auto t0 = std::chrono::steady_clock::now();
  if (options.inks == InkModel::Rgb) out.scene = b.finish();
  if (b.flattened_groups()) out.warnings.push_back(flattened_groups_warning(b.flattened_groups()));
  out.lower_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace mpvg::pdf
