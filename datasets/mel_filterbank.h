#pragma once
#include <cstdint>
#include <vector>

#include "datasets/log_mel_settings.h"

namespace fscil {

double hz_to_mel(double hz, MelScale scale);
double mel_to_hz(double mel, MelScale scale);

// Triangular Mel filters as torchaudio's melscale_fbanks builds them:
// frequency_bins x n_mels, row-major.
struct MelFilterbank {
  std::int64_t frequency_bins = 0;
  std::int64_t n_mels = 0;
  std::vector<double> weights;

  static MelFilterbank build(const LogMelSettings& settings);
  // Filters that no FFT bin reaches (all-zero columns).
  std::int64_t empty_filters() const;
  // First and one-past-last non-zero row of each filter, to skip zeros when applying.
  std::vector<std::int64_t> first_bin, end_bin;
};

}  // namespace fscil
