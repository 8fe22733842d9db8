#include "tools/fscil-bench/options/seed_list.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace fscil {
namespace {

TEST(SeedList, AcceptsListsAndRanges) {
  EXPECT_EQ(parse_seed_list("1"), (std::vector<std::uint64_t>{1}));
  EXPECT_EQ(parse_seed_list("1,2,3"), (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(parse_seed_list("1-5"), (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(parse_seed_list("7,2-3"), (std::vector<std::uint64_t>{7, 2, 3}));
}

TEST(SeedList, RejectsGarbage) {
  for (const char* bad : {"", "a", "1,,2", "1,", "-3", "5-2", "1.5", "1;2", "2,2", "99999999999999999999"}) {
    EXPECT_THROW(parse_seed_list(bad), CliError) << bad;
  }
}

}  // namespace
}  // namespace fscil
