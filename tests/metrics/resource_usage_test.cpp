#include "metrics/resource_usage.h"

#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace fscil {
namespace {

// The process's resident bytes, as the kernel counts them (whatever malloc holds free included).
std::int64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::int64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * sysconf(_SC_PAGESIZE);
}

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

}  // namespace
}  // namespace fscil
