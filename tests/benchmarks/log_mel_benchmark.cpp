// The log-Mel front end against torchaudio on the same work in the same run, per preset: a batch
// of random segments (the preset's channels and length) to log-Mel features. Two references:
// torchaudio 0.13's MelSpectrogram + AmplitudeToDB from Python (pytorch_anchors.py, earlier in
// the same `bench` run), and the same pipeline written here with the LibTorch operators it calls
// (stft with a periodic Hann window, |.|^2, a matrix product with the filterbank,
// 10 log10(max(x, 1e-10))), which also gives the largest difference in dB from ours.
// One line per preset: segments/s of each, the speed-ups and that difference.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <torch/torch.h>

#include <chrono>

#include "datasets/log_mel_extractor.h"
#include "tests/benchmarks/pytorch_anchors.h"

namespace {

struct Preset {
  const char* name;
  std::int64_t channels, length;
};

constexpr std::int64_t kSegments = 64;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

torch::Tensor torchaudio_log_mel(const torch::Tensor& signals, const fscil::LogMelSettings& settings,
                                 const torch::Tensor& filterbank, const torch::Tensor& window) {
  const torch::Tensor flat = signals.reshape({-1, signals.size(-1)});
  const torch::Tensor spectrum = torch::stft(flat, settings.n_fft, settings.hop, settings.n_fft, window,
                                             settings.center, "reflect", false, true, true);
  const torch::Tensor power = spectrum.abs().pow(2);  // rows x bins x frames
  const torch::Tensor mel = torch::matmul(power.transpose(1, 2), filterbank).transpose(1, 2);
  return 10.0 * torch::log10(mel.clamp_min(1e-10)).view({signals.size(0), signals.size(1), settings.n_mels, -1});
}

void log_mel(benchmark::State& state, Preset preset) {
  const fscil::LogMelSettings settings = fscil::log_mel_preset(preset.name);
  const fscil::LogMelExtractor extractor(settings);
  const fscil::MelFilterbank bank = fscil::MelFilterbank::build(settings);
  const torch::Tensor filterbank =
      torch::tensor(bank.weights, torch::kDouble).view({bank.frequency_bins, bank.n_mels}).to(torch::kFloat);
  const torch::Tensor window = torch::hann_window(settings.n_fft, torch::TensorOptions().dtype(torch::kFloat));
  torch::manual_seed(1);
  const torch::Tensor signals = torch::randn({kSegments, preset.channels, preset.length});
  fscil::FloatArray input(signals.sizes().vec());
  std::copy(signals.data_ptr<float>(), signals.data_ptr<float>() + signals.numel(), input.values.begin());
  const int threads = torch::get_num_threads();

  fscil::FloatArray ours;
  double ours_seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    ours = extractor.extract(input, threads);
    ours_seconds += seconds_since(start);
  }
  // torchaudio's pipeline afterwards, as many times: interleaving the two would leave torch's
  // OpenMP workers spinning through our timings.
  torch::Tensor reference;
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t i = 0; i < state.iterations(); ++i) reference = torchaudio_log_mel(signals, settings, filterbank, window);
  const double torch_seconds = seconds_since(start);
  const double segments = static_cast<double>(kSegments * state.iterations());
  const double ours_rate = segments / ours_seconds, torch_rate = segments / torch_seconds;
  const torch::Tensor ours_tensor = torch::from_blob(ours.values.data(), ours.shape, torch::kFloat);
  const double max_db = (ours_tensor - reference).abs().max().item<double>();
  const std::optional<double> python_rate = fscil::pytorch_rate(fmt::format("log_mel/{}", preset.name));
  state.counters["ours_seg_per_s"] = ours_rate;
  state.counters["torchaudio_ops_seg_per_s"] = torch_rate;
  state.counters["x_vs_ops"] = ours_rate / torch_rate;
  if (python_rate) {
    state.counters["torchaudio_python_seg_per_s"] = *python_rate;
    state.counters["x_vs_python"] = ours_rate / *python_rate;
  }
  state.counters["max_diff_dB"] = max_db;
  // Against the slower of the two would flatter us; the target holds against the faster.
  const double faster = python_rate ? std::max(torch_rate, *python_rate) : torch_rate;
  const char* whose = python_rate ? "torchaudio" : "torchaudio's operators (no Python rate)";
  state.SetLabel(fmt::format("{}; within 0.01 dB: {}", fscil::anchor_label(ours_rate, faster, 4, whose),
                             max_db <= 0.01 ? "met" : "MISSED"));
}

BENCHMARK_CAPTURE(log_mel, haptex, Preset{"haptex", 5, 500})->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(log_mel, lmt108, Preset{"lmt108", 3, 8000})->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(log_mel, ls100, Preset{"ls100", 3, 32000})->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(log_mel, ns100, Preset{"ns100", 3, 64000})->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
