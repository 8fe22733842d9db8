// CoP-FSCIL's incremental update time with PSPC (5-way 5-shot: N_ps probes of every support
// sample, calibrated prototypes, 200 fine-tuning steps), against N_ps, on HapTex-shaped
// (5 x 64 x 24) and LMT108-shaped (3 x 64 x 493) inputs: the paper's update-time table.
// The encoder's weights do not change the cost, so the base session is skipped (0 epochs).
// Targets: HapTex N_ps = 100 within 2.5 s, LMT108 N_ps = 10 within 5 s; the bound beside each
// is its probe forwards' FLOPs at the matrix-multiply peak.
#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include <chrono>

#include "methods/cop_fscil/cop_fscil_method.h"
#include "core/parameter_set.h"

namespace {

constexpr std::int64_t base_classes = 10, way = 5, shot = 5;

// This machine's 2048 x 2048 matrix-product rate, measured once in this run.
double peak_gflops() {
  static const double gflops = [] {
    const torch::Tensor a = torch::randn({2048, 2048}), b = torch::randn({2048, 2048});
    torch::mm(a, b);  // warm-up
    constexpr int kProducts = 10;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kProducts; ++i) torch::mm(a, b);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return kProducts * 2.0 * 2048 * 2048 * 2048 / seconds / 1e9;
  }();
  return gflops;
}

fscil::SessionData labelled(std::int64_t first_class, std::int64_t classes, std::int64_t per_class,
                            const fscil::InputShape& input) {
  fscil::SessionData data;
  data.features = torch::randn({classes * per_class, input.channels, input.mel_bins, input.frames});
  data.labels = torch::div(torch::arange(classes * per_class), per_class, "floor") + first_class;
  for (std::int64_t c = 0; c < classes; ++c) data.new_classes.push_back(first_class + c);
  data.session = first_class == 0 ? 0 : 1;
  return data;
}

void pspc_update(benchmark::State& state, fscil::InputShape input) {
  fscil::ParameterSet params;
  params.set("pretrain_epochs", "0");
  params.set("pit_epochs", "0");
  params.set("pspc_probes", std::to_string(state.range(0)));
  torch::manual_seed(1);
  fscil::RunContext context;
  context.generator = std::mt19937_64(1);
  context.total_classes = static_cast<int>(base_classes + way);
  context.base_classes = static_cast<int>(base_classes);
  context.input = input;
  const fscil::SessionData base = labelled(0, base_classes, 4, input);
  const fscil::SessionData support = labelled(base_classes, way, shot, input);
  std::unique_ptr<fscil::Method> method;
  for (auto _ : state) {
    state.PauseTiming();
    method = fscil::make_cop_fscil(params);
    method->train_base(base, context);
    state.ResumeTiming();
    method->learn_session(support, context);
  }
  const double forwards = static_cast<double>(way * shot * (state.range(0) + 1));
  const double gflop = forwards * static_cast<double>(method->inference_cost(input).flops()) / 1e9;
  state.counters["probe_forwards"] = forwards;
  state.counters["GFLOP"] = gflop;
  state.counters["peak_GFLOP_per_s"] = peak_gflops();
  state.counters["bound_s_at_peak"] = gflop / peak_gflops();
}

BENCHMARK_CAPTURE(pspc_update, haptex_shape, fscil::InputShape{5, 64, 24, 500})
    ->Arg(5)->Arg(10)->Arg(50)->Arg(100)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);
BENCHMARK_CAPTURE(pspc_update, lmt108_shape, fscil::InputShape{3, 64, 493, 7900})
    ->Arg(5)->Arg(10)->Arg(50)->Arg(100)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace
