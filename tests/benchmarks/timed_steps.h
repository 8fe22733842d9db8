#pragma once
#include <benchmark/benchmark.h>

#include <chrono>

namespace fscil {

// Wall seconds of a benchmark's timed steps, after one untimed step: first-touch page faults and
// oneDNN's kernel generation are not the rate.
template <typename Step>
double seconds_of_steps(benchmark::State& state, const Step& step) {
  step();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) step();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace fscil
