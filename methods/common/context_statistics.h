#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>
#include <string>

#include "methods/method.h"

namespace fscil {

// The bank CoP-FSCIL's context probes draw references from, and PITS-SC records during its
// pretraining so that the two can share that stage (cop-fscil/cpi continues from it).
constexpr std::int64_t kContextBankCapacity = 1024;  // cpi_bank (ours)

// Per-sample, per-channel mean and standard deviation over the F x T plane: N x 2C ([mu; sigma]).
torch::Tensor channel_statistics(const torch::Tensor& features);

// The Context Statistic Bank: the most recent statistics seen (FIFO).
class ContextStatisticBank {
 public:
  explicit ContextStatisticBank(std::int64_t capacity = kContextBankCapacity) : capacity_(capacity) {}
  void push(const torch::Tensor& statistics);  // N x 2C
  std::int64_t size() const { return count_; }
  // Per row of `statistics` (N x 2C), the entry ranked `rank` by Euclidean distance d_ij, farthest
  // first (rank 0 = the farthest; clamped to the bank's size): N x 2C. With `standardised` each
  // of the 2C statistics is first divided by its standard deviation over the bank, so that no
  // channel's level dominates the distance.
  torch::Tensor farthest_from(const torch::Tensor& statistics, std::int64_t rank = 0, bool standardised = false) const;
  // N entries drawn uniformly.
  torch::Tensor random_entries(std::int64_t n, std::mt19937_64& generator) const;
  // Its contents into `state` under `prefix` (copies), and back; MethodError when they are missing
  // or do not fit its capacity.
  void save_into(MethodState& state, const std::string& prefix) const;
  void restore_from(const MethodState& state, const std::string& prefix);

 private:
  torch::Tensor stored() const { return entries_.narrow(0, 0, count_); }

  std::int64_t capacity_;
  torch::Tensor entries_;  // capacity x 2C ring; the first count_ rows are filled
  std::int64_t count_ = 0, next_ = 0;
};

}  // namespace fscil
