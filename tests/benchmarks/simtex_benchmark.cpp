// Wall time to simulate the full simulated datasets (targets: simtex < 10 s, simtex-lmt < 30 s
// on 2 cores) and to prepare them for a run (segments + log-Mel features, no cache).
#include <benchmark/benchmark.h>

#include <sstream>

#include "datasets/dataset_catalog.h"
#include "datasets/simtex.h"
#include "core/parameter_set.h"

namespace {

void generate(benchmark::State& state, fscil::SimtexConfig (*config)()) {
  std::size_t samples = 0;
  for (auto _ : state) {
    const auto recordings = fscil::generate_simtex(config());
    samples = 0;
    for (const auto& recording : recordings) samples += recording.signal.size();
    benchmark::DoNotOptimize(recordings.data());
  }
  state.counters["samples"] = static_cast<double>(samples);
}

void prepare(benchmark::State& state, const char* name) {
  for (auto _ : state) {
    std::stringstream log;
    const auto dataset = fscil::prepare_dataset(name, fscil::DatasetRequest{}, fscil::ParameterSet(), log);
    benchmark::DoNotOptimize(dataset.features.values.data());
  }
}

BENCHMARK_CAPTURE(generate, simtex, fscil::simtex_haptex_config)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);
BENCHMARK_CAPTURE(generate, simtex_lmt, fscil::simtex_lmt_config)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(prepare, simtex, "simtex")->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(prepare, simtex_lmt, "simtex-lmt")->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
