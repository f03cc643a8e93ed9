#include "lib/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <queue>
#include <set>
#include <thread>

#include "lib/pipeline/cli.h"
#include "lib/pipeline/json.h"
#include "lib/output/png_writer.h"
#include "core/error.h"

namespace mpvg::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Forest frames (frame/forest.h): small items waiting together are rendered
// as one frame, one tree build for all of them, up to Config::forest_scenes.
// An item is small with at most kForestItemSegments input segments and
// kForestItemPixels pixels; a frame takes items while their sums stay
// within kForestSegments and kForestPixels, all with the same options but
// size and view (same_frame_options).
constexpr size_t kForestItemSegments = 150000, kForestSegments = 600000;
constexpr double kForestItemPixels = 6e6, kForestPixels = 24e6;

struct FrameBudget {
  size_t segments = 0, scenes = 0;
  double pixels = 0;
  static bool small(const Job& j) {
    return j.scene.input_segment_count <= kForestItemSegments && double(j.width) * j.height <= kForestItemPixels;
  }
  // Counts `last`, the frame's latest item; false when the frame is full.
  bool add(const Config& c, const Job& first, const Job& last) {
    segments += last.scene.input_segment_count;
    pixels += double(last.width) * last.height;
    scenes++;
    return small(first) && int(scenes) < c.forest_scenes;
  }
  // May `next` join the frame?
  bool fits(const Job& first, const Job& next) const {
    return small(next) && same_frame_options(first.options, next.options) && same_frame_grid(first.plan, next.plan) &&
           segments + next.scene.input_segment_count <= kForestSegments &&
           pixels + double(next.width) * next.height <= kForestPixels;
  }
};

// The shared state; everything under `m`. Threads hold it by shared_ptr,
// with a copy of the Config: a thread still busy with an item that timed
// out is left behind by run().
struct State {
  const Config c;
  explicit State(const Config& config) : c(config) {}

  std::mutex m;
  std::condition_variable cv;
  Clock::time_point t_start = Clock::now();
  int next = 0;       // the next ticket to prepare
  int in_flight = 0;  // items taken and not yet finished
  int preparing = 0;  // items being prepared now
  int max_in_flight = 1;
  int renderers = 0;     // render threads still running
  bool rendering_done = false;
  Result result;
  // Prepared items waiting for a renderer, lowest index first.
  struct Later {
    bool operator()(const std::unique_ptr<Job>& a, const std::unique_ptr<Job>& b) const { return a->index > b->index; }
  };
  std::priority_queue<std::unique_ptr<Job>, std::vector<std::unique_ptr<Job>>, Later> to_render;
  std::deque<std::unique_ptr<Job>> to_write;
  // 8-bit images of written items, whose memory the render threads reuse:
  // fresh memory costs a page fault per 4 KiB while the copy from the
  // device fills it, many times the copy's own time in a virtual machine.
  std::vector<std::vector<uint8_t>> spare_rgba8;
  // --timeout: when each item being prepared or rendered started, the
  // items being prepared, and those that timed out while a thread still
  // works on them (that thread drops them when its stage ends).
  std::map<int, Clock::time_point> started;
  std::map<int, Clock::duration> spent;  // preparation time of items waiting for a renderer
  std::set<int> in_prepare, timed_out;
  std::map<int, Clock::time_point> began;  // --report: when each item in flight was taken
  int live_threads = 0;   // render threads and workers not yet returned
  bool stopping = false;  // every item is through: the watchdog ends

  bool all_finished() const { return result.finished >= c.tickets; }

  // Did ticket t time out while its stage ran (under m)? Then it has been
  // reported already, and is dropped.
  bool dropped(int t) {
    if (!timed_out.erase(t)) return false;
    started.erase(t);
    cv.notify_all();
    return true;
  }

  // The watchdog of --timeout: fails the items past the limit.
  void watch() {
    std::unique_lock<std::mutex> lock(m);
    const auto limit = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(c.timeout_s));
    while (!stopping) {
      cv.wait_for(lock, std::chrono::milliseconds(50));
      const auto now = Clock::now();
      for (const auto& [t, t0] : started) {
        if (timed_out.count(t) || now - t0 < limit) continue;
        timed_out.insert(t);
        if (in_prepare.erase(t)) preparing--;
        result.timed_out++;
        char why[64];
        std::snprintf(why, sizeof why, ": timed out after %g s", c.timeout_s);
        finish(nullptr, c.label(t) + why, false, t);
      }
    }
  }

  // Reports an item's end (under m): its error if any, its warnings and
  // stats, the progress line.
  void finish(const Job* job, const std::string& error, bool unrendered = false, int ticket = -1) {
    Result& r = result;
    r.finished++;
    in_flight--;
    if (!error.empty()) r.failed++;
    const int t = job ? job->index : ticket;
    if (c.report) {
      const auto at = began.find(t);
      const double ms = at == began.end() ? 0 : ms_since(at->second);
      if (at != began.end()) began.erase(at);
      const char* status = error.empty() ? "ok" : timed_out.count(t) ? "timed out" : "failed";
      static const std::vector<std::string> kNone;
      const std::string line =
          report_line(c.report_input ? c.report_input(t) : c.label(t), c.report_output ? c.report_output(t) : "",
                      status, ms, job ? job->warnings : kNone, error);
      std::fprintf(c.report, "%s\n", line.c_str());
      std::fflush(c.report);
    }
    if (job && error.empty() && c.written) c.written(*job);
    const char* nl = c.progress ? "\r\033[K" : "";
    if (!error.empty() && c.failed) c.failed(job ? job->index : ticket, error);
    // Items no renderer could take are counted, and reported once at the end.
    if (unrendered) r.unrendered++;
    else if (!error.empty() && !c.failed) std::fprintf(stderr, "%s%s: %s\n", nl, c.program, error.c_str());
    if (job && !c.quiet)
      for (const std::string& w : job->warnings)
        std::fprintf(stderr, "%s%s: %s: warning: %s\n", nl, c.program, job->label.c_str(), w.c_str());
    if (job && error.empty()) {
      const RenderStats& st = job->stats;
      r.prepare[0] += job->prepare_ms[0];
      r.prepare[1] += job->prepare_ms[1];
      r.encode += st.encode_ms;
      r.preprocess += st.stroke_ms + st.abstract_ms + st.subdivide_ms + st.prune_ms;
      r.render += st.schedule_ms + st.sample_ms;
      r.render_wall += job->render_ms;
      r.png += job->png_ms;
      r.write += job->write_ms;
      if (c.stats)
        std::fprintf(stderr,
                     "%s%s: %dx%d, %s %.2f ms, %s %.2f ms, encoding %.2f ms, preprocessing %.2f ms, rendering "
                     "%.2f ms, PNG %.2f ms\n%s",
                     nl, job->label.c_str(), job->width, job->height, c.prepare_names[0], job->prepare_ms[0],
                     c.prepare_names[1], job->prepare_ms[1], st.encode_ms,
                     st.stroke_ms + st.abstract_ms + st.subdivide_ms + st.prune_ms, st.schedule_ms + st.sample_ms, job->png_ms,
                     cli::format_stats(st).c_str());
    }
    if (c.progress) {
      const double s = ms_since(t_start) / 1000;
      const double rate = r.finished / std::max(s, 1e-3);
      std::fprintf(stderr, "\r%s: %d of %d %ss, %.1f/s, ETA %.0f s", c.program, r.finished, c.tickets, c.unit, rate,
                   (c.tickets - r.finished) / std::max(rate, 1e-3));
    }
    cv.notify_all();
  }

  void write(Job& job) {
    const auto t0 = Clock::now();
    if (c.deliver) {
      c.deliver(job);
      job.png_ms = ms_since(t0);
      return;
    }
    png::EncodeOptions options;
    if (c.compression >= 0) options.level = c.compression;
    const bool rgb = c.color == png::Color::Rgb;
    std::vector<uint8_t> bytes;
    // TIFF, JPEG (print preview's TIFFs too): the OpenImageIO module, with
    // the page's resolution.
    image::EncodeOptions encode = c.encode;
    encode.dpi = job.dpi;
    encode.dpi_y = job.dpi_y;
    if (job.inks) {
      write_ink_page(*job.inks, job.out, job.width, job.height, job.rgba8.data(), encode);
      job.png_ms = ms_since(t0);
      return;
    }
    if (!job.png_rows.rows.empty()) {
      bytes = png::encode_filtered(job.width, job.height, job.png_rows, options);
    } else if (c.format != image::Format::Png) {
      bytes = c.bits == 16 ? image::encode_rgba16(c.format, job.width, job.height,
                                                  to_rgba16(job.image, c.gamma).data(), c.color, encode)
                           : image::encode_rgba8(c.format, job.width, job.height, job.rgba8.data(), c.color, encode);
    } else
      bytes =
          !job.png.zlib.empty() ? png::wrap(job.width, job.height, 8, job.png.channels, job.png.zlib.data(), job.png.zlib.size())
        : c.bits == 16 && rgb ? png::encode_rgba16(job.width, job.height, to_rgba16(job.image, c.gamma).data(), options)
        : c.bits == 16        ? png::encode_gray16(job.width, job.height, to_rgba16(job.image, c.gamma).data(), options)
        : rgb                 ? png::encode_rgba8(job.width, job.height, job.rgba8.data(), options)
                              : png::encode_gray8(job.width, job.height, job.rgba8.data(), c.color, options);
    if (c.format == image::Format::Png) png::set_resolution(bytes, job.dpi, job.dpi_y);
    const auto t1 = Clock::now();
    png::write_file(job.out, bytes);
    job.write_ms = ms_since(t1);
    job.png_ms = ms_since(t0);
  }

  // A worker: writes rendered items first, prepares new ones while there
  // is room, until every item is through.
  void work(int w) {
    std::unique_lock<std::mutex> lock(m);
    for (;;) {
      const auto t_wait = Clock::now();
      cv.wait(lock, [&] {
        return !to_write.empty() || (next < c.tickets && in_flight < max_in_flight) ||
               (next >= c.tickets && (rendering_done || all_finished()));
      });
      result.worker_idle += ms_since(t_wait);
      if (!to_write.empty()) {
        std::unique_ptr<Job> job = std::move(to_write.front());
        to_write.pop_front();
        lock.unlock();
        std::string error;
        try {
          write(*job);
        } catch (const std::exception& e) {
          error = job->label + ": " + error_message(e);
        }
        job->image = ImageF{};
        lock.lock();
        if (!error.empty()) result.write_failed++;
        spare_rgba8.push_back(std::move(job->rgba8.empty() ? job->png_rows.rows : job->rgba8));
        finish(job.get(), error);
        continue;
      }
      if (next >= c.tickets) return;  // rendering done, nothing to write
      const int t = next++;
      in_flight++;
      preparing++;
      if (c.report) began[t] = Clock::now();
      if (c.timeout_s > 0) {
        started[t] = Clock::now();
        in_prepare.insert(t);
      }
      lock.unlock();
      std::unique_ptr<Job> job;
      std::string error;
      try {
        job = c.prepare(t, w);
        job->index = t;
      } catch (const std::exception& e) {
        const std::string label = c.label(t);
        error = error_message(e);
        // Messages that name the item already (the PDF parser's "page 3:
        // ...") keep their own form.
        if (error.rfind(label, 0) != 0) error = label + ": " + error;
      }
      lock.lock();
      if (dropped(t)) continue;  // its preparation was counted out by the watchdog
      preparing--;
      in_prepare.erase(t);
      if (started.count(t)) {
        // The clock stops while the item waits for a renderer.
        if (job) spent[t] = Clock::now() - started[t];
        started.erase(t);
      }
      if (job && renderers > 0) {
        to_render.push(std::move(job));
      } else {
        finish(job.get(), job ? job->label + ": not rendered" : error, job != nullptr, t);
      }
      cv.notify_all();
    }
  }

  // Is the PNG stage run where the frame renders (level 1 on the device)?
  // Not for grey or mono: the device's PNG stage writes RGB(A) only; nor
  // for TIFF or JPEG.
  bool png_on_device(const FrameRenderer& renderer) const {
    return renderer.backend() == Backend::Cuda && c.compression == 1 && c.color == png::Color::Rgb &&
           c.format == image::Format::Png;
  }
  // Or its first half, the rows' filtering (at every other level, RGB
  // PNGs from CUDA render threads): a worker is left with deflate, about
  // half of its PNG time (BENCHMARKS.md, issue 49), and a quarter fewer
  // bytes come back from the device for an opaque page. Not for print
  // preview's ink passes, which the workers write from the 8-bit codes.
  bool filter_on_device(const FrameRenderer& renderer, const Job& job) const {
    return renderer.backend() == Backend::Cuda && c.compression != 1 && c.color == png::Color::Rgb &&
           c.format == image::Format::Png && c.bits == 8 && !c.deliver && !job.inks;
  }
  FrameOutputKind output_kind(const FrameRenderer& renderer, const Job& job) const {
    return png_on_device(renderer)           ? FrameOutputKind::Png
           : filter_on_device(renderer, job) ? FrameOutputKind::Filtered
                                             : FrameOutputKind::Rgba8;
  }

  // Renders one item in a frame of its own; the error message, or empty.
  std::string render_one(FrameRenderer& renderer, Job& job, std::vector<uint8_t> storage) {
    job.stats.stage_times = c.stats;
    try {
      if (job.filtered) {
        job.scene = renderer.encode(*job.filtered, job.plan, job.options, &job.stats);
        job.filtered.reset();
        job.warnings.insert(job.warnings.end(), job.stats.warnings.begin(), job.stats.warnings.end());
      }
      if (c.bits == 16)
        job.image = renderer.render(job.scene, job.options, &job.stats);
      else if (c.device_output)
        job.device_image = renderer.render_rgba8_device(job.scene, job.plan, job.options, &job.stats);
      else if (const FrameOutputKind kind = output_kind(renderer, job); kind == FrameOutputKind::Png) {
        // Level 1 only, asked for: the default (level 2 on the workers)
        // gives the same bytes whichever backend renders, and on the H100
        // host (16 cores, BENCHMARKS.md "PNG stage") it is also faster:
        // the render threads bound a batch, and the device's PNG stage
        // holds each up ~1.4 ms more per file (111-117 files/s against
        // 128-135). Level 1 pays off where workers are few for the render
        // threads: ~22 ms of a worker's time per 1024 px file become ~1.
        try {
          job.png = renderer.render_png(job.scene, job.plan, job.options, &job.stats);
        } catch (const Error&) {
          // the PNG stage's buffers did not fit the device: the frame
          // again, compressed by a worker
          job.rgba8 = renderer.render_rgba8(job.scene, job.plan, job.options, &job.stats, std::move(storage));
        }
      } else if (kind == FrameOutputKind::Filtered)
        job.png_rows = renderer.render_filtered(job.scene, job.plan, job.options, &job.stats, std::move(storage));
      else
        job.rgba8 = renderer.render_rgba8(job.scene, job.plan, job.options, &job.stats, std::move(storage));
    } catch (const std::exception& e) {
      return job.label + ": " + error_message(e);
    }
    return {};
  }

  // A render thread: one renderer for every item it takes, until every
  // item is prepared and rendered.
  void render(int r) {
    std::unique_ptr<FrameRenderer> renderer;
    std::string failure;
    try {
      renderer = c.make_renderer(r);
    } catch (const std::exception& e) {
      failure = error_message(e);
    }
    std::unique_lock<std::mutex> lock(m);
    if (!renderer) {
      // nullptr without an error: this thread is not needed (CUDA turned
      // out to be absent and one CPU render thread does the work).
      if (!failure.empty())
        std::fprintf(stderr, "%s%s: %s\n", c.progress ? "\r\033[K" : "", c.program, failure.c_str());
      retire();
      return;
    }
    for (;;) {
      const auto t_wait = Clock::now();
      cv.wait(lock, [&] { return !to_render.empty() || (next >= c.tickets && (preparing == 0 || all_finished())); });
      result.render_idle += ms_since(t_wait);
      if (to_render.empty()) break;
      // The item, and with it as many small items waiting now as a forest
      // frame takes (none is waited for: an item is never held back beyond
      // the frame it joins).
      std::vector<std::unique_ptr<Job>> jobs;
      FrameBudget budget;
      do {
        jobs.push_back(std::move(const_cast<std::unique_ptr<Job>&>(to_render.top())));
        to_render.pop();
        const Job& j = *jobs.back();
        if (auto it = spent.find(j.index); it != spent.end()) {
          started[j.index] = Clock::now() - it->second;
          spent.erase(it);
        }
      } while (c.bits == 8 && !to_render.empty() && !jobs.front()->filtered && !to_render.top()->filtered &&
               budget.add(c, *jobs.front(), *jobs.back()) && budget.fits(*jobs.front(), *to_render.top()));
      // Buffers of written items for the 8-bit images (fresh memory costs a
      // page fault per 4 KiB while the copy fills it: a forest frame without
      // them took 16-17 ms of its render thread a pgfmanual page, 12-13
      // alone).
      std::vector<std::vector<uint8_t>> storage;
      while (storage.size() < jobs.size() && !spare_rgba8.empty()) {
        storage.push_back(std::move(spare_rgba8.back()));
        spare_rgba8.pop_back();
      }
      lock.unlock();
      std::vector<std::string> errors(jobs.size());
      const auto t0 = Clock::now();
      bool done = false;
      if (jobs.size() > 1) {
        try {
          std::vector<FrameScene> frame;
          for (const auto& j : jobs) {
            j->stats.stage_times = c.stats;
            frame.push_back(FrameScene{&j->scene, &j->plan, &j->stats});
          }
          // A frame's items share their options and the run's, so the
          // first item's output kind is every item's (checked).
          const FrameOutputKind kind = output_kind(*renderer, *jobs.front());
          for (const auto& j : jobs)
            if (output_kind(*renderer, *j) != kind) throw Error("frame of mixed outputs");
          std::vector<FrameRenderer::Output> out =
              renderer->render_forest(frame, jobs.front()->options, kind, std::move(storage));
          for (size_t k = 0; k < jobs.size(); k++) {
            jobs[k]->png = std::move(out[k].png);
            jobs[k]->png_rows = std::move(out[k].filtered);
            jobs[k]->rgba8 = std::move(out[k].rgba8);
          }
          done = true;
        } catch (const std::exception&) {
          // Rendered one by one below: the frame's failure may be one
          // item's, or the items' together (device memory), not each one's.
          for (const auto& j : jobs) j->stats = RenderStats{};
        }
      }
      if (!done)
        for (size_t k = 0; k < jobs.size(); k++)
          errors[k] = render_one(*renderer, *jobs[k], k < storage.size() ? std::move(storage[k]) : std::vector<uint8_t>{});
      const double share = ms_since(t0) / double(jobs.size());
      lock.lock();
      result.frames += done ? 1 : static_cast<int>(jobs.size());
      for (size_t k = 0; k < jobs.size(); k++) {
        std::unique_ptr<Job>& job = jobs[k];
        job->scene = EncodedScene{};
        job->render_ms = share;
        if (dropped(job->index)) continue;
        started.erase(job->index);
        if (errors[k].empty()) {
          to_write.push_back(std::move(job));
        } else {
          finish(job.get(), errors[k]);
        }
      }
      cv.notify_all();
    }
    retire();
  }

  // A render thread ends (under m). The last one fails what is left
  // waiting, if it gave up before the work was done.
  void retire() {
    if (--renderers == 0) {
      while (!to_render.empty()) {
        std::unique_ptr<Job> job = std::move(const_cast<std::unique_ptr<Job>&>(to_render.top()));
        to_render.pop();
        finish(job.get(), job->label + ": not rendered", true);
      }
      rendering_done = true;
    }
    cv.notify_all();
  }
};

}  // namespace

Result run(const Config& config) {
  auto state = std::make_shared<State>(config);
  State& s = *state;
  if (config.tickets <= 0) return s.result;
  const int workers = std::max(1, std::min(config.workers, config.tickets));
  const int renderers = std::max(1, std::min(config.render_threads, config.tickets));
  // Room for every render thread's forest frame besides the workers' items
  // (a window of `renderers` items starved the workers once frames took
  // several: pgfmanual 144 -> 130 pages/s with frames of up to 8).
  s.max_in_flight = workers + 4 + renderers * std::max(1, config.forest_scenes);
  s.renderers = renderers;
  s.live_threads = renderers + workers;
  auto ended = [](State& st) {
    std::lock_guard<std::mutex> lock(st.m);
    st.live_threads--;
    st.cv.notify_all();
  };
  std::vector<std::thread> threads;
  for (int r = 0; r < renderers; r++)
    threads.emplace_back([state, r, ended] {
      state->render(r);
      ended(*state);
    });
  for (int w = 0; w < workers; w++)
    threads.emplace_back([state, w, ended] {
      state->work(w);
      ended(*state);
    });
  std::thread watchdog;
  if (config.timeout_s > 0) watchdog = std::thread([state] { state->watch(); });
  Result result;
  {
    // Done when every thread has returned but those still inside a stage
    // of an item that timed out: those are left to finish on their own.
    std::unique_lock<std::mutex> lock(s.m);
    s.cv.wait(lock, [&] { return s.live_threads <= static_cast<int>(s.timed_out.size()); });
    s.stopping = true;
    s.cv.notify_all();
    result = s.result;
    result.abandoned = s.live_threads;
  }
  if (watchdog.joinable()) watchdog.join();
  for (std::thread& t : threads) t.detach();  // each has returned or is abandoned
  const char* nl = config.progress ? "\r\033[K" : "";
  if (result.unrendered && !config.failed)
    std::fprintf(stderr, "%s%s: %d %ss not rendered: no renderer could start\n", nl, config.program, result.unrendered,
                 config.unit);
  // The summary line of a job of several items, on a terminal or not.
  if (config.failed) {
    // (the caller heard of every failure)
  } else if (config.tickets > 1 && (!config.quiet || result.failed))
    std::fprintf(stderr, "%s%s: %d %ss, %d written, %d failed%s\n", nl, config.program, config.tickets, config.unit,
                 result.finished - result.failed, result.failed,
                 result.timed_out ? (" (" + std::to_string(result.timed_out) + " timed out)").c_str() : "");
  else if (config.progress)
    std::fprintf(stderr, "%s", nl);
  result.seconds = ms_since(s.t_start) / 1000;
  return result;
}

std::string report_line(const std::string& input, const std::string& output, const char* status, double ms,
                        const std::vector<std::string>& warnings, const std::string& error) {
  std::string line = "{\"input\": " + json::quote(input) + ", \"output\": " + json::quote(output) +
                     ", \"status\": " + json::quote(status) + ", \"ms\": " + json::number(ms, 1) +
                     ", \"warnings\": " + json::string_array(warnings);
  if (!error.empty()) line += ", \"error\": " + json::quote(error);
  return line + "}";
}

std::string summary(const Config& c, const Result& r, const char* backend) {
  const double s = std::max(r.seconds, 1e-9);
  const int ok = std::max(1, r.finished - r.failed);
  const int workers = std::max(1, std::min(c.workers, c.tickets));
  const int renderers = std::max(1, std::min(c.render_threads, c.tickets));
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%s: %d %ss in %.3f s (%.1f %ss/s), %d workers, %d render threads, %d frames, %s backend\n"
                "%s: per %s (mean ms): %s %.2f, %s %.2f, encoding %.2f, preprocessing %.2f, rendering %.2f, "
                "render thread %.2f, PNG %.2f (of which writing the file %.2f); idle: render threads %.0f%%, "
                "workers %.0f%%\n",
                c.program, r.finished, c.unit, s, r.finished / s, c.unit, workers, renderers, r.frames, backend, c.program,
                c.unit, c.prepare_names[0], r.prepare[0] / ok, c.prepare_names[1], r.prepare[1] / ok, r.encode / ok,
                r.preprocess / ok, r.render / ok, r.render_wall / ok, r.png / ok, r.write / ok,
                100 * r.render_idle / (renderers * s * 1000), 100 * r.worker_idle / (workers * s * 1000));
  return buf;
}

}  // namespace mpvg::pipeline
