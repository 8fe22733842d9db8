#include "metrics/context_dispersion.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fscil {
namespace {

TEST(ContextDispersion, MatchesTheRatioWorkedOutByHand) {
  // Class 0 in contexts 7 and 8: context means (0,0) and (2,0).
  // Class 1 in context 7 only, mean (1,4).  Class 2 in contexts 7 and 8: (4,0) and (6,1).
  const std::vector<float> embeddings = {0, 0, 0, 0, 2, 0,   // class 0: two samples in 7, one in 8
                                         1, 4, 1, 4,         // class 1
                                         4, 0, 6, 1};        // class 2
  const std::vector<std::int64_t> labels = {0, 0, 0, 1, 1, 2, 2};
  const std::vector<int> contexts = {7, 7, 8, 7, 7, 7, 8};
  const ContextDispersion result = measure_context_dispersion(embeddings, 2, labels, contexts);
  ASSERT_EQ(result.ratio.size(), 3u);
  // Class 0: mean is (2/3, 0); context spread |(0,0)-(2,0)| = 2.
  //   nearest class: class 1 at |(2/3,0)-(1,4)| = sqrt(1/9 + 16) = 4.0139, class 2 at |(2/3,0)-(5,.5)| = 4.3621.
  EXPECT_NEAR(result.ratio[0], 2.0 / std::sqrt(1.0 / 9 + 16), 1e-12);
  // Class 1: one context only, so no context dispersion.
  EXPECT_DOUBLE_EQ(result.ratio[1], 0.0);
  // Class 2: spread |(4,0)-(6,1)| = sqrt(5); nearest |(5,.5)-(1,4)| = sqrt(16+12.25), |(5,.5)-(2/3,0)| = 4.3621.
  const double nearest = std::min(std::sqrt(16 + 12.25), std::sqrt(std::pow(5 - 2.0 / 3, 2) + 0.25));
  EXPECT_NEAR(result.ratio[2], std::sqrt(5.0) / nearest, 1e-12);
  EXPECT_NEAR(result.mean, (result.ratio[0] + result.ratio[2]) / 3, 1e-12);
  EXPECT_DOUBLE_EQ(result.max, std::max(result.ratio[0], result.ratio[2]));
}

TEST(ContextDispersion, RejectsInconsistentInput) {
  EXPECT_THROW(measure_context_dispersion({0, 0}, 2, {0}, {1, 2}), std::invalid_argument);
  EXPECT_THROW(measure_context_dispersion({0, 0}, 2, {0}, {1}), std::invalid_argument);
}

}  // namespace
}  // namespace fscil
