#pragma once
#include <cstdint>

#include "core/stopwatch.h"

namespace fscil {

// Peak resident set size of this process since the last reset_peak_resident() (or its start),
// in bytes.
std::int64_t peak_resident_bytes();
// Starts a new peak from the current resident size, so each run of a multi-run process reports
// its own peak. Without Linux's clear_refs the peak stays process-wide.
void reset_peak_resident();
// The resident set size of this process now, in bytes (0 where /proc cannot be read).
std::int64_t resident_bytes();
// Gives the kernel back the free memory malloc keeps for reuse (keep_freed_memory_for_reuse), so
// the resident set is what is in use: before a run's memory is measured from it, or an earlier
// run's freed blocks would serve the next one unseen.
void give_back_freed_memory();

// Makes malloc keep freed memory for reuse instead of returning it to the kernel. glibc serves
// blocks above 32 MiB by mmap and unmaps them on free, so every training step on a large input
// paid for fresh zeroed pages: 30% of LMT108-shaped ResNet-18 training was page faults. Call once
// at the start of main().
void keep_freed_memory_for_reuse();
// Undoes keep_freed_memory_for_reuse: malloc maps each block of 1 MiB and more on its own and
// unmaps it on free, and gives back a free heap top of 1 MiB and more, so the resident set follows
// what is in use (heap blocks kept for reuse fragment: a freed block too small for the next
// request stays resident beside it). For a run under a memory limit, which asks for memory before
// speed.
void return_large_blocks_to_the_kernel();

// CPU seconds spent so far by this process (all its threads) and by the whole machine (every
// core's busy time, other processes' and the time a host took from the VM, "steal", included; from
// /proc/stat, 0 where it cannot be read). Two readings tell how much of the cores other work held
// between them.
struct CpuTimes {
  double process_seconds = 0;
  double machine_seconds = 0;
};
CpuTimes cpu_times_now();


}  // namespace fscil
