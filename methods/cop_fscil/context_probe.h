#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>

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

// Per-sample, per-channel mean and standard deviation over the F x T plane: N x 2C ([mu; sigma]).
torch::Tensor channel_statistics(const torch::Tensor& features);

// The Context Statistic Bank: the most recent statistics seen (FIFO).
class ContextStatisticBank {
 public:
  explicit ContextStatisticBank(std::int64_t capacity = 1024) : capacity_(capacity) {}
  void push(const torch::Tensor& statistics);  // N x 2C
  std::int64_t size() const { return count_; }
  // Per row of `statistics` (N x 2C), the entry ranked `rank` by Euclidean distance d_ij, farthest
  // first (rank 0 = the farthest; clamped to the bank's size): N x 2C. With `standardised` each
  // of the 2C statistics is first divided by its standard deviation over the bank, so that no
  // channel's level dominates the distance.
  torch::Tensor farthest_from(const torch::Tensor& statistics, std::int64_t rank = 0, bool standardised = false) const;
  // N entries drawn uniformly.
  torch::Tensor random_entries(std::int64_t n, std::mt19937_64& generator) const;

 private:
  torch::Tensor stored() const { return entries_.narrow(0, 0, count_); }

  std::int64_t capacity_;
  torch::Tensor entries_;  // capacity x 2C ring; the first count_ rows are filled
  std::int64_t count_ = 0, next_ = 0;
};

enum class ReferenceChoice { farthest, random };

struct ContextProbeSettings {
  ProbeSpace space = ProbeSpace::standardised;  // cpi_space
  ViewRanges view;
  ReferenceChoice reference = ReferenceChoice::farthest;  // cpi_reference
  bool standardised_distance = true;   // cpi_distance=standardised|raw
  bool ranked_references = true;       // cpi_references=ranked|same: probe n of a sample takes the n-th farthest
  double mix_alpha = 0.1;              // cpi_mix_alpha, MixStyle's Beta(0.1, 0.1) (ours)
  std::int64_t bank_capacity = 1024;   // cpi_bank (ours)
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

 private:
  ContextProbeSettings settings_;
  ContextStatisticBank bank_;
};

}  // namespace fscil
