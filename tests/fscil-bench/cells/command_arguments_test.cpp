#include "tools/fscil-bench/cells/command_arguments.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace fscil {
namespace {

TEST(CommandArguments, WriteEveryOptionAndTheSweepWithoutThreadsResumeOrCell) {
  RunOptions options;
  options.methods = "pits-sc,cop-fscil/cpi+pspc";
  options.dataset = "simtex-mini";
  options.profile = "smoke";
  options.seeds = "1-3";
  options.threads = 7;
  options.resume = true;
  options.cell = 4;
  options.out = "out dir";
  options.cache_dir = "/c";
  options.no_stage_cache = true;
  options.selection = "validation";
  options.save_model = true;
  options.assignments = {"pic_weight=0.1", "shot=3"};
  const auto words = command_arguments(options, {"pspc_probes=5,50"});
  const std::vector<std::string> expected = {
      "sweep", "--grid", "pspc_probes=5,50", "--methods", "pits-sc,cop-fscil/cpi+pspc", "--dataset", "simtex-mini",
      "--profile", "smoke", "--seeds", "1-3", "--out", "out dir", "--features", "auto", "--split-mode", "recording",
      "--class-order", "natural", "--evaluate-on", "test", "--selection", "validation", "--cache-dir", "/c",
      "--no-stage-cache", "--save-model", "--set", "pic_weight=0.1", "--set", "shot=3"};
  EXPECT_EQ(words, expected);
  EXPECT_EQ(command_arguments(options, {}).front(), "--methods");
}

// What the shell reads back from the line is the words themselves.
TEST(CommandArguments, ShellCommandQuotesWhatTheShellWouldSplitOrExpand) {
  const std::vector<std::string> words = {"fscil-bench", "--out", "a b", "--set", "x=$HOME", "it's", "", "*", "p/q+r=1,2"};
  const std::string line = shell_command(words);
  EXPECT_EQ(line, "fscil-bench --out 'a b' --set 'x=$HOME' 'it'\\''s' '' '*' p/q+r=1,2");
  FILE* shell = ::popen(("printf '%s\\n' " + line).c_str(), "r");
  ASSERT_NE(shell, nullptr);
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, shell) != nullptr) output += buffer;
  ASSERT_EQ(::pclose(shell), 0);
  std::string joined;
  for (const auto& word : words) joined += word + "\n";
  EXPECT_EQ(output, joined);
}

}  // namespace
}  // namespace fscil
