#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>

namespace fscil {

// Ranges of CPI's random view, in units of each sample's log-Mel standard deviation (ours: the
// paper's features are standardised, ours are dB, so we scale by the sample's own spread).
struct ViewRanges {
  double global_bias = 0.5;   // b_g ~ U(-a_g, a_g)
  double channel_bias = 0.3;  // b_ch ~ U(-a_ch, a_ch) per channel
  double tilt = 0.5;          // s ~ U(-a_s, a_s), times r_f = 2f/(F-1) - 1
  double noise = 0.1;         // eta ~ N(0, s_eta^2)
  double max_shift_fraction = 0.125;  // dt ~ U{-d, d} frames, d = fraction * T
};

// View(M) = Roll_dt(M + b_g + b_ch + s r_f + eta) on N x C x F x T, drawn per sample. The shift
// is padded, not circular: vacated frames repeat the edge frame (ours).
torch::Tensor random_view(const torch::Tensor& features, const ViewRanges& ranges, std::mt19937_64& generator);

// Per-sample, per-channel mean and standard deviation over the F x T plane: N x 2C ([mu; sigma]).
torch::Tensor channel_statistics(const torch::Tensor& features);

// The Context Statistic Bank: the most recent statistics seen (FIFO).
class ContextStatisticBank {
 public:
  explicit ContextStatisticBank(std::int64_t capacity = 1024) : capacity_(capacity) {}
  void push(const torch::Tensor& statistics);  // N x 2C
  std::int64_t size() const { return count_; }
  // Per row of `statistics` (N x 2C), the entry farthest from it (Euclidean): N x 2C.
  torch::Tensor farthest_from(const torch::Tensor& statistics) const;
  // N entries drawn uniformly.
  torch::Tensor random_entries(std::int64_t n, std::mt19937_64& generator) const;

 private:
  torch::Tensor stored() const { return entries_.narrow(0, 0, count_); }

  std::int64_t capacity_;
  torch::Tensor entries_;  // capacity x 2C ring; the first count_ rows are filled
  std::int64_t count_ = 0, next_ = 0;
};

enum class ReferenceChoice { farthest, random };

// Pseudo-context statistic transfer: each sample's channel statistics are mixed with a bank
// reference's, lambda ~ Beta(alpha, alpha), and the sample re-standardised onto them:
// sigma_mix * (M - mu) / sigma + mu_mix. Falls back to the batch itself when the bank is empty.
torch::Tensor transfer_statistics(const torch::Tensor& features, const ContextStatisticBank& bank,
                                  ReferenceChoice choice, double alpha, std::mt19937_64& generator);

struct ContextProbeSettings {
  ViewRanges view;
  ReferenceChoice reference = ReferenceChoice::farthest;
  double mix_alpha = 0.1;               // MixStyle's Beta(0.1, 0.1) (ours)
  std::int64_t bank_capacity = 1024;    // (ours)
};

// CPI as a whole: T_cp(M) = Mix(View(M)) with a bank of the statistics it has been shown.
class ContextProbe {
 public:
  explicit ContextProbe(const ContextProbeSettings& settings)
      : settings_(settings), bank_(settings.bank_capacity) {}
  // Probes of `features`, without gradient.
  torch::Tensor intervene(const torch::Tensor& features, std::mt19937_64& generator) const;
  // The statistics of real samples join the bank as future references.
  void observe(const torch::Tensor& features) { bank_.push(channel_statistics(features)); }
  torch::Tensor view(const torch::Tensor& features, std::mt19937_64& generator) const {
    return random_view(features, settings_.view, generator);
  }

 private:
  ContextProbeSettings settings_;
  ContextStatisticBank bank_;
};

}  // namespace fscil
