// Where a training step of the shared ResNet-18 spends its time, on one input shape: LibTorch's
// profiler over a few steps (after warm-up), each operator's self time (its time less that of
// the operators it called) summed per operator and input shape, so the rows say which kernel
// and, by the shape (channels and map), which stage. The counterpart for PyTorch from Python is
// pytorch_step_profile.py: same model, batch, optimiser and threads.
//
//   resnet18_step_profile CHANNELS MEL_BINS FRAMES [STEPS] [ROWS]
#include <fmt/format.h>
#include <torch/csrc/autograd/profiler_legacy.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/number_text.h"
#include "methods/common/encoder_step.h"
#include "metrics/resource_usage.h"

namespace {

namespace profiler = torch::autograd::profiler;

constexpr std::int64_t kBatch = 128;

struct Row {
  double self_us = 0;
  std::int64_t calls = 0;
};

std::string shape_text(const std::vector<std::vector<std::int64_t>>& shapes) {
  // The first input's shape locates an operator in the network; the rest would split rows of one kernel.
  if (shapes.empty() || shapes.front().empty()) return "";
  return fmt::format("[{}]", fmt::join(shapes.front(), ", "));
}

// Self time per operator and input shape from each thread's push/pop events.
std::map<std::pair<std::string, std::string>, Row> self_times(const profiler::thread_event_lists& threads) {
  std::map<std::pair<std::string, std::string>, Row> rows;
  struct Open {
    const profiler::LegacyEvent* push;
    double children_us = 0;
  };
  for (const auto& events : threads) {
    std::vector<Open> open;
    for (const auto& event : events) {
      if (event.kind() == profiler::EventKind::PushRange) {
        open.push_back({&event});
      } else if (event.kind() == profiler::EventKind::PopRange && !open.empty()) {
        const Open closed = open.back();
        open.pop_back();
        const double inclusive = closed.push->cpuElapsedUs(event);
        Row& row = rows[{closed.push->name(), shape_text(closed.push->shapes())}];
        row.self_us += inclusive - closed.children_us;
        ++row.calls;
        if (!open.empty()) open.back().children_us += inclusive;
      }
    }
  }
  return rows;
}

// argv[index] as a whole number of at least `least`, or `fallback` when absent; nullopt when it does not read.
std::optional<std::int64_t> argument(int argc, char** argv, int index, std::int64_t least, std::int64_t fallback) {
  if (index >= argc) return fallback;
  const auto value = fscil::parse_number<std::int64_t>(argv[index]);
  if (!value || *value < least) return std::nullopt;
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  const auto channels = argument(argc, argv, 1, 1, 0), mel_bins = argument(argc, argv, 2, 8, 0),
             frames = argument(argc, argv, 3, 8, 0), steps = argument(argc, argv, 4, 1, 3),
             shown = argument(argc, argv, 5, 1, 30);
  if (argc < 4 || argc > 6 || !channels || !mel_bins || !frames || !steps || !shown) {
    fmt::print(stderr, "resnet18_step_profile: expected CHANNELS MEL_BINS FRAMES [STEPS] [ROWS], whole numbers: "
                       "CHANNELS, STEPS and ROWS >= 1, MEL_BINS and FRAMES >= 8\n");
    return 2;
  }
  // As the benchmarks run (torch_benchmark_main.cpp): every core, freed memory kept for reuse.
  fscil::keep_freed_memory_for_reuse();
  torch::set_num_threads(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  torch::manual_seed(1);
  fscil::EncoderStep work(*channels, *mel_bins, *frames, kBatch);
  work.train();
  work.train();  // warm-up: first-touch page faults and oneDNN's kernel generation are not the step

  const auto unprofiled_start = std::chrono::steady_clock::now();
  for (std::int64_t step = 0; step < *steps; ++step) work.train();
  const double unprofiled_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - unprofiled_start).count() /
      static_cast<double>(*steps);

  profiler::enableProfilerLegacy(torch::profiler::impl::ProfilerConfig(torch::profiler::impl::ProfilerState::CPU,
                                                                       /*report_input_shapes=*/true));
  for (std::int64_t step = 0; step < *steps; ++step) work.train();
  const auto rows = self_times(profiler::disableProfilerLegacy());

  std::vector<std::pair<std::pair<std::string, std::string>, Row>> sorted(rows.begin(), rows.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second.self_us > b.second.self_us; });
  double total_us = 0;
  std::map<std::string, double> per_operator;
  for (const auto& [key, row] : sorted) {
    total_us += row.self_us;
    per_operator[key.first] += row.self_us;
  }
  fmt::print("training step {}x{}x{}, batch {}, {} threads: {:.1f} ms unprofiled, {:.1f} ms of operators profiled "
             "(the shares below are of these)\n",
             *channels, *mel_bins, *frames, kBatch, torch::get_num_threads(), unprofiled_ms,
             total_us / 1000 / static_cast<double>(*steps));
  fmt::print("\n{:>9} {:>6} {:>6}  {:<48} {}\n", "ms/step", "share", "calls", "operator", "first input");
  for (std::size_t i = 0; i < std::min<std::size_t>(*shown, sorted.size()); ++i) {
    const auto& [key, row] = sorted[i];
    fmt::print("{:9.2f} {:5.1f}% {:6}  {:<48} {}\n", row.self_us / 1000 / static_cast<double>(*steps),
               100 * row.self_us / total_us, row.calls / *steps, key.first, key.second);
  }
  std::vector<std::pair<std::string, double>> operators(per_operator.begin(), per_operator.end());
  std::sort(operators.begin(), operators.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  fmt::print("\n{:>9} {:>6}  {}\n", "ms/step", "share", "operator (all shapes)");
  for (std::size_t i = 0; i < std::min<std::size_t>(*shown, operators.size()); ++i) {
    fmt::print("{:9.2f} {:5.1f}%  {}\n", operators[i].second / 1000 / static_cast<double>(*steps),
               100 * operators[i].second / total_us, operators[i].first);
  }
  return 0;
}
