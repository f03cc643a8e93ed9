#include "apps/pipeline.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <mutex>
#include <queue>
#include <thread>

#include "apps/cli.h"
#include "apps/png_writer.h"

namespace mpvg::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// The shared state; everything under `m`.
struct State {
  const Config& c;
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

  // Reports an item's end (under m): its error if any, its warnings and
  // stats, the progress line.
  void finish(const Job* job, const std::string& error, bool unrendered = false) {
    Result& r = result;
    r.finished++;
    in_flight--;
    if (!error.empty()) r.failed++;
    const char* nl = c.progress ? "\r\033[K" : "";
    // Items no renderer could take are counted, and reported once at the end.
    if (unrendered) r.unrendered++;
    else if (!error.empty()) std::fprintf(stderr, "%s%s: %s\n", nl, c.program, error.c_str());
    if (job && !c.quiet)
      for (const std::string& w : job->warnings)
        std::fprintf(stderr, "%s%s: %s: warning: %s\n", nl, c.program, job->label.c_str(), w.c_str());
    if (job && error.empty()) {
      const RenderStats& st = job->stats;
      r.prepare[0] += job->prepare_ms[0];
      r.prepare[1] += job->prepare_ms[1];
      r.encode += st.encode_ms;
      r.preprocess += st.abstract_ms + st.subdivide_ms + st.prune_ms;
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
                     st.abstract_ms + st.subdivide_ms + st.prune_ms, st.schedule_ms + st.sample_ms, job->png_ms,
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
    const std::vector<uint8_t> bytes =
        c.bits == 16 ? png::encode_rgba16(job.width, job.height, to_rgba16(job.image, c.gamma).data())
                     : png::encode_rgba8(job.width, job.height, job.rgba8.data());
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
               (next >= c.tickets && rendering_done);
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
          error = job->label + ": " + e.what();
        }
        job->image = ImageF{};
        lock.lock();
        spare_rgba8.push_back(std::move(job->rgba8));
        finish(job.get(), error);
        continue;
      }
      if (next >= c.tickets) return;  // rendering done, nothing to write
      const int t = next++;
      in_flight++;
      preparing++;
      lock.unlock();
      std::unique_ptr<Job> job;
      std::string error;
      try {
        job = c.prepare(t, w);
        job->index = t;
      } catch (const std::exception& e) {
        const std::string label = c.label(t);
        error = e.what();
        // Messages that name the item already (the PDF parser's "page 3:
        // ...") keep their own form.
        if (error.rfind(label, 0) != 0) error = label + ": " + error;
      }
      lock.lock();
      preparing--;
      if (job && renderers > 0) {
        to_render.push(std::move(job));
      } else {
        finish(job.get(), job ? job->label + ": not rendered" : error, job != nullptr);
      }
      cv.notify_all();
    }
  }

  // A render thread: one renderer for every item it takes, until every
  // item is prepared and rendered.
  void render(int r) {
    std::unique_ptr<FrameRenderer> renderer;
    std::string failure;
    try {
      renderer = c.make_renderer(r);
    } catch (const std::exception& e) {
      failure = e.what();
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
      cv.wait(lock, [&] { return !to_render.empty() || (next >= c.tickets && preparing == 0); });
      result.render_idle += ms_since(t_wait);
      if (to_render.empty()) break;
      std::unique_ptr<Job> job = std::move(const_cast<std::unique_ptr<Job>&>(to_render.top()));
      to_render.pop();
      std::vector<uint8_t> storage;
      if (!spare_rgba8.empty()) {
        storage = std::move(spare_rgba8.back());
        spare_rgba8.pop_back();
      }
      lock.unlock();
      std::string error;
      const auto t0 = Clock::now();
      try {
        if (c.bits == 16)
          job->image = renderer->render(job->scene, job->options, &job->stats);
        else
          job->rgba8 = renderer->render_rgba8(job->scene, job->plan, job->options, &job->stats, std::move(storage));
      } catch (const std::exception& e) {
        error = job->label + ": " + e.what();
      }
      job->scene = EncodedScene{};
      job->render_ms = ms_since(t0);
      lock.lock();
      if (error.empty()) {
        to_write.push_back(std::move(job));
        cv.notify_all();
      } else {
        finish(job.get(), error);
      }
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
  State s(config);
  if (config.tickets <= 0) return s.result;
  const int workers = std::max(1, std::min(config.workers, config.tickets));
  const int renderers = std::max(1, std::min(config.render_threads, config.tickets));
  s.max_in_flight = workers + 4 + renderers;
  s.renderers = renderers;
  std::vector<std::thread> threads;
  for (int r = 0; r < renderers; r++) threads.emplace_back([&s, r] { s.render(r); });
  for (int w = 0; w < workers; w++) threads.emplace_back([&s, w] { s.work(w); });
  for (std::thread& t : threads) t.join();
  if (config.progress)
    std::fprintf(stderr, "\r\033[K%s: %d %ss, %d failed\n", config.program, config.tickets, config.unit,
                 s.result.failed);
  if (s.result.unrendered)
    std::fprintf(stderr, "%s: %d %ss not rendered: no renderer could start\n", config.program, s.result.unrendered,
                 config.unit);
  s.result.seconds = ms_since(s.t_start) / 1000;
  return s.result;
}

std::string summary(const Config& c, const Result& r, const char* backend) {
  const double s = std::max(r.seconds, 1e-9);
  const int ok = std::max(1, r.finished - r.failed);
  const int workers = std::max(1, std::min(c.workers, c.tickets));
  const int renderers = std::max(1, std::min(c.render_threads, c.tickets));
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%s: %d %ss in %.3f s (%.1f %ss/s), %d workers, %d render threads, %s backend\n"
                "%s: per %s (mean ms): %s %.2f, %s %.2f, encoding %.2f, preprocessing %.2f, rendering %.2f, "
                "render thread %.2f, PNG %.2f (of which writing the file %.2f); idle: render threads %.0f%%, "
                "workers %.0f%%\n",
                c.program, r.finished, c.unit, s, r.finished / s, c.unit, workers, renderers, backend, c.program,
                c.unit, c.prepare_names[0], r.prepare[0] / ok, c.prepare_names[1], r.prepare[1] / ok, r.encode / ok,
                r.preprocess / ok, r.render / ok, r.render_wall / ok, r.png / ok, r.write / ok,
                100 * r.render_idle / (renderers * s * 1000), 100 * r.worker_idle / (workers * s * 1000));
  return buf;
}

}  // namespace mpvg::pipeline
