#include "metrics/resource_usage.h"

#include <malloc.h>
#include <sys/resource.h>

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "core/number_text.h"

namespace fscil {

namespace {

// A "Name:    1234 kB" line of /proc/self/status, in bytes.
std::optional<std::int64_t> status_bytes(const char* name) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(name, 0) != 0) continue;
    const auto first = line.find_first_of("0123456789");
    if (first == std::string::npos) continue;
    const auto digits = line.substr(first, line.find_first_not_of("0123456789", first) - first);
    if (const auto kilobytes = parse_number<std::int64_t>(digits)) return *kilobytes * 1024;
  }
  return std::nullopt;
}

}  // namespace

std::int64_t peak_resident_bytes() {
  // VmHWM is the peak that clear_refs resets; ru_maxrss never resets.
  if (const auto peak = status_bytes("VmHWM:")) return *peak;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

void reset_peak_resident() {
  std::ofstream clear_refs("/proc/self/clear_refs");
  clear_refs << "5";
}

std::int64_t resident_bytes() { return status_bytes("VmRSS:").value_or(0); }

void give_back_freed_memory() { malloc_trim(0); }

void keep_freed_memory_for_reuse() {
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);  // -1: never give the heap's top back
}

void return_large_blocks_to_the_kernel() {
  constexpr int kLargeBlock = 1 << 20;
  mallopt(M_MMAP_THRESHOLD, kLargeBlock);  // a fixed threshold: glibc no longer raises it
  mallopt(M_MMAP_MAX, 1 << 16);            // glibc's default count of mapped blocks
  mallopt(M_TRIM_THRESHOLD, kLargeBlock);
}

CpuTimes cpu_times_now() {
  CpuTimes times;
  times.process_seconds = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  // "cpu  user nice system idle iowait irq softirq steal ..." in clock ticks, over every core.
  std::ifstream stat("/proc/stat");
  std::string line;
  if (!std::getline(stat, line) || line.rfind("cpu ", 0) != 0) return times;
  std::istringstream fields(line.substr(4));
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  if (!(fields >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal)) return times;
  times.machine_seconds = (user + nice + system + irq + softirq + steal) / static_cast<double>(sysconf(_SC_CLK_TCK));
  return times;
}

}  // namespace fscil
