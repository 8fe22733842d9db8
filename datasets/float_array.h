#pragma once
#include <cstdint>
#include <functional>
#include <numeric>
#include <vector>

namespace fscil {

// A dense row-major float array with its shape; the torch-free currency of datasets/.
struct FloatArray {
  std::vector<std::int64_t> shape;
  std::vector<float> values;

  FloatArray() = default;
  explicit FloatArray(std::vector<std::int64_t> dims)
      : shape(std::move(dims)), values(static_cast<std::size_t>(element_count(shape))) {}

  static std::int64_t element_count(const std::vector<std::int64_t>& dims) {
    return std::accumulate(dims.begin(), dims.end(), std::int64_t{1}, std::multiplies<>());
  }
  std::int64_t size() const { return static_cast<std::int64_t>(values.size()); }
  // Elements in one entry of the leading dimension.
  std::int64_t row_size() const {
    return shape.empty() ? 0 : element_count({shape.begin() + 1, shape.end()});
  }
  float* row(std::int64_t index) { return values.data() + index * row_size(); }
  const float* row(std::int64_t index) const { return values.data() + index * row_size(); }
};

}  // namespace fscil
