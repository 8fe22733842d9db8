#pragma once
#include <cstddef>
#include <functional>

namespace fscil {

// The one thread loop of the harness: runs body(i) for every i in [0, count) on up to `threads`
// threads (0 or less: the hardware's), the calling thread among them. Indices are taken in
// order; once a body throws no new index is started, and after every worker has stopped the
// exception of the lowest failing index is rethrown to the caller, so a worker's error is never
// lost and never terminates the program.
void parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

// The most threads a command takes (--threads, --jobs, --cpus-per-task): the cores of the largest
// common node (2 x 128-core EPYC), so a run's thread count from any cluster node can be repeated
// anywhere (it is part of a run's identity), while a typo such as 100000 is refused before it
// starts 100000 threads (3.7 GB resident, 262 GB virtual before anything ran).
constexpr int kMaxThreads = 256;

// The one default thread count: `requested` when above 0, else every hardware thread (at least 1).
int thread_count(int requested);

}  // namespace fscil
