#include "datasets/mel_filterbank.h"

#include <algorithm>
#include <cmath>

namespace fscil {

namespace {
// Slaney's scale is linear below 1 kHz (200/3 Hz per Mel) and logarithmic above.
constexpr double kSlaneyHzPerMel = 200.0 / 3.0;
constexpr double kSlaneyBreakHz = 1000.0;
constexpr double kSlaneyBreakMel = kSlaneyBreakHz / kSlaneyHzPerMel;
const double kSlaneyLogStep = std::log(6.4) / 27.0;
}  // namespace

double hz_to_mel(double hz, MelScale scale) {
  if (scale == MelScale::htk) return 2595.0 * std::log10(1.0 + hz / 700.0);
  if (hz < kSlaneyBreakHz) return hz / kSlaneyHzPerMel;
  return kSlaneyBreakMel + std::log(hz / kSlaneyBreakHz) / kSlaneyLogStep;
}

double mel_to_hz(double mel, MelScale scale) {
  if (scale == MelScale::htk) return 700.0 * (std::pow(10.0, mel / 2595.0) - 1.0);
  if (mel < kSlaneyBreakMel) return mel * kSlaneyHzPerMel;
  return kSlaneyBreakHz * std::exp(kSlaneyLogStep * (mel - kSlaneyBreakMel));
}

MelFilterbank MelFilterbank::build(const LogMelSettings& settings) {
  MelFilterbank bank;
  bank.frequency_bins = settings.frequency_bins();
  bank.n_mels = settings.n_mels;
  bank.weights.assign(bank.frequency_bins * bank.n_mels, 0.0);
  const double f_max = settings.f_max > 0 ? settings.f_max : settings.sample_rate / 2;

  // torchaudio spaces the bin frequencies up to floor(sample_rate / 2).
  const double top = std::floor(settings.sample_rate / 2);
  std::vector<double> bin_hz(bank.frequency_bins);
  for (std::int64_t k = 0; k < bank.frequency_bins; ++k) {
    bin_hz[k] = bank.frequency_bins == 1 ? 0 : top * k / static_cast<double>(bank.frequency_bins - 1);
  }
  const double mel_low = hz_to_mel(settings.f_min, settings.scale);
  const double mel_high = hz_to_mel(f_max, settings.scale);
  std::vector<double> edge_hz(bank.n_mels + 2);
  for (std::int64_t m = 0; m < bank.n_mels + 2; ++m) {
    edge_hz[m] = mel_to_hz(mel_low + (mel_high - mel_low) * m / static_cast<double>(bank.n_mels + 1),
                           settings.scale);
  }

  for (std::int64_t m = 0; m < bank.n_mels; ++m) {
    const double left = edge_hz[m], centre = edge_hz[m + 1], right = edge_hz[m + 2];
    const double area_norm = settings.norm == MelNorm::slaney ? 2.0 / (right - left) : 1.0;
    for (std::int64_t k = 0; k < bank.frequency_bins; ++k) {
      const double rising = (bin_hz[k] - left) / (centre - left);
      const double falling = (right - bin_hz[k]) / (right - centre);
      const double weight = std::max(0.0, std::min(rising, falling));
      bank.weights[k * bank.n_mels + m] = weight * area_norm;
    }
  }

  bank.first_bin.assign(bank.n_mels, 0);
  bank.end_bin.assign(bank.n_mels, 0);
  for (std::int64_t m = 0; m < bank.n_mels; ++m) {
    std::int64_t first = bank.frequency_bins, end = 0;
    for (std::int64_t k = 0; k < bank.frequency_bins; ++k) {
      if (bank.weights[k * bank.n_mels + m] != 0.0) {
        first = std::min(first, k);
        end = k + 1;
      }
    }
    bank.first_bin[m] = first < end ? first : 0;
    bank.end_bin[m] = end;
  }
  return bank;
}

std::int64_t MelFilterbank::empty_filters() const {
  std::int64_t empty = 0;
  for (std::int64_t m = 0; m < n_mels; ++m) empty += end_bin[m] == 0 ? 1 : 0;
  return empty;
}

}  // namespace fscil
