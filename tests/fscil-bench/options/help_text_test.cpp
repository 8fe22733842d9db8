// Help text is wrapped between words to the width asked, continuation lines indented.
#include "tools/fscil-bench/options/help_text.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

TEST(HelpText, WrapsBetweenWordsWithinTheWidthAndIndentsWhatFollows) {
  EXPECT_EQ(wrap_words("one two three four", 9), "one two\nthree\nfour");
  EXPECT_EQ(wrap_words("one two three four", 9, 2), "one two\n  three\n  four");
  EXPECT_EQ(wrap_words("  spaced   out\n words ", 100), "spaced out words");
  EXPECT_EQ(wrap_words("a --very-long-option-name b", 8), "a\n--very-long-option-name\nb");  // never cut a word
  EXPECT_EQ(wrap_words("", 10), "");
}

TEST(HelpText, ALabelledRowKeepsItsColumnOnEveryLine) {
  const std::string row = labelled_lines("  pits-sc", std::string(60, 'a') + " " + std::string(20, 'b'), 25);
  EXPECT_EQ(row, "  pits-sc                " + std::string(60, 'a') + "\n" + std::string(25, ' ') + std::string(20, 'b'));
  EXPECT_EQ(labelled_lines("a-name-longer-than-the-column", "text", 10), "a-name-longer-than-the-column text");
}

TEST(HelpText, ASubcommandsFooterNamesTheMainCommandsOptionsButHelpAndVersion) {
  CLI::App app;
  app.set_version_flag("--version", "1");
  std::string methods, dataset;
  app.add_option("--methods", methods);
  app.add_option("--dataset", dataset);
  const std::string footer = run_options_footer(app);
  const std::string names = footer.substr(footer.find(':') + 1);
  EXPECT_EQ(names, " --methods --dataset") << footer;
}

}  // namespace
}  // namespace fscil
