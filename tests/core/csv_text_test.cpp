#include "core/csv_text.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

using Fields = std::vector<std::string>;

TEST(CsvText, SplitsAtCommasOutsideQuotesAndUnquotesRfc4180Fields) {
  EXPECT_EQ(csv_fields("a,b,c"), (Fields{"a", "b", "c"}));
  EXPECT_EQ(csv_fields(" a , b "), (Fields{"a", "b"}));
  EXPECT_EQ(csv_fields("\"x, y\",2"), (Fields{"x, y", "2"}));
  EXPECT_EQ(csv_fields("\"say \"\"hi\"\"\",3"), (Fields{"say \"hi\"", "3"}));
  EXPECT_EQ(csv_fields("a,"), (Fields{"a", ""}));
  EXPECT_EQ(csv_fields("a&b \"q\" 'x',2"), (Fields{"a&b \"q\" 'x'", "2"}));  // a quote inside a field is a character
  EXPECT_EQ(csv_fields(" \" padded \" ,x"), (Fields{"padded", "x"}));
  EXPECT_EQ(csv_fields(""), (Fields{""}));
}

TEST(CsvText, AFieldWrittenIsReadBackWhole) {
  EXPECT_EQ(csv_field("plain text"), "plain text");
  EXPECT_EQ(csv_field("a, b"), "\"a, b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");  // RFC 4180; csv_lines would split it: writers keep them out
  for (const std::string text : {"x, y", "a \"q\", b", "", "one", "\"", "\"start"}) {
    EXPECT_EQ(csv_fields(csv_field(text) + ",next"), (Fields{text, "next"})) << text;
  }
}

TEST(CsvText, LinesLoseTheByteOrderMarkAndCarriageReturns) {
  EXPECT_EQ(csv_lines("\xEF\xBB\xBFh1,h2\r\n1,2\r\n"), (Fields{"h1,h2", "1,2"}));
  EXPECT_EQ(csv_lines("a\n\nb"), (Fields{"a", "", "b"}));
}

}  // namespace
}  // namespace fscil
