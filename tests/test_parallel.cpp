// core/parallel.h: every index exactly once, whatever the thread count, and
// an exception from one item reaches the caller after all threads stop.
#include <atomic>
#include <stdexcept>
#include <vector>

#include "core/parallel.h"
#include "tests/catch.h"

using namespace mpvg;

TEST_CASE("parallel_for visits every index once", "[parallel]") {
  for (int threads : {0, 1, 3, 64})
    for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(10000)}) {
      std::vector<std::atomic<int>> hits(n);
      parallel_for(n, threads, [&](size_t i) { hits[i].fetch_add(1); });
      for (size_t i = 0; i < n; i++) REQUIRE(hits[i].load() == 1);
    }
}

TEST_CASE("parallel_for rethrows the first exception after joining", "[parallel]") {
  std::atomic<size_t> done{0};
  REQUIRE_THROWS_AS(parallel_for(1000, 4,
                                 [&](size_t i) {
                                   if (i == 17) throw std::runtime_error("item 17");
                                   done.fetch_add(1);
                                 }),
                    std::runtime_error);
  CHECK(done.load() < 1000);
}
