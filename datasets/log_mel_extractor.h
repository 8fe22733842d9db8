#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "datasets/float_array.h"
#include "datasets/log_mel_settings.h"
#include "datasets/mel_filterbank.h"

namespace fscil {

// Log-Mel spectrograms on FFTW3 (single precision), matching torchaudio 0.13's
// MelSpectrogram (periodic Hann window, power 2) followed by 10*log10(max(x, 1e-10)).
// Thread-safe for concurrent extract() calls once constructed.
class LogMelExtractor {
 public:
  explicit LogMelExtractor(const LogMelSettings& settings);
  ~LogMelExtractor();
  LogMelExtractor(const LogMelExtractor&) = delete;
  LogMelExtractor& operator=(const LogMelExtractor&) = delete;

  const LogMelSettings& settings() const { return settings_; }
  std::int64_t frames(std::int64_t length) const { return settings_.frames(length); }
  // Filters no FFT bin falls into; callers warn about them once (torchaudio warns too).
  std::int64_t empty_filters() const { return filterbank_.empty_filters(); }
  // Throws DatasetError when signals of `length` samples give no frame.
  void check_length(std::int64_t length) const;

  // signals: ... x L (any leading shape, e.g. N x C x L) -> ... x n_mels x frames.
  FloatArray extract(const FloatArray& signals, int threads = 0) const;
  // rows independent signals of `length` samples -> rows x n_mels x frames(length).
  void extract_rows(const float* signals, std::int64_t rows, std::int64_t length, float* out,
                    int threads = 0) const;

 private:
  // False, as soon as a row holds a non-finite sample (that row and the rest of the range unwritten).
  bool extract_range(const float* signals, std::int64_t first, std::int64_t last, std::int64_t length,
                     float* out) const;

  LogMelSettings settings_;
  MelFilterbank filterbank_;
  std::vector<float> window_;
  // Filter m's non-zero weights, bins first_bin[m] .. end_bin[m] - 1, from filter_offset_[m].
  std::vector<float> filter_weights_;
  std::vector<std::size_t> filter_offset_;
  struct Plan;
  std::unique_ptr<Plan> plan_;
};

}  // namespace fscil
