// Does `--precision bf16` pay on this CPU? The shared encoder's training step and inference pass
// (as resnet18_benchmark runs them) in fp32 and in bf16 as a run computes it (the encoder's stem
// and stages under LibTorch's CPU autocast, methods/common/precision.h), and one 3 x 3
// convolution, forward and backward, in both types in the channels-last layout oneDNN's kernels
// use. Each bf16 figure is labelled with its ratio to the fp32
// figure measured just before it in this run. Only a CPU with AVX512-BF16 (or AMX) has the bf16
// kernels; on others bf16 is emulated, and the label says so.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <torch/torch.h>

#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "methods/common/encoder_step.h"
#include "tests/benchmarks/pytorch_anchors.h"
#include "tests/benchmarks/timed_steps.h"

namespace {

constexpr std::int64_t kBatch = 128;
constexpr double kWorthIt = 1.3;  // (ours) what a precision that changes the numbers must buy: the speed issues' target

std::map<std::string, double>& fp32_rates() {
  static std::map<std::string, double> rates;
  return rates;
}

bool has_bf16_kernels() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  const std::string text{std::istreambuf_iterator<char>(cpuinfo), std::istreambuf_iterator<char>()};
  return text.find("avx512_bf16") != std::string::npos || text.find("amx_bf16") != std::string::npos;
}

void report(benchmark::State& state, const std::string& figure, bool bf16, double seconds) {
  const double rate = static_cast<double>(kBatch * state.iterations()) / seconds;
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(kBatch), benchmark::Counter::kIsIterationInvariantRate);
  if (!bf16) {
    fp32_rates()[figure] = rate;
    state.SetLabel("fp32");
    return;
  }
  const auto fp32 = fp32_rates().find(figure);
  if (fp32 == fp32_rates().end()) {
    state.SetLabel("no fp32 rate: its fp32 twin must run first (a filter that keeps it, no random interleaving)");
    return;
  }
  static const bool native = has_bf16_kernels();
  state.SetLabel(fscil::anchor_label(rate, fp32->second, kWorthIt, "fp32") +
                 (native ? "" : " (no AVX512-BF16 or AMX: bf16 emulated)"));
}

struct Shape {
  const char* name;
  std::int64_t channels, mel_bins, frames;
};

void step(benchmark::State& state, Shape shape, bool train, bool bf16) {
  torch::manual_seed(1);
  fscil::EncoderStep work(shape.channels, shape.mel_bins, shape.frames, kBatch,
                          bf16 ? fscil::Precision::bf16 : fscil::Precision::fp32);
  const auto once = [&] {
    if (train)
      work.train();
    else
      work.infer();
  };
  const double seconds = fscil::seconds_of_steps(state, once);
  report(state, fmt::format("{}/{}", train ? "train" : "infer", shape.name), bf16, seconds);
}

// ResNet-18's first stage on an NS-100 batch: 128 x 64 x 32 x 16.
void conv3x3(benchmark::State& state, bool bf16) {
  const auto type = bf16 ? torch::kBFloat16 : torch::kFloat;
  const auto layout = torch::MemoryFormat::ChannelsLast;
  const torch::Tensor input = torch::randn({kBatch, 64, 32, 16}).to(type).contiguous(layout).requires_grad_();
  const torch::Tensor weight = torch::randn({64, 64, 3, 3}).to(type).contiguous(layout).requires_grad_();
  // The gradients are returned, not accumulated into .grad, so no step adds a previous one's.
  const auto once = [&] { torch::autograd::grad({torch::conv2d(input, weight, {}, 1, 1).sum()}, {input, weight}); };
  report(state, "conv3x3", bf16, fscil::seconds_of_steps(state, once));
}

constexpr Shape kHaptex{"haptex_5x64x24", 5, 64, 24};
constexpr Shape kNs100{"ns100_3x128x63", 3, 128, 63};

// Registration order is run order (unless interleaved at random): each fp32 figure before its bf16 twin.
BENCHMARK_CAPTURE(conv3x3, fp32, false)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(conv3x3, bf16, true)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK_CAPTURE(step, train_haptex_fp32, kHaptex, true, false)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(step, train_haptex_bf16, kHaptex, true, true)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(step, infer_haptex_fp32, kHaptex, false, false)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(step, infer_haptex_bf16, kHaptex, false, true)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(step, train_ns100_fp32, kNs100, true, false)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK_CAPTURE(step, train_ns100_bf16, kNs100, true, true)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
BENCHMARK_CAPTURE(step, infer_ns100_fp32, kNs100, false, false)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(10);
BENCHMARK_CAPTURE(step, infer_ns100_bf16, kNs100, false, true)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(10);

}  // namespace
