#pragma once
#include <atomic>
#include <cstdint>

namespace fscil {

// The run's --max-memory. A training pass asks, before it keeps its activations, whether the
// bytes it is about to need on top of what the process holds now would pass the limit; if so it
// recomputes them in backward instead (the same numbers). The budget counts those passes.
class MemoryBudget {
 public:
  explicit MemoryBudget(std::int64_t limit_bytes) : limit_bytes_(limit_bytes) {}
  // True, and counted, when in_use_bytes() + `more_bytes` > the limit: the pass recomputes.
  bool would_exceed(std::int64_t more_bytes);
  // Passes the limit made recompute since the last call.
  std::int64_t take_exceeding_passes() { return exceeding_passes_.exchange(0); }

 private:
  std::int64_t limit_bytes_;
  std::atomic<std::int64_t> exceeding_passes_{0};
};

// Resident bytes the process uses now: its resident set less what malloc holds free. Under
// keep_freed_memory_for_reuse (metrics/resource_usage.h) freed blocks stay resident in malloc's
// heaps, and the next allocations take them before the resident set grows, so they are room, not
// use. 0 where /proc/self/statm cannot be read (then no pass is over the limit).
std::int64_t in_use_bytes();

}  // namespace fscil
