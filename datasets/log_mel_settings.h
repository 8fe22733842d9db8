#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace fscil {

enum class MelScale { htk, slaney };
enum class MelNorm { none, slaney };

// Parameters of the log-Mel front end; defaults follow torchaudio 0.13's MelSpectrogram.
struct LogMelSettings {
  // The filterbank holds (n_fft / 2 + 1) x n_mels weights: these bounds keep it under 2 GiB.
  static constexpr std::int64_t kMaxFftSize = std::int64_t{1} << 20;
  static constexpr std::int64_t kMaxMelBins = 1024;
  // 10 MHz is past any tactile or audio sensor.
  static constexpr double kMaxSampleRate = 1e7;

  double sample_rate = 16000;
  std::int64_t n_fft = 400;
  std::int64_t hop = 200;
  std::int64_t n_mels = 128;
  double f_min = 0;
  double f_max = 0;  // 0 = sample_rate / 2
  bool center = true;  // reflect-pad n_fft / 2 on both sides
  MelScale scale = MelScale::htk;
  MelNorm norm = MelNorm::none;

  std::int64_t frequency_bins() const { return n_fft / 2 + 1; }
  // Frames produced for a signal of `length` samples.
  std::int64_t frames(std::int64_t length) const;
  // Whether a signal of `length` samples gives a frame (and, centred, can be reflect-padded).
  bool takes(std::int64_t length) const { return frames(length) >= 1 && (!center || length > n_fft / 2); }
  // Canonical text naming every value, for cache keys and result files.
  std::string describe() const;
};

// The per-dataset presets of the paper's spectrogram table (PROTOCOLS.md).
LogMelSettings log_mel_preset(const std::string& name);
std::vector<std::string> log_mel_preset_names();

MelScale parse_mel_scale(const std::string& text);
MelNorm parse_mel_norm(const std::string& text);

}  // namespace fscil
