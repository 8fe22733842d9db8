#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>

#include "methods/common/context_statistics.h"

namespace fscil {

// Where CPI acts: after the encoder's per-Mel-bin input norm bn0, on the standardised map (as
// PITS-SC's released code applies its augmentations), or before it, on the dB log-Mel.
enum class ProbeSpace { standardised, raw };

// Ranges of CPI's random view: in standardised units after bn0; before it, in units of each
// sample's log-Mel standard deviation (dB maps have no common unit).
struct ViewRanges {
  double global_bias = 0.25;   // b_g ~ U(-a_g, a_g)
  double channel_bias = 0.15;  // b_ch ~ U(-a_ch, a_ch) per channel
  double tilt = 0.25;          // s ~ U(-a_s, a_s), times r_f = 2f/(F-1) - 1
  double noise = 0.05;         // eta ~ N(0, s_eta^2)
  double max_shift_fraction = 0.125;  // dt ~ U{-d, d} frames, d = fraction * T
};

// View(M) = Roll_dt(M + b_g + b_ch + s r_f + eta) on N x C x F x T, drawn per sample. The shift
// is padded, not circular: vacated frames repeat the edge frame (ours). With
// `in_sample_spread_units` the additive terms are scaled by each sample's standard deviation.
torch::Tensor random_view(const torch::Tensor& features, const ViewRanges& ranges, bool in_sample_spread_units,
                          std::mt19937_64& generator);

enum class ReferenceChoice { farthest, random };

struct ContextProbeSettings {
  ProbeSpace space = ProbeSpace::standardised;  // cpi_space
  ViewRanges view;
  ReferenceChoice reference = ReferenceChoice::farthest;  // cpi_reference
  bool standardised_distance = true;   // cpi_distance=standardised|raw
  bool ranked_references = true;       // cpi_references=ranked|same: probe n of a sample takes the n-th farthest
  double mix_alpha = 0.1;              // cpi_mix_alpha, MixStyle's Beta(0.1, 0.1) (ours)
  std::int64_t bank_capacity = kContextBankCapacity;  // cpi_bank (ours)
};

// Pseudo-context statistic transfer: each sample's channel statistics are mixed with a bank
// reference's (the `rank`-th farthest, or a random entry), lambda ~ Beta(alpha, alpha), and the
// sample re-standardised onto them: sigma_mix * (M - mu) / sigma + mu_mix. Falls back to the
// batch itself when the bank is empty.
torch::Tensor transfer_statistics(const torch::Tensor& features, const ContextStatisticBank& bank,
                                  const ContextProbeSettings& settings, std::int64_t rank, std::mt19937_64& generator);

// CPI as a whole: T_cp(M) = Mix(View(M)) with a bank of the statistics it has been shown.
class ContextProbe {
 public:
  explicit ContextProbe(const ContextProbeSettings& settings)
      : settings_(settings), bank_(settings.bank_capacity) {}
  // Probes of `features` (maps in settings().space), without gradient. `rank` picks the reference
  // when a sample gets several probes: probe n takes the n-th farthest (with ranked references).
  torch::Tensor intervene(const torch::Tensor& features, std::mt19937_64& generator, std::int64_t rank = 0) const;
  // The statistics of real samples join the bank as future references.
  void observe(const torch::Tensor& features) { bank_.push(channel_statistics(features)); }
  torch::Tensor view(const torch::Tensor& features, std::mt19937_64& generator) const {
    return random_view(features, settings_.view, settings_.space == ProbeSpace::raw, generator);
  }
  const ContextProbeSettings& settings() const { return settings_; }
  ContextStatisticBank& bank() { return bank_; }

 private:
  ContextProbeSettings settings_;
  ContextStatisticBank bank_;
};

}  // namespace fscil
