// Strokes as fill geometry: each painted stroke becomes a filled path whose
// outline stroke::stroke_to_fill computes, all of them in parallel once the
// document walk is over.
#include <chrono>

#include "core/parallel.h"
#include "parsers/svg/svg_converter.h"

namespace mpvg::svg::detail {

// The stroke of shapes_[shape] as a filled path (nonzero) with the stroke
// paint, or nothing when it paints nothing (SVG 2 painting.html#StrokeProperties:
// stroke none, zero width, invisible or fully transparent). `bbox` is the
// shape's, for paint servers. The outline itself is computed later, with
// all others, by convert_strokes().
std::optional<Op> Converter::shape_stroke(uint32_t shape, const Style& st, const Affine& space, ShapeBox& bbox) {
  const Inherited& inh = st.inh;
  if (inh.stroke.kind == PaintSpec::Kind::None || !inh.visible || !(inh.stroke_width > 0)) return std::nullopt;
  StrokeJob job;
  job.source = shape;
  job.style.join = inh.stroke_join;
  job.style.cap = inh.stroke_cap;
  job.style.miter_limit = inh.stroke_miterlimit;
  job.style.dashes = inh.stroke_dasharray;
  job.style.dash_offset = inh.stroke_dashoffset;
  Op op = Op::of(OpKind::Fill);
  op.stroke = true;
  op.rule = FillRule::NonZero;
  op.aliased = inh.aliased_shapes;
  // Device pixels for tolerances and hairlines: the scene as the parse
  // options expect it to be rendered.
  stroke::Hairline hl;
  if (st.non_scaling_stroke) {
    // vector-effect: non-scaling-stroke: the stroke is computed in the
    // host coordinate space, here scene units (SVG 2 coords.html#VectorEffects).
    hl = stroke::hairline(inh.stroke_width, device_);
    job.device = device_;
    job.transform_first = true;
    job.space = space;
    op.xf = Affine{};
  } else {
    hl = stroke::hairline(inh.stroke_width, device_ * space);
    job.device = device_ * space;
    op.xf = space;
  }
  const auto paint = make_paint(inh.stroke, inh.stroke_opacity * hl.opacity, bbox, space);
  if (!paint) return std::nullopt;
  op.paint = *paint;
  job.style.width = hl.width;
  job.out = static_cast<uint32_t>(shapes_.size());
  shapes_.emplace_back();
  op.shape = job.out;
  stroke_jobs_.push_back(std::move(job));
  return op;
}

// Converts every stroke to fill geometry, in parallel. A stroke is the
// union of its subpaths' strokes, each dashed from the start of the
// pattern (SVG 2 painting.html#StrokeDashing), so a path of several
// subpaths is stroked one subpath per task (one long stroke does not hold
// up the others) and the pieces are concatenated in order: the result is
// the same geometry as stroking it whole. A stroke that comes out empty
// paints nothing.
void Converter::convert_strokes() {
  const auto t0 = std::chrono::steady_clock::now();
  struct Task {
    uint32_t job;
    int64_t contour;  // -1: the whole source
  };
  std::vector<Task> tasks;
  std::vector<size_t> first_task(stroke_jobs_.size() + 1);
  for (uint32_t j = 0; j < stroke_jobs_.size(); j++) {
    first_task[j] = tasks.size();
    const size_t n = shapes_[stroke_jobs_[j].source].contours().size();
    if (n <= 1)
      tasks.push_back({j, -1});
    else
      for (size_t c = 0; c < n; c++) tasks.push_back({j, static_cast<int64_t>(c)});
  }
  first_task[stroke_jobs_.size()] = tasks.size();
  std::vector<Path> pieces(tasks.size());
  parallel_for(tasks.size(), s_.options.threads, [&](size_t i) {
    const StrokeJob& job = stroke_jobs_[tasks[i].job];
    const Path& whole = shapes_[job.source];
    const Path part = tasks[i].contour < 0 ? Path{} : whole.contour_path(static_cast<size_t>(tasks[i].contour));
    const Path& source = tasks[i].contour < 0 ? whole : part;
    pieces[i] = job.transform_first
                    ? stroke::stroke_to_fill(stroke::transformed(source, job.space), job.style, job.device)
                    : stroke::stroke_to_fill(source, job.style, job.device);
  });
  if (s_.options.collect_strokes) {
    for (const StrokeJob& job : stroke_jobs_) {
      StrokeStyle st;
      st.width = job.style.width;
      st.join = static_cast<uint32_t>(job.style.join);
      st.cap = static_cast<uint32_t>(job.style.cap);
      st.miter_limit = job.style.miter_limit;
      st.dashes = job.style.dashes;
      st.dash_offset = job.style.dash_offset;
      const Path& src = shapes_[job.source];
      if (job.transform_first)
        s_.collected_strokes.add(stroke::transformed(src, job.space), st, job.device, job.out);
      else
        s_.collected_strokes.add(src, st, job.device, job.out);
    }
  }
  for (size_t j = 0; j < stroke_jobs_.size(); j++) {
    Path& out = shapes_[stroke_jobs_[j].out];
    out = std::move(pieces[first_task[j]]);
    for (size_t i = first_task[j] + 1; i < first_task[j + 1]; i++) out.append(pieces[i]);
  }
  s_.stroke_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s_.stroked_paths += stroke_jobs_.size();
  for (Op& op : ops_)
    if (op.kind == OpKind::Fill && op.stroke && shapes_[op.shape].empty()) op.kind = OpKind::Bounds;
}

}  // namespace mpvg::svg::detail
