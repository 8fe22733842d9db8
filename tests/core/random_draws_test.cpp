#include "core/random_draws.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <vector>

#include "core/error.h"
#include "core/seeded_shuffle.h"

// The golden values below were computed once with these functions and cross-checked against an
// independent Python implementation of MT19937-64 (from Matsumoto and Nishimura's reference code)
// and of each algorithm. Results that go through log, sqrt or pow are compared to 4 ulps, so that
// another libm's last-bit rounding is not mistaken for a change of algorithm.

namespace fscil {
namespace {

struct Moments {
  double mean = 0, variance = 0;
};

template <typename Draw>
Moments moments_of(Draw draw, int count = 200000) {
  double sum = 0, squares = 0;
  for (int i = 0; i < count; ++i) {
    const double x = draw();
    sum += x;
    squares += x * x;
  }
  const double mean = sum / count;
  return {mean, squares / count - mean * mean};
}

TEST(RandomDraws, TheEngineIsTheStandardsMt19937_64) {
  std::mt19937_64 standard_default;
  standard_default.discard(9999);
  EXPECT_EQ(standard_default(), 9981545732273789042ULL);  // required of the 10000th output by [rand.predef]
  std::mt19937_64 generator(42);
  for (std::uint64_t expected : {13930160852258120406ULL, 11788048577503494824ULL, 13874630024467741450ULL,
                                 2513787319205155662ULL}) {
    EXPECT_EQ(generator(), expected);
  }
}

TEST(RandomDraws, UniformRealIsTheTop53BitsOfOneOutputScaledIntoTheRange) {
  std::mt19937_64 raw(42), generator(42), shifted(42);
  for (double expected : {0.75515553295453897, 0.63903139385469743, 0.7521452007480266, 0.13627268363243705}) {
    const double by_hand = static_cast<double>(raw() >> 11) / 9007199254740992.0;  // 2^53
    EXPECT_EQ(by_hand, expected);
    EXPECT_EQ(uniform_real(generator, 0, 1), expected);
  }
  for (double expected : {1.7757776647726948, 1.1951569692734871, 1.7607260037401331, -1.3186365818378147}) {
    EXPECT_EQ(uniform_real(shifted, -2, 3), expected);
  }
}

TEST(RandomDraws, UniformRealNeverReturnsTheUpperEndEvenWhereRoundingWouldReachIt) {
  std::mt19937_64 generator(1);
  const double low = 1.0, high = std::nextafter(1.0, 2.0);  // low + (high - low) * u rounds up to high half the time
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(uniform_real(generator, low, high), low);
}

TEST(RandomDraws, UniformIndexIsTheOutputModuloNAndRedrawsOutputsBelowTwoToThe64ModN) {
  std::mt19937_64 raw(42), generator(42);
  for (std::uint64_t expected : {6, 4, 0, 2, 1, 8}) {
    EXPECT_EQ(raw() % 10, expected);  // 2^64 mod 10 = 6: none of these outputs is redrawn
    EXPECT_EQ(uniform_index(generator, 10), expected);
  }

  // n = 2^63 + 1 redraws outputs below 2^64 mod n = 2^63 - 1, about half of them.
  const std::uint64_t n = (std::uint64_t{1} << 63) + 1, rejected_below = (std::uint64_t{1} << 63) - 1;
  std::mt19937_64 outputs_of(42), big(42);
  std::vector<std::uint64_t> outputs(5);
  for (auto& output : outputs) output = outputs_of();
  ASSERT_LT(outputs[3], rejected_below);
  for (std::size_t kept : {0, 1, 2, 4}) {
    ASSERT_GE(outputs[kept], rejected_below);
    EXPECT_EQ(uniform_index(big, n), outputs[kept] % n);
  }
  for (int i = 0; i < 10000; ++i) ASSERT_LT(uniform_index(big, n), n);
}

TEST(RandomDraws, UniformIndexOverThreeIsUniform) {
  std::mt19937_64 generator(7);
  const int draws = 300000;
  std::vector<int> counts(3, 0);
  for (int i = 0; i < draws; ++i) ++counts.at(uniform_index(generator, 3));
  for (int count : counts) EXPECT_NEAR(count, draws / 3, 1500);  // about 6 standard deviations
}

TEST(RandomDraws, UniformIntIncludesBothEnds) {
  std::mt19937_64 generator(42);
  for (std::int64_t expected : {3, 0, 2, 1, 3, 3}) EXPECT_EQ(uniform_int(generator, -3, 3), expected);
  std::set<std::int64_t> seen;
  for (int i = 0; i < 10000; ++i) seen.insert(uniform_int(generator, -2, 2));
  EXPECT_EQ(seen, (std::set<std::int64_t>{-2, -1, 0, 1, 2}));
  EXPECT_EQ(uniform_int(generator, 5, 5), 5);
  const auto lowest = std::numeric_limits<std::int64_t>::min(), highest = std::numeric_limits<std::int64_t>::max();
  std::mt19937_64 raw(generator);
  const std::int64_t anything = uniform_int(generator, lowest, highest);
  EXPECT_EQ(static_cast<std::uint64_t>(anything) - static_cast<std::uint64_t>(lowest), raw());  // lowest + one output
}

TEST(RandomDraws, NormalPinsItsFirstDrawsAndHasTheNormalsMoments) {
  std::mt19937_64 standard(42), shifted(42);
  for (double expected : {1.2938204232729367, 0.39797739618378869, 1.1185550524574781, -1.4922470037224238}) {
    EXPECT_DOUBLE_EQ(normal(standard, 0, 1), expected);
  }
  for (double expected : {7.5876408465458738, 5.7959547923675778, 7.2371101049149562, 2.0155059925551524}) {
    EXPECT_DOUBLE_EQ(normal(shifted, 5, 2), expected);
  }
  const Moments moments = moments_of([&] { return normal(standard, 5, 2); });
  EXPECT_NEAR(moments.mean, 5.0, 0.02);
  EXPECT_NEAR(moments.variance, 4.0, 0.06);
}

TEST(RandomDraws, NormalKeepsNothingBetweenCalls) {
  std::mt19937_64 generator(3);
  normal(generator, 0, 1);  // the polar method made a pair: its second value must not be served next
  std::mt19937_64 same_state(generator);
  EXPECT_EQ(normal(generator, 0, 1), normal(same_state, 0, 1));
}

TEST(RandomDraws, GammaPinsItsFirstDrawsAndHasTheGammasMomentsAboveAndBelowShapeOne) {
  std::mt19937_64 above(42), below(42);
  for (double expected : {9.3672097749246603, 2.2596658388087247, 1.2575896015113193, 5.1179431438643359}) {
    EXPECT_DOUBLE_EQ(gamma(above, 2.5, 2), expected);
  }
  for (double expected : {0.059358077235739284, 0.43254714448722009, 0.35091325156811914, 0.016157051301031105}) {
    EXPECT_DOUBLE_EQ(gamma(below, 0.5, 1), expected);
  }
  const Moments shape_above_one = moments_of([&] { return gamma(above, 2.5, 2); });  // mean 5, variance 10
  EXPECT_NEAR(shape_above_one.mean, 5.0, 0.04);
  EXPECT_NEAR(shape_above_one.variance, 10.0, 0.25);
  const Moments shape_below_one = moments_of([&] { return gamma(below, 0.5, 1); });  // mean 0.5, variance 0.5
  EXPECT_NEAR(shape_below_one.mean, 0.5, 0.01);
  EXPECT_NEAR(shape_below_one.variance, 0.5, 0.025);
}

TEST(RandomDraws, BetaPinsItsFirstDrawsAndHasTheBetasMoments) {
  std::mt19937_64 generator(42);
  for (double expected : {0.068353650652172887, 0.24537757397475107, 0.048583074966653789, 0.24602383055294219}) {
    EXPECT_DOUBLE_EQ(beta(generator, 0.8, 2.4), expected);
  }
  const Moments moments = moments_of([&] { return beta(generator, 0.8, 2.4); });
  EXPECT_NEAR(moments.mean, 0.25, 0.003);
  EXPECT_NEAR(moments.variance, 0.8 * 2.4 / (3.2 * 3.2 * 4.2), 0.002);
}

TEST(RandomDraws, BernoulliIsAUniformBelowP) {
  std::mt19937_64 generator(42);
  for (bool expected : {false, false, false, true, false, true, false, false}) {
    EXPECT_EQ(bernoulli(generator, 0.3), expected);
  }
  int never = 0, always = 0, often = 0;
  for (int i = 0; i < 100000; ++i) {
    never += bernoulli(generator, 0.0);
    always += bernoulli(generator, 1.0);
    often += bernoulli(generator, 0.3);
  }
  EXPECT_EQ(never, 0);
  EXPECT_EQ(always, 100000);
  EXPECT_NEAR(often, 30000, 900);  // about 6 standard deviations
}

TEST(RandomDraws, ShuffleWithIsFisherYatesOverUniformIndex) {
  std::mt19937_64 generator(42);
  std::vector<int> values(10);
  std::iota(values.begin(), values.end(), 0);
  shuffle_with(values, generator);
  EXPECT_EQ(values, (std::vector<int>{1, 7, 9, 0, 3, 8, 4, 2, 5, 6}));
}

TEST(RandomDraws, BadArgumentsThrowProtocolError) {
  std::mt19937_64 generator(1);
  const double infinity = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(uniform_real(generator, 1, 0), ProtocolError);
  EXPECT_THROW(uniform_real(generator, 0, infinity), ProtocolError);
  EXPECT_THROW(uniform_index(generator, 0), ProtocolError);
  EXPECT_THROW(uniform_int(generator, 2, 1), ProtocolError);
  EXPECT_THROW(normal(generator, 0, -1), ProtocolError);
  EXPECT_THROW(normal(generator, 0, nan), ProtocolError);
  EXPECT_THROW(gamma(generator, 0, 1), ProtocolError);
  EXPECT_THROW(gamma(generator, -1, 1), ProtocolError);
  EXPECT_THROW(gamma(generator, 1, 0), ProtocolError);
  EXPECT_THROW(beta(generator, 0, 1), ProtocolError);
  EXPECT_THROW(bernoulli(generator, 1.5), ProtocolError);
  EXPECT_THROW(bernoulli(generator, nan), ProtocolError);
}

}  // namespace
}  // namespace fscil
