// A PDF page as a pipeline job (lib/pipeline/pdf_page_job.h).
#include "lib/pipeline/pdf_page_job.h"

#include <algorithm>
#include <cmath>

#include "lib/output/ink_output.h"
#include "frame/encoding.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_builder.h"

namespace mpvg {

std::unique_ptr<pipeline::Job> pdf_page_job(const PdfPageRequest& request, const cli::Options& opt,
                                            const pdf::Document& doc, int n, const std::string& out) {
  auto job = std::make_unique<pipeline::Job>();
  job->label = "page " + std::to_string(n);
  job->out = out;
  // -scale-to, -scale-to-x/-y: the resolution follows from the page's
  // size. The page is lowered for the finer of the two axes' resolutions
  // (its flattening and glyphs are exact enough for both).
  const PdfPageRequest& pdf = request;
  double sx = 1, sy = 1;
  // One budget for the page: its lowering, then its render.
  pdf::PageOptions page_options = pdf.page;
  page_options.budget = cli::make_budget(opt);
  pdf::PageResult page = doc.page(
      n - 1,
      [&](double w, double h) {
        page_scale(pdf, w, h, &sx, &sy);
        return std::max(sx, sy);
      },
      page_options);
  const Scene& first = page.ink_passes.empty() ? page.scene : page.ink_passes[0];
  job->prepare_ms[0] = page.interpret_ms;
  job->prepare_ms[1] = page.lower_ms;
  job->warnings = std::move(page.warnings);
  // Recorded in the files (-scale-to: the page's own resolution).
  job->dpi = sx * 72;
  job->dpi_y = sy * 72;
  int width = page_pixels(first.width, sx);
  int height = page_pixels(first.height, sy);
  // -x -y -W -H: a window of the page's pixels (the rest of the page if
  // -W or -H is absent), as pdftoppm crops.
  if (pdf.crop_x || pdf.crop_y || pdf.crop_w || pdf.crop_h) {
    width = pdf.crop_w ? pdf.crop_w : std::max(1, width - pdf.crop_x);
    height = pdf.crop_h ? pdf.crop_h : std::max(1, height - pdf.crop_y);
  }
  const Affine view = Affine::translate(-pdf.crop_x, -pdf.crop_y) * Affine::scale(sx, sy);
  if (page.ink_passes.empty()) {
    cli::check_frame(opt, width, height);
    job->width = width;
    job->height = height;
    job->options = cli::render_options(opt, width, height, view, page_options.budget);
    job->plan = plan_render(job->options);
    job->scene = encode_for(page.scene, job->plan, job->options.gamma, &job->stats);
    return job;
  }
  // Print preview: the passes side by side in one frame (apps/
  // ink_output.h), each clipped to its window of the page, kGap pixels
  // apart so that no filter reaches from one into the next.
  constexpr int kGap = 4;
  const int passes = static_cast<int>(page.ink_passes.size());
  const int wide = passes * (width + kGap) - kGap;
  cli::check_frame(opt, wide, height);
  SceneBuilder b((pdf.crop_x + wide) / sx, first.height);
  b.set_budget(page_options.budget.get());
  for (int p = 0; p < passes; p++) {
    const double x0 = pdf.crop_x / sx, y0 = pdf.crop_y / sy, dx = p * (width + kGap) / sx;
    b.push();
    b.clip(b.add_geometry(Path::rectangle(x0, y0, x0 + width / sx, y0 + height / sy)),
           Affine::translate(dx, 0), FillRule::NonZero);
    b.activate();
    b.append(page.ink_passes[p], Affine::translate(dx, 0));
    b.pop();
  }
  const Scene scene = b.finish();
  auto inks = std::make_shared<InkPage>();
  inks->names = page.ink_names;
  inks->spot_cmyk = page.spot_cmyk;
  inks->width = width;
  inks->gap = kGap;
  inks->separations = pdf.page.inks == pdf::InkModel::Separations;
  job->inks = std::move(inks);
  job->width = wide;
  job->height = height;
  job->options = cli::render_options(opt, wide, height, view, page_options.budget);
  job->plan = plan_render(job->options);
  job->scene = encode_for(scene, job->plan, job->options.gamma, &job->stats);
  return job;
}

}  // namespace mpvg
