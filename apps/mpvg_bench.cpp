// mpvg_bench: GPU timings of the pipeline on SVG inputs at 1024 px width,
// beside the paper's Table 1 (GTX Titan). Per-stage times come from CUDA
// events after warm-up, medians over --runs repetitions; end-to-end is the
// wall time of `svg2png --backend cuda` on the same input.
//
//   mpvg_bench [--runs N] [--json FILE] [--svg2png PATH] [--shapes T,I,U;...] [--ramp-lut N]
//              [--grid-levels N] [--min-segments N] [--throughput K,K,...] FILE.svg...
//
// --grid-levels N builds the trees with N levels of coarse grid
// (TreeParams::grid_levels; default: from each scene's density).
// --min-segments N stops subdividing cells of N geometry entries or fewer
// (TreeParams::min_segments, the paper's stopping rule) for every column;
// default: the rule from each column's samples (stop_rule, core/tree/tree.h:
// 1x8 4, 1x32 and 4x4x32 1), which the sweep over N was measured for. The
// preprocessing columns are the 1x32 tree's.
//
// --throughput measures the render side of pdf2png's pipeline alone: for
// each K, K threads with a FrameRenderer each (their own device buffers and
// per-thread stream, as pdf2png's render threads) render the input at
// 1275 px width (a letter page at 150 dpi), 4x4x32, to 8-bit RGBA copied
// back, frame after frame; frames per second over the wall time, and each
// frame's mean stage times. The per-stage table is skipped.
//
// --ramp-lut N encodes colour ramps as lookup tables of N knots instead of
// exact knots (EncodeOptions::ramp_lut). When an input NAME_gradients.svg
// (scripts/make_gradient_bench.py) or NAME_groups.svg
// (scripts/make_group_bench.py) follows NAME.svg, the ratio of their render
// times is printed: the cost of per-sample gradients, or of nested groups
// and masks against the same scene flattened.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <atomic>
#include <map>
#include <mutex>
#include <thread>
#include <sstream>
#include <string>
#include <vector>

#include "frame/encoding.h"
#include "core/error.h"
#include "frame/frame.h"
#include "lib/backend/backend.h"
#include "gpu/gpu_backend.h"
#include "parsers/svg/svg_parser.h"
#include "cpu/cpu_frame.h"
#include "frame/scene_info.h"

using namespace mpvg;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Paper {
  double pre, r8, r32, r4432;
};
// Table 1 of the paper, GTX Titan, ms (with strokes converted to fills).
const std::map<std::string, Paper> kPaper = {
    {"tiger", {31.04, 12.89, 17.24, 52.70}},
    {"boston", {128.02, 37.22, 41.81, 71.14}},
    {"hawaii", {115.29, 26.16, 29.48, 50.50}},
    {"reschart", {24.96, 8.51, 11.14, 32.34}},
};

std::vector<gpu::SamplerShape> parse_shapes(const std::string& s) {
  std::vector<gpu::SamplerShape> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ';')) {
    gpu::SamplerShape sh;
    if (std::sscanf(item.c_str(), "%d,%d,%d", &sh.threads, &sh.chunk, &sh.batch) == 3) out.push_back(sh);
  }
  return out;
}

// The render side's ceiling (--throughput): see the header.
void throughput(const std::string& file, const std::vector<int>& thread_counts, int frames) {
  const int w = 1275;
  const svg::ParseResult doc = svg::parse_svg_file(file, svg::ParseOptions::at_width(w));
  const int h = static_cast<int>(std::lround(doc.scene.height * w / doc.scene.width));
  RenderOptions o;
  o.width = w;
  o.height = h;
  o.view = Affine::scale(w / doc.scene.width, h / doc.scene.height);
  o.filter = Filter::Cardinal;
  o.pattern = PatternKind::BlueNoise;
  o.samples = 32;
  o.backend = Backend::Cuda;
  o.background = RGBA{1, 1, 1, 1};
  o.aliased_paths = has_aliased_paths(doc.scene);
  const RenderPlan plan = plan_render(o);
  const EncodedScene enc = encode_for(doc.scene, plan, o.gamma);
  const std::string name = std::filesystem::path(file).stem().string();
  for (int k : thread_counts) {
    std::atomic<int> next{0}, ready{0};
    std::atomic<bool> go{false};
    std::mutex m;
    double pre = 0, render = 0, wall = 0;
    std::vector<std::thread> threads;
    for (int t = 0; t < k; t++)
      threads.emplace_back([&] {
        FrameRenderer r(Backend::Cuda);
        for (int warm = 0; warm < 2; warm++) r.render_rgba8(enc, plan, o);
        ready++;
        while (!go) std::this_thread::yield();
        double my_pre = 0, my_render = 0, my_wall = 0;
        while (next++ < frames) {
          RenderStats st;
          const auto t0 = std::chrono::steady_clock::now();
          r.render_rgba8(enc, plan, o, &st);
          my_wall += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
          my_pre += st.stroke_ms + st.abstract_ms + st.subdivide_ms + st.prune_ms;
          my_render += st.schedule_ms + st.sample_ms;
        }
        std::lock_guard<std::mutex> lock(m);
        pre += my_pre;
        render += my_render;
        wall += my_wall;
      });
    while (ready < k) std::this_thread::yield();
    const auto t0 = std::chrono::steady_clock::now();
    go = true;
    for (std::thread& t : threads) t.join();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-10s %dx%d, %d render threads: %.1f frames/s; per frame: preprocessing %.2f ms, rendering %.2f ms, "
                "thread wall %.2f ms\n",
                name.c_str(), w, h, k, frames / s, pre / frames, render / frames, wall / frames);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 21;
  std::string json_path, svg2png = "svg2png", shapes_arg, throughput_arg;
  EncodeOptions encode_options;
  int grid_levels = -1;
  int min_segments = -1;
  std::vector<std::string> files;
  for (int i = 1; i < argc; i++) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--json" && i + 1 < argc) json_path = argv[++i];
    else if (a == "--svg2png" && i + 1 < argc) svg2png = argv[++i];
    else if (a == "--shapes" && i + 1 < argc) shapes_arg = argv[++i];
    else if (a == "--ramp-lut" && i + 1 < argc) encode_options.ramp_lut = std::atoi(argv[++i]);
    else if (a == "--throughput" && i + 1 < argc) throughput_arg = argv[++i];
    else if (a == "--grid-levels" && i + 1 < argc) grid_levels = std::atoi(argv[++i]);
    else if (a == "--min-segments" && i + 1 < argc) min_segments = std::max(1, std::atoi(argv[++i]));
    else files.push_back(a);
  }
  if (files.empty()) {
    std::fprintf(stderr,
                 "usage: mpvg_bench [--runs N] [--json FILE] [--svg2png PATH] [--shapes T,I,U;...] [--ramp-lut N] "
                 "[--grid-levels N] [--min-segments N] [--throughput K,K,...] FILE.svg...\n");
    return 2;
  }
  if (!throughput_arg.empty()) {
    std::vector<int> ks;
    std::stringstream ss(throughput_arg);
    std::string item;
    while (std::getline(ss, item, ',')) ks.push_back(std::max(1, std::atoi(item.c_str())));
    try {
      for (const std::string& f : files) throughput(f, ks, std::max(runs, 20));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mpvg_bench: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  try {
    const std::string device = gpu::device_name();
    std::printf("device: %s, %d runs per measurement (median)\n\n", device.c_str(), runs);
    std::string json = "{\n  \"device\": \"" + device + "\",\n  \"runs\": " + std::to_string(runs) + ",\n  \"inputs\": [\n";
    std::printf("%-10s %7s %7s %7s %7s %7s %8s %7s %7s %7s %7s %7s %7s %9s | %8s %8s %8s\n", "input", "stroke", "abstr",
                "subdiv", "prune", "pre", "pre-wall", "sched", "sample", "1x8", "1x32", "4x4x32", "MiB", "svg2png",
                "paper-pre", "paper-32", "paper-44");
    gpu::Context ctx;
    std::vector<std::string> rows;
    std::map<std::string, std::array<double, 3>> renders;  // 1x8, 1x32, 4x4x32 per input
    for (size_t fi = 0; fi < files.size(); fi++) {
      const std::string& f = files[fi];
      const std::string name = std::filesystem::path(f).stem().string();
      const svg::ParseResult doc = svg::parse_svg_file(f, svg::ParseOptions::at_width(1024));
      const int w = 1024, h = static_cast<int>(std::lround(doc.scene.height * 1024.0 / doc.scene.width));
      // The paper's three modes: box 1x8 and 1x32, and 4x4x32 (cardinal
      // cubic B-spline, 32 blue-noise samples per unit area, linear light).
      auto plan_for = [&](Filter f, PatternKind pk, int samples) {
        RenderOptions o;
        o.width = w;
        o.height = h;
        o.view = Affine::scale(w / doc.scene.width, h / doc.scene.height);
        o.filter = f;
        o.pattern = pk;
        o.samples = samples;
        o.aliased_paths = has_aliased_paths(doc.scene);
        return plan_render(o);
      };
      const RenderPlan p8 = plan_for(Filter::Box, PatternKind::Stratified, 8);
      const RenderPlan p32 = plan_for(Filter::Box, PatternKind::Stratified, 32);
      const RenderPlan pc = plan_for(Filter::Cardinal, PatternKind::BlueNoise, 32);
      const EncodedScene enc = encode(doc.scene, p32.view, Gamma::Srgb, encode_options);
      const EncodedScene enc_c = encode(doc.scene, pc.view, Gamma::Linear, encode_options);
      // Each plan's tree: the stopping rule from its samples, unless --min-segments.
      auto tree_of = [&](const RenderPlan& p) {
        TreeParams t = p.tree;
        t.grid_levels = grid_levels;
        if (min_segments > 0) t.min_segments = static_cast<uint32_t>(min_segments);
        return t;
      };
      const TreeParams params = tree_of(p32), params8 = tree_of(p8), params_c = tree_of(pc);
      const bool tree8 = params8.min_segments != params.min_segments;  // 1x8 needs a tree of its own
      const PaintRecord bg = background_paint(RGBA{0, 0, 0, 0}, Gamma::Srgb);
      auto r8 = [&](gpu::GpuTimes* t) { return ctx.render_on_device(p8.integ, p8.frame, bg, t); };
      auto r32 = [&](gpu::GpuTimes* t) { return ctx.render_on_device(p32.integ, p32.frame, bg, t); };
      auto r4432 = [&](gpu::GpuTimes* t) { return ctx.render_on_device(pc.integ, pc.frame, bg, t); };
      for (int warm = 0; warm < 3; warm++) {
        ctx.build(enc_c, pc.frame.ua_w, pc.frame.ua_h, params_c);
        r4432(nullptr);
        if (tree8) {
          ctx.build(enc, w, h, params8);
          r8(nullptr);
        }
        ctx.build(enc, w, h, params);
        if (!tree8) r8(nullptr);
        r32(nullptr);
      }
      std::vector<double> sk, ab, sd, pr, pre, prew, sch32, sam32, t8, t32, t4432, integ4432;
      for (int r = 0; r < runs; r++) {
        gpu::GpuTimes tc;
        ctx.build(enc_c, pc.frame.ua_w, pc.frame.ua_h, params_c);
        t4432.push_back(r4432(&tc));
        integ4432.push_back(tc.integrate_ms);
        if (tree8) {
          ctx.build(enc, w, h, params8);
          t8.push_back(r8(nullptr));
        }
        gpu::GpuTimes tb;
        prew.push_back(ctx.build_timed(enc, w, h, params, &tb));
        sk.push_back(tb.stroke_ms);
        ab.push_back(tb.abstract_ms);
        sd.push_back(tb.subdivide_ms);
        pr.push_back(tb.prune_ms);
        pre.push_back(tb.preprocess_ms());
        if (!tree8) t8.push_back(r8(nullptr));
        gpu::GpuTimes t;
        t32.push_back(r32(&t));
        sch32.push_back(t.schedule_ms);
        sam32.push_back(t.sample_ms);
      }
      const double mib = ctx.tree_bytes() / 1048576.0;
      const gpu::Context::BuildCounts bc = ctx.build_counts();
      // A frame as a pipeline runs it (no stage timers): the build alone
      // (events around it), then build + render + the 8-bit codes back,
      // host wall; with its round trips and launches; host-driven, then
      // device-driven (gpu::GpuDrive), in the same run.
      struct FrameRun {
        double pre_wall = 0, frame = 0;
        size_t syncs = 0, launches = 0;
        bool driven = false;
      };
      auto frame_run = [&](gpu::GpuDrive d) {
        ctx.set_drive(d);
        FrameRun fr;
        std::vector<double> pw, fw;
        for (int r = 0; r < runs + 2; r++) {
          const double b = ctx.build_timed(enc, w, h, params, nullptr);
          const size_t s0 = ctx.host_syncs(), l0 = ctx.kernel_launches();
          const auto t0 = std::chrono::steady_clock::now();
          ctx.build(enc, w, h, params, nullptr, /*render_follows=*/true);
          const std::vector<uint8_t> px = ctx.render_rgba8(p32.integ, p32.frame, bg, false);
          const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
          fr.syncs = ctx.host_syncs() - s0;
          fr.launches = ctx.kernel_launches() - l0;
          const gpu::Context::BuildCounts k = ctx.build_counts();
          fr.driven = k.driven && !k.fallback;
          if (r >= 2) pw.push_back(b), fw.push_back(ms);
        }
        fr.pre_wall = median(pw);
        fr.frame = median(fw);
        return fr;
      };
      const FrameRun fh = frame_run(gpu::GpuDrive::Host), fd = frame_run(gpu::GpuDrive::Auto);
      std::printf("    frame 1x32, host-driven: pre-wall %.3f ms, frame %.3f ms, %zu round trips, %zu launches; "
                  "device-driven%s: pre-wall %.3f ms, frame %.3f ms, %zu round trips, %zu launches\n",
                  fh.pre_wall, fh.frame, fh.syncs, fh.launches, fd.driven ? "" : " (fell back)", fd.pre_wall, fd.frame,
                  fd.syncs, fd.launches);
      // End to end: the command-line tool, parse and PNG writing included.
      std::vector<double> e2e;
      const std::string cmd = svg2png + " -q --backend cuda --aa 1x32 --gamma srgb -w 1024 '" + f + "' /tmp/mpvg_bench_out.png";
      for (int r = 0; r < 5; r++) {
        const auto t0 = std::chrono::steady_clock::now();
        if (std::system(cmd.c_str()) != 0) {
          e2e.clear();
          break;
        }
        e2e.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      const auto paper = kPaper.find(name);
      char line[512];
      std::snprintf(line, sizeof line, "%-10s %7.3f %7.3f %7.3f %7.3f %7.3f %8.3f %7.3f %7.3f %7.3f %7.3f %7.3f %7.2f %9.1f | %8.2f %8.2f %8.2f",
                    name.c_str(), median(sk), median(ab), median(sd), median(pr), median(pre), median(prew), median(sch32),
                    median(sam32), median(t8), median(t32), median(t4432), mib, e2e.empty() ? NAN : median(e2e),
                    paper != kPaper.end() ? paper->second.pre : NAN, paper != kPaper.end() ? paper->second.r32 : NAN,
                    paper != kPaper.end() ? paper->second.r4432 : NAN);
      std::printf("%s\n", line);
      renders[name] = {median(t8), median(t32), median(t4432)};
      size_t suffix = name.rfind("_gradients");
      if (suffix == std::string::npos) suffix = name.rfind("_groups");
      if (suffix != std::string::npos && renders.count(name.substr(0, suffix))) {
        const auto& solid = renders[name.substr(0, suffix)];
        const auto& grad = renders[name];
        std::printf("    %s / %s render time: 1x8 %.3f, 1x32 %.3f, 4x4x32 %.3f\n", name.c_str(),
                    name.substr(0, suffix).c_str(), grad[0] / solid[0], grad[1] / solid[1], grad[2] / solid[2]);
      }
      std::printf("    build: depth %d, %zu kernel launches, %zu CUB calls, %zu host round trips\n", bc.depth,
                  bc.launches, bc.cub_calls, bc.syncs);
      std::fflush(stdout);
      char js[2048];
      std::snprintf(js, sizeof js,
                    "    {\"input\": \"%s\", \"width\": %d, \"height\": %d, \"input_segments\": %zu, "
                    "\"stroke_ms\": %.4f, \"abstract_ms\": %.4f, \"subdivide_ms\": %.4f, \"prune_ms\": %.4f, \"preprocess_ms\": %.4f, "
                    "\"preprocess_wall_ms\": %.4f, \"schedule_1x32_ms\": %.4f, \"sample_integrate_1x32_ms\": %.4f, "
                    "\"render_1x8_ms\": %.4f, \"render_1x32_ms\": %.4f, \"render_4x4x32_ms\": %.4f, "
                    "\"integrate_4x4x32_ms\": %.4f, \"tree_mib\": %.3f, \"svg2png_ms\": %.2f, "
                    "\"depth\": %d, \"launches\": %zu, \"cub_calls\": %zu, \"host_round_trips\": %zu, "
                    "\"host_driven\": {\"preprocess_wall_ms\": %.4f, \"frame_ms\": %.4f, \"frame_round_trips\": %zu, "
                    "\"frame_launches\": %zu}, \"device_driven\": {\"driven\": %s, \"preprocess_wall_ms\": %.4f, "
                    "\"frame_ms\": %.4f, \"frame_round_trips\": %zu, \"frame_launches\": %zu}}",
                    name.c_str(), w, h, enc.input_segment_count, median(sk), median(ab), median(sd), median(pr), median(pre),
                    median(prew), median(sch32), median(sam32), median(t8), median(t32), median(t4432),
                    median(integ4432), mib,
                    e2e.empty() ? -1.0 : median(e2e), bc.depth, bc.launches, bc.cub_calls, bc.syncs, fh.pre_wall,
                    fh.frame, fh.syncs, fh.launches, fd.driven ? "true" : "false", fd.pre_wall, fd.frame, fd.syncs,
                    fd.launches);
      rows.push_back(js);
      // Sampler shapes (threads S, chunk I, batch U), 1x32 render time.
      for (const gpu::SamplerShape& sh : parse_shapes(shapes_arg)) {
        ctx.set_sampler_shape(sh);
        std::vector<double> t;
        r32(nullptr);
        for (int r = 0; r < runs; r++) t.push_back(r32(nullptr));
        std::printf("    shape S=%d I=%d U=%d: 1x32 %.3f ms\n", sh.threads, sh.chunk, sh.batch, median(t));
        char sj[256];
        std::snprintf(sj, sizeof sj, "    {\"input\": \"%s\", \"shape\": [%d, %d, %d], \"render_1x32_ms\": %.4f}",
                      name.c_str(), sh.threads, sh.chunk, sh.batch, median(t));
        rows.push_back(sj);
      }
      ctx.set_sampler_shape(gpu::SamplerShape{});
    }
    for (size_t i = 0; i < rows.size(); i++) json += rows[i] + (i + 1 < rows.size() ? ",\n" : "\n");
    json += "  ]\n}\n";
    if (!json_path.empty()) {
      FILE* fp = std::fopen(json_path.c_str(), "w");
      if (!fp) throw Error("cannot write " + json_path);
      std::fputs(json.c_str(), fp);
      std::fclose(fp);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mpvg_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
