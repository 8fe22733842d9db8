#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <deque>
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
  explicit ContextStatisticBank(std::size_t capacity = 1024) : capacity_(capacity) {}
  void push(const torch::Tensor& statistics);  // N x 2C
  std::size_t size() const { return entries_.size(); }
  // The entry farthest (Euclidean) from `statistics` (2C), or a uniformly random one.
  torch::Tensor farthest_from(const torch::Tensor& statistics) const;
  torch::Tensor random_entry(std::mt19937_64& generator) const;

 private:
  std::size_t capacity_;
  std::deque<torch::Tensor> entries_;
};

enum class ReferenceChoice { farthest, random };

// Pseudo-context statistic transfer: each sample's channel statistics are mixed with a bank
// reference's, lambda ~ Beta(alpha, alpha), and the sample re-standardised onto them:
// sigma_mix * (M - mu) / sigma + mu_mix. Falls back to the batch itself when the bank is empty.
torch::Tensor transfer_statistics(const torch::Tensor& features, const ContextStatisticBank& bank,
                                  ReferenceChoice choice, double alpha, std::mt19937_64& generator);

}  // namespace fscil
