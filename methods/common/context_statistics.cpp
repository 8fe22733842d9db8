#include "methods/common/context_statistics.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "methods/common/module_state.h"
#include "core/random_draws.h"

namespace fscil {

torch::Tensor channel_statistics(const torch::Tensor& features) {
  const torch::Tensor flat = features.flatten(2);
  return torch::cat({flat.mean(2), flat.std(2)}, 1);
}

void ContextStatisticBank::push(const torch::Tensor& statistics) {
  const torch::Tensor rows = statistics.detach();
  if (!entries_.defined() || entries_.size(1) != rows.size(1)) {
    entries_ = torch::zeros({capacity_, rows.size(1)}, rows.options());
    count_ = next_ = 0;
  }
  for (std::int64_t i = 0; i < rows.size(0); ++i) {
    entries_[next_].copy_(rows[i]);
    next_ = (next_ + 1) % capacity_;
    count_ = std::min(count_ + 1, capacity_);
  }
}

torch::Tensor ContextStatisticBank::farthest_from(const torch::Tensor& statistics, std::int64_t rank,
                                                  bool standardised) const {
  TORCH_CHECK(count_ > 0, "the context statistic bank is empty");
  torch::Tensor queries = statistics.detach().view({-1, entries_.size(1)});
  torch::Tensor candidates = stored();
  if (standardised && count_ > 1) {
    const torch::Tensor scale = candidates.std(0, /*unbiased=*/true, /*keepdim=*/true).clamp_min(1e-6);
    queries = queries / scale;
    candidates = candidates / scale;
  }
  const std::int64_t k = std::min(rank, count_ - 1) + 1;
  const torch::Tensor ranked = std::get<1>(torch::cdist(queries, candidates).topk(k, 1));
  return stored().index_select(0, ranked.select(1, k - 1));
}

torch::Tensor ContextStatisticBank::random_entries(std::int64_t n, std::mt19937_64& generator) const {
  TORCH_CHECK(count_ > 0, "the context statistic bank is empty");
  std::vector<std::int64_t> picked(static_cast<std::size_t>(n));
  for (auto& index : picked) index = uniform_int(generator, 0, count_ - 1);
  return stored().index_select(0, torch::tensor(picked));
}

void ContextStatisticBank::save_into(MethodState& state, const std::string& prefix) const {
  state[prefix + "entries"] = entries_.defined() ? entries_.clone() : torch::zeros({0});
  state[prefix + "count"] = torch::tensor(count_);
  state[prefix + "next"] = torch::tensor(next_);
}

void ContextStatisticBank::restore_from(const MethodState& state, const std::string& prefix) {
  const torch::Tensor& entries = take(state, prefix + "entries");
  const std::int64_t count = take(state, prefix + "count").item<std::int64_t>();
  const std::int64_t next = take(state, prefix + "next").item<std::int64_t>();
  const bool empty = entries.dim() == 1 && entries.size(0) == 0;
  if ((empty && count != 0) || (!empty && (entries.dim() != 2 || entries.size(0) != capacity_)) || count < 0 ||
      count > capacity_ || next < 0 || next >= capacity_) {
    throw MethodError(fmt::format("{}: a context statistic bank of {} entries, expected one of capacity {}", prefix,
                                  count, capacity_));
  }
  entries_ = empty ? torch::Tensor() : entries.clone();
  count_ = count;
  next_ = next;
}

}  // namespace fscil
