#include "metrics/resource_usage.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdlib>

namespace fscil {
namespace {

constexpr std::int64_t kBlock = std::int64_t{64} << 20;

// Resident bytes a touched-then-freed 64 MiB block leaves behind. A small block allocated after
// it pins the heap's top, so trimming the top cannot give the block back: only unmapping can.
std::int64_t resident_left_by_a_freed_block() {
  malloc_trim(0);  // free heap memory the process held before would serve the block unseen
  const std::int64_t before = resident_bytes();
  volatile char* block = static_cast<volatile char*>(std::malloc(kBlock));
  void* pin = std::malloc(64);
  if (block == nullptr || pin == nullptr) std::exit(3);
  for (std::int64_t at = 0; at < kBlock; at += 4096) block[at] = 1;
  std::free(const_cast<char*>(block));
  const std::int64_t left = resident_bytes() - before;
  std::free(pin);
  return left;
}

// Each policy changes the whole process's malloc, so each case runs in a child process of its own.
TEST(ResourceUsage, KeptFreedMemoryStaysResidentForReuse) {
  EXPECT_EXIT(
      {
        keep_freed_memory_for_reuse();
        std::exit(resident_left_by_a_freed_block() > kBlock / 2 ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
}

TEST(ResourceUsage, UnderAMemoryLimitLargeBlocksGoBackToTheKernel) {
  EXPECT_EXIT(
      {
        keep_freed_memory_for_reuse();
        return_large_blocks_to_the_kernel();
        std::exit(resident_left_by_a_freed_block() < kBlock / 8 ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
}

// What a run that needs 32 MiB is seen to add, after an earlier run freed a 64 MiB block that
// malloc keeps for reuse (the main job's case): with the freed memory given back first, its own
// 32 MiB; without, nothing, as the earlier run's block serves it unseen.
std::int64_t seen_to_add_after_a_freed_block(bool give_back) {
  keep_freed_memory_for_reuse();
  resident_left_by_a_freed_block();
  if (give_back) give_back_freed_memory();
  reset_peak_resident();
  const std::int64_t start = resident_bytes();
  volatile char* need = static_cast<volatile char*>(std::malloc(kBlock / 2));
  if (need == nullptr) std::exit(3);
  for (std::int64_t at = 0; at < kBlock / 2; at += 4096) need[at] = 1;
  return peak_resident_bytes() - start;
}

TEST(ResourceUsage, ARunsPeakAboveItsStartIsItsOwnOnceFreedMemoryIsGivenBack) {
  EXPECT_EXIT(std::exit(seen_to_add_after_a_freed_block(true) > kBlock * 3 / 8 ? 0 : 1), testing::ExitedWithCode(0), "");
  EXPECT_EXIT(std::exit(seen_to_add_after_a_freed_block(false) < kBlock / 8 ? 0 : 1), testing::ExitedWithCode(0), "")
      << "without giving back, the earlier block serves the run unseen";
}

}  // namespace
}  // namespace fscil
