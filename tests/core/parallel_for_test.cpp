#include "core/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

namespace fscil {
namespace {

TEST(ParallelFor, RunsEveryIndexOnceOnAnyNumberOfThreads) {
  for (const int threads : {0, 1, 2, 7}) {
    std::vector<std::atomic<int>> visits(1000);
    parallel_for(visits.size(), threads, [&](std::size_t i) { ++visits[i]; });
    for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << ", threads " << threads;
  }
  parallel_for(0, 4, [](std::size_t) { FAIL() << "no index to run"; });
}

TEST(ParallelFor, CarriesTheLowestFailingIndexsErrorToTheCallerAndStopsTakingWork) {
  std::atomic<std::size_t> started{0};
  try {
    parallel_for(10000, 4, [&](std::size_t i) {
      ++started;
      if (i == 40 || i == 41 || i == 900) throw std::runtime_error("index " + std::to_string(i));
    });
    FAIL() << "the worker's error was lost";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "index 40");
  }
  // Every index up to the failure ran, and once it failed at most one more per thread started.
  EXPECT_GE(started.load(), 41u);
  EXPECT_LT(started.load(), 10000u);
}

}  // namespace
}  // namespace fscil
