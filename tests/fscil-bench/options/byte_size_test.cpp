#include "tools/fscil-bench/options/byte_size.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace fscil {
namespace {

TEST(ByteSize, ReadsBinaryUnits) {
  EXPECT_EQ(parse_byte_size("4294967296", "--max-memory"), 4294967296);
  EXPECT_EQ(parse_byte_size("4G", "--max-memory"), 4294967296);
  EXPECT_EQ(parse_byte_size("4GiB", "--max-memory"), 4294967296);
  EXPECT_EQ(parse_byte_size("4gb", "--max-memory"), 4294967296);
  EXPECT_EQ(parse_byte_size("512M", "--max-memory"), 536870912);
  EXPECT_EQ(parse_byte_size("1.5K", "--max-memory"), 1536);
  EXPECT_EQ(parse_byte_size("4Gi", "--max-memory"), 4294967296);
  EXPECT_EQ(parse_byte_size("4096B", "--max-memory"), 4096);
  EXPECT_EQ(parse_byte_size("1T", "--max-memory"), 1099511627776);
  EXPECT_EQ(parse_byte_size("1024T", "--max-memory"), 1125899906842624);
}

TEST(ByteSize, RefusesNonsenseWithTheOptionNamed) {
  for (const char* bad : {"", "G", "0", "0.0001", "-1G", "4X", "4 G", "4GG", "4Gx", ".5G", "5.G", "1.2.3M", "nan",
                          "inf", "1P", "1025T", "1e9", "4G\n", "1.5", "1.5B", "4Gib!", "B"}) {
    try {
      parse_byte_size(bad, "--max-memory");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const CliError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("--max-memory '", 0), 0u) << error.what();
    }
  }
}

}  // namespace
}  // namespace fscil
