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

}  // namespace fscil
