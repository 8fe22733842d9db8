#pragma once
#include <cstdint>
#include <vector>

namespace fscil {

// The paper's context-to-class dispersion ratio, measured with known contexts:
//   R(y) = max_{c != c'} |m(y,c) - m(y,c')| / min_{y' != y} |m(y) - m(y')|
// where m(y,c) is the mean embedding of class y's samples acquired in context c and m(y) the
// mean of all its samples. A class seen in a single context has no context dispersion: R = 0.
struct ContextDispersion {
  std::vector<double> ratio;  // per class, in order of first appearance of the label
  double mean = 0;
  double max = 0;
};

// embeddings: rows x dimension, row-major; labels and contexts per row (context ids are any
// integers naming distinct acquisition contexts). Needs at least two classes.
ContextDispersion measure_context_dispersion(const std::vector<float>& embeddings, std::int64_t dimension,
                                             const std::vector<std::int64_t>& labels, const std::vector<int>& contexts);

}  // namespace fscil
