#include "core/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace fscil {
namespace {

TEST(NumberText, ReadsTheWholeTextAsADecimalNumber) {
  EXPECT_EQ(parse_number<double>("0.25"), 0.25);
  EXPECT_EQ(parse_number<double>("-1.5e3"), -1500.0);
  EXPECT_EQ(parse_number<double>("+2"), 2.0);
  EXPECT_EQ(parse_number<std::int64_t>("-9223372036854775808"), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(parse_number<int>("+7"), 7);
  EXPECT_EQ(parse_number<std::uint64_t>("18446744073709551615"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(parse_number<float>("0.1"), 0.1f);  // read as a float, not a double rounded twice
}

TEST(NumberText, RefusesAnythingElse) {
  for (const char* text : {"", " 1", "1 ", "1x", "0x10", "1,5", "+", "+-1", "--1", "e5", "1e", "١"}) {
    EXPECT_FALSE(parse_number<double>(text)) << text;
    EXPECT_FALSE(parse_number<std::int64_t>(text)) << text;
  }
  EXPECT_FALSE(parse_number<int>("2147483648"));
  EXPECT_FALSE(parse_number<int>("1.0"));
  EXPECT_FALSE(parse_number<std::uint64_t>("-1"));
  EXPECT_FALSE(parse_number<std::uint64_t>("-0"));
  EXPECT_FALSE(parse_number<double>("1e400"));
}

TEST(NumberText, ReadsWhatCheckpointsWriteForADivergedLossAndSubnormals) {
  EXPECT_TRUE(std::isnan(*parse_number<double>("nan")));
  EXPECT_TRUE(std::isnan(*parse_number<double>("-nan")));
  EXPECT_EQ(parse_number<double>("-inf"), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(parse_number<double>("4.9406564584124654e-324"), std::numeric_limits<double>::denorm_min());
  EXPECT_FALSE(parse_finite_number("inf"));
  EXPECT_FALSE(parse_finite_number("nan"));
  EXPECT_EQ(parse_finite_number("3"), 3.0);
}

}  // namespace
}  // namespace fscil
