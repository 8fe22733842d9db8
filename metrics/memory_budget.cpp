#include "metrics/memory_budget.h"

#include <malloc.h>
#include <unistd.h>

#include <fstream>

namespace fscil {

bool MemoryBudget::would_exceed(std::int64_t more_bytes) {
  if (in_use_bytes() + more_bytes <= limit_bytes_) return false;
  ++exceeding_passes_;
  return true;
}

std::int64_t in_use_bytes() {
  std::ifstream statm("/proc/self/statm");  // pages: total, resident, ...
  std::int64_t total_pages = 0, resident_pages = 0;
  statm >> total_pages >> resident_pages;
  const auto held_free = static_cast<std::int64_t>(mallinfo2().fordblks);
  const std::int64_t resident = resident_pages * sysconf(_SC_PAGESIZE);
  return resident > held_free ? resident - held_free : 0;
}

}  // namespace fscil
