// The shared ResNet-18 (D = 256, with PITS-SC's input norm) trained and run as the methods do,
// against PyTorch doing the same work from Python, measured earlier in the same `bench` run
// (pytorch_anchors.py), with the achieved GFLOP/s beside a 2048 x 2048 matrix product and a
// 3 x 3 convolution measured here. Training GFLOP/s counts 3 x the forward (forward, input
// gradients, weight gradients). Target: at least 1.3x PyTorch's rate on every shape.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <torch/torch.h>

#include "methods/common/encoder_step.h"
#include "methods/common/resnet18.h"
#include "tests/benchmarks/pytorch_anchors.h"
#include "tests/benchmarks/timed_steps.h"

namespace {

constexpr std::int64_t kBatch = 128;
constexpr double kTarget = 1.3;  // times PyTorch's rate

struct Shape {
  const char* name;  // as pytorch_anchors.py names it
  std::int64_t channels, mel_bins, frames;
};

double forward_flops(fscil::ResNet18Encoder& encoder, const Shape& shape) {
  fscil::ModelCost cost;
  encoder->count_cost(cost, "encoder", {shape.channels, shape.mel_bins, shape.frames});
  return static_cast<double>(cost.flops());
}

void report(benchmark::State& state, const std::string& figure, double flops_per_sample, double seconds) {
  const double rate = static_cast<double>(kBatch * state.iterations()) / seconds;
  const std::optional<double> pytorch = fscil::pytorch_rate(figure);
  state.SetLabel(fscil::anchor_label(rate, pytorch, kTarget, "PyTorch"));
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(kBatch), benchmark::Counter::kIsIterationInvariantRate);
  if (pytorch) state.counters["pytorch_samples_per_s"] = *pytorch;
  state.counters["GFLOP_per_s"] =
      benchmark::Counter(flops_per_sample * kBatch / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

void train(benchmark::State& state, Shape shape) {
  torch::manual_seed(1);
  fscil::EncoderStep work(shape.channels, shape.mel_bins, shape.frames, kBatch);
  const double seconds = fscil::seconds_of_steps(state, [&] { work.train(); });
  report(state, fmt::format("train/{}", shape.name), 3 * forward_flops(work.encoder(), shape), seconds);
}

void infer(benchmark::State& state, Shape shape) {
  torch::manual_seed(1);
  fscil::EncoderStep work(shape.channels, shape.mel_bins, shape.frames, kBatch);
  const double seconds = fscil::seconds_of_steps(state, [&] { work.infer(); });
  report(state, fmt::format("infer/{}", shape.name), forward_flops(work.encoder(), shape), seconds);
}

void matmul_peak(benchmark::State& state) {
  const torch::Tensor a = torch::randn({2048, 2048}), b = torch::randn({2048, 2048});
  for (auto _ : state) benchmark::DoNotOptimize(torch::mm(a, b).data_ptr());
  state.counters["GFLOP_per_s"] =
      benchmark::Counter(2.0 * 2048 * 2048 * 2048 / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

void conv3x3_peak(benchmark::State& state) {
  // ResNet-18's widest 3 x 3 layer on a HapTex batch: 128 x 64 x 16 x 6.
  torch::NoGradGuard no_grad;
  const torch::Tensor input = torch::randn({kBatch, 64, 16, 6}), weight = torch::randn({64, 64, 3, 3});
  for (auto _ : state) benchmark::DoNotOptimize(torch::conv2d(input, weight, {}, 1, 1).data_ptr());
  state.counters["GFLOP_per_s"] = benchmark::Counter(2.0 * kBatch * 64 * 16 * 6 * 64 * 9 / 1e9,
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(matmul_peak)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK(conv3x3_peak)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
// The tactile shapes (HapTex, LMT108) and the audio ones (LS-100, NS-100); the names and timing
// rules are pytorch_anchors.py's.
BENCHMARK_CAPTURE(train, haptex_5x64x24, Shape{"haptex_5x64x24", 5, 64, 24})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(infer, haptex_5x64x24, Shape{"haptex_5x64x24", 5, 64, 24})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(train, lmt108_3x64x493, Shape{"lmt108_3x64x493", 3, 64, 493})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK_CAPTURE(infer, lmt108_3x64x493, Shape{"lmt108_3x64x493", 3, 64, 493})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK_CAPTURE(train, ls100_3x128x178, Shape{"ls100_3x128x178", 3, 128, 178})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK_CAPTURE(infer, ls100_3x128x178, Shape{"ls100_3x128x178", 3, 128, 178})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK_CAPTURE(train, ns100_3x128x63, Shape{"ns100_3x128x63", 3, 128, 63})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK_CAPTURE(infer, ns100_3x128x63, Shape{"ns100_3x128x63", 3, 128, 63})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(10);

}  // namespace
