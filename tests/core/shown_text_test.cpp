#include "core/shown_text.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

TEST(ShownText, InvisibleAndInvalidBytesAreSpelledOutAndReadableTextIsKept) {
  EXPECT_EQ(shown_text("velocity"), "velocity");
  EXPECT_EQ(shown_text("\xEF\xBB\xBFtime\r"), "\\ufefftime\\r");
  EXPECT_EQ(shown_text(std::string("a\0b\x1b[0m\t\n", 9)), "a\\x00b\\x1b[0m\\t\\n");
  EXPECT_EQ(shown_text("Stoff_\xC3\xA4_\xE2\x82\xAC"), "Stoff_\xC3\xA4_\xE2\x82\xAC");  // UTF-8 is shown as text
  EXPECT_EQ(shown_text("\xC3(\xFF\xE2\x82"), "\\xc3(\\xff\\xe2\\x82");                  // broken UTF-8 is not
  EXPECT_EQ(shown_text(""), "");
}

TEST(ShownText, ALongFieldIsCutAfterEightyCharactersWithItsSize) {
  EXPECT_EQ(shown_text(std::string(80, 'x')), std::string(80, 'x'));
  EXPECT_EQ(shown_text(std::string(20'000'000, 'x')), std::string(80, 'x') + "... (20000000 bytes in all)");
  EXPECT_EQ(shown_text(std::string(100, '\x01')).substr(0, 8), "\\x01\\x01");
  EXPECT_EQ(shown_text(std::string(100, '\x01')).size(), 80 * 4 + std::string("... (100 bytes in all)").size());
}

TEST(IsOneLine, RefusesEveryControlCharacterAndKeepsPrintableAndUtf8Text) {
  EXPECT_TRUE(is_one_line("our reading of X: \\input{y} ~ ^ 100%"));
  EXPECT_TRUE(is_one_line("caf\xC3\xA9"));
  EXPECT_TRUE(is_one_line(""));
  for (const char* text : {"two\nlines", "a\rb", "tab\there", "del\x7F", "bell\x07"}) {
    EXPECT_FALSE(is_one_line(text)) << shown_text(text);
  }
  EXPECT_FALSE(is_one_line(std::string_view("nul\0byte", 8)));
}

}  // namespace
}  // namespace fscil
