// main() of the benchmarks that run LibTorch: all cores (LibTorch starts with one thread) and
// malloc keeping freed blocks, as fscil-bench itself runs.
#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include <thread>

#include "metrics/resource_usage.h"

int main(int argc, char** argv) {
  fscil::keep_freed_memory_for_reuse();
  torch::set_num_threads(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
