#include "metrics/context_dispersion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace fscil {

namespace {

struct Mean {
  std::vector<double> sum;
  std::int64_t count = 0;
  void add(const float* row, std::int64_t dimension) {
    if (sum.empty()) sum.assign(dimension, 0.0);
    for (std::int64_t d = 0; d < dimension; ++d) sum[d] += row[d];
    ++count;
  }
  std::vector<double> value() const {
    std::vector<double> mean(sum);
    for (double& v : mean) v /= static_cast<double>(count);
    return mean;
  }
};

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double squares = 0;
  for (std::size_t d = 0; d < a.size(); ++d) squares += (a[d] - b[d]) * (a[d] - b[d]);
  return std::sqrt(squares);
}

}  // namespace

ContextDispersion measure_context_dispersion(const std::vector<float>& embeddings, std::int64_t dimension,
                                             const std::vector<std::int64_t>& labels, const std::vector<int>& contexts) {
  if (labels.size() != contexts.size() || static_cast<std::int64_t>(labels.size()) * dimension !=
                                              static_cast<std::int64_t>(embeddings.size())) {
    throw std::invalid_argument("embeddings, labels and contexts disagree in size");
  }
  std::vector<std::int64_t> classes;
  std::map<std::int64_t, Mean> class_means;
  std::map<std::int64_t, std::map<int, Mean>> context_means;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (class_means.count(labels[i]) == 0) classes.push_back(labels[i]);
    class_means[labels[i]].add(&embeddings[i * dimension], dimension);
    context_means[labels[i]][contexts[i]].add(&embeddings[i * dimension], dimension);
  }
  if (classes.size() < 2) throw std::invalid_argument("context dispersion needs at least two classes");

  std::map<std::int64_t, std::vector<double>> centres;
  for (const auto& [label, mean] : class_means) centres[label] = mean.value();
  ContextDispersion result;
  for (std::int64_t label : classes) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& [other, centre] : centres) {
      if (other != label) nearest = std::min(nearest, distance(centres[label], centre));
    }
    std::vector<std::vector<double>> per_context;
    for (const auto& [context, mean] : context_means[label]) per_context.push_back(mean.value());
    double widest = 0;
    for (std::size_t a = 0; a < per_context.size(); ++a) {
      for (std::size_t b = a + 1; b < per_context.size(); ++b) widest = std::max(widest, distance(per_context[a], per_context[b]));
    }
    result.ratio.push_back(nearest > 0 ? widest / nearest : std::numeric_limits<double>::infinity());
  }
  double sum = 0;
  for (double ratio : result.ratio) {
    sum += ratio;
    result.max = std::max(result.max, ratio);
  }
  result.mean = sum / static_cast<double>(result.ratio.size());
  return result;
}

}  // namespace fscil
