#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>

namespace fscil {

// N samples of one kind (log-Mel features or raw signals), gathered by index when needed. The
// rows are either held in memory or made on request (the runner computes the features of a
// dataset too large to keep them from its raw signals, batch by batch); a method cannot tell
// which, and the same index always gives the same values.
class SampleRows {
 public:
  using Gather = std::function<torch::Tensor(const torch::Tensor& index)>;

  SampleRows() = default;
  // Rows held in memory; implicit, so any tensor of samples can stand where rows are expected.
  SampleRows(torch::Tensor rows);  // NOLINT(google-explicit-constructor)
  SampleRows(std::int64_t count, Gather gather);

  std::int64_t count() const { return count_; }
  // The rows at `index` (int64), in that order.
  torch::Tensor gather(const torch::Tensor& index) const;
  // Rows [first, first + size).
  torch::Tensor range(std::int64_t first, std::int64_t size) const;
  // Every row at once: for sets known to be small (a session's shots, a replay memory).
  torch::Tensor all() const;

 private:
  std::int64_t count_ = 0;
  torch::Tensor held_;
  Gather gather_;
};

// `transform` applied to consecutive batches of at most `batch_size` rows, results concatenated
// along the first dimension; bounds memory to one batch of rows at a time.
torch::Tensor map_batches(const SampleRows& rows, std::int64_t batch_size,
                          const std::function<torch::Tensor(const torch::Tensor&)>& transform);

}  // namespace fscil
