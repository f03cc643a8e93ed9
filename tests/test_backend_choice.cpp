// --backend auto's cost model (lib/backend/cost_model.cpp): the decisions it must
// take whatever its constants, and the start-up object without a device.
#include <cmath>

#include "lib/backend/backend.h"
#include "tests/catch.h"

using namespace mpvg;

namespace {

CostInputs frame(int width, int height, size_t segments, int samples, int support) {
  CostInputs in;
  in.input_segments = segments;
  in.unit_areas = double(width) * height;
  in.samples = samples;
  in.support = support;
  in.pixels = size_t(width) * height;
  in.cpu_threads = 2;
  in.gpu_possible = true;
  return in;
}

}  // namespace

TEST_CASE("cost model: no device means the CPU", "[backend]") {
  CostInputs in = frame(4096, 4096, 1000000, 32, 4);
  in.gpu_possible = false;
  const BackendChoice c = choose_backend(in);
  CHECK(c.backend == Backend::Cpu);
  CHECK(c.why == "no CUDA device");
}

TEST_CASE("cost model: a tiny frame renders on the CPU while CUDA starts", "[backend]") {
  CostInputs in = frame(10, 10, 4, 32, 4);
  in.gpu_wait_ms = expected_gpu_startup_ms();
  const BackendChoice c = choose_backend(in);
  CHECK(c.backend == Backend::Cpu);
  CHECK(c.cpu_ms < c.gpu_ms);
  CHECK(c.why.find("ms on 2 CPU threads") != std::string::npos);
}

TEST_CASE("cost model: a large frame goes to a ready GPU", "[backend]") {
  CostInputs in = frame(1024, 1024, 60000, 32, 4);  // tiger at 1024 px, 4x4x32
  in.gpu_wait_ms = 0;
  const BackendChoice c = choose_backend(in);
  CHECK(c.backend == Backend::Cuda);
  CHECK(c.gpu_ms < c.cpu_ms);
}

TEST_CASE("cost model: estimates grow with the work, waiting only counts against the GPU", "[backend]") {
  const CostInputs small = frame(256, 256, 1000, 8, 1);
  CostInputs big = frame(2048, 2048, 100000, 32, 4);
  CHECK(choose_backend(big).cpu_ms > choose_backend(small).cpu_ms);
  CHECK(choose_backend(big).gpu_ms > choose_backend(small).gpu_ms);
  CostInputs waiting = big;
  waiting.gpu_wait_ms = 100;
  CHECK(std::abs(choose_backend(waiting).gpu_ms - (choose_backend(big).gpu_ms + 100)) < 1e-9);
  CHECK(choose_backend(waiting).cpu_ms == choose_backend(big).cpu_ms);
  // More CPU threads, a cheaper CPU frame.
  CostInputs wide = big;
  wide.cpu_threads = 16;
  CHECK(choose_backend(wide).cpu_ms < choose_backend(big).cpu_ms);
  // Between the two: somewhere the choice flips from the CPU to the GPU.
  CostInputs in = frame(64, 64, 100, 32, 4);
  in.gpu_wait_ms = 50;
  bool seen_cpu = false, seen_gpu = false;
  for (int w = 16; w <= 8192; w *= 2) {
    in = frame(w, w, size_t(w) * 40, 32, 4);
    in.gpu_wait_ms = 50;
    const Backend b = choose_backend(in).backend;
    if (b == Backend::Cpu) CHECK_FALSE(seen_gpu);  // no flip back
    seen_cpu |= b == Backend::Cpu;
    seen_gpu |= b == Backend::Cuda;
  }
  CHECK(seen_cpu);
  CHECK(seen_gpu);
}

TEST_CASE("GPU start-up: nothing starts for the CPU; without a device take() says why", "[backend]") {
  RenderOptions like;
  GpuStartup cpu(Backend::Cpu, like);
  CHECK_FALSE(cpu.started());
  CHECK(cpu.done());
  std::string why;
  CHECK(cpu.take(&why) == nullptr);
  CHECK_FALSE(why.empty());
  GpuStartup autostart(Backend::Auto, like);
  CHECK((autostart.started() || !cuda_available()));
  std::unique_ptr<FrameRenderer> r = autostart.take(&why);
  CHECK(autostart.done());
  if (cuda_available()) {
    REQUIRE(r != nullptr);
    CHECK(r->backend() == Backend::Cuda);
  } else {
    CHECK(r == nullptr);
    CHECK_FALSE(why.empty());
  }
}
