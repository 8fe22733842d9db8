#include "methods/sample_rows.h"

#include <algorithm>
#include <vector>

namespace fscil {

SampleRows::SampleRows(torch::Tensor rows) : count_(rows.defined() ? rows.size(0) : 0), held_(std::move(rows)) {}

SampleRows::SampleRows(std::int64_t count, Gather gather) : count_(count), gather_(std::move(gather)) {}

torch::Tensor SampleRows::gather(const torch::Tensor& index) const {
  return held_.defined() ? held_.index_select(0, index) : gather_(index);
}

torch::Tensor SampleRows::range(std::int64_t first, std::int64_t size) const {
  if (held_.defined()) return held_.narrow(0, first, size);
  return gather_(torch::arange(first, first + size, torch::kLong));
}

torch::Tensor SampleRows::all() const { return held_.defined() ? held_ : range(0, count_); }

torch::Tensor map_batches(const SampleRows& rows, std::int64_t batch_size,
                          const std::function<torch::Tensor(const torch::Tensor&)>& transform) {
  std::vector<torch::Tensor> parts;
  for (std::int64_t first = 0; first < rows.count(); first += batch_size) {
    parts.push_back(transform(rows.range(first, std::min(batch_size, rows.count() - first))));
  }
  return torch::cat(parts);
}

}  // namespace fscil
