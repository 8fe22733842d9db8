#include "tools/fscil-bench/cells/command_arguments.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>

#include "tools/fscil-bench/options/run_option_table.h"

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
      "--no-stage-cache", "--save-model", "--precision", "fp32", "--set", "pic_weight=0.1", "--set", "shot=3"};
  EXPECT_EQ(words, expected);
  EXPECT_EQ(command_arguments(options, {}).front(), "--methods");
}

// The one option table both declares the options and writes them: what it writes parses back to
// the same options, and what it leaves out (threads, cell) keeps its default.
TEST(RunOptionTable, WrittenOptionsParseBackToTheSameOptions) {
  RunOptions options;
  options.methods = "prototype";
  options.dataset = "simtex-mini";
  options.profile = "paper";
  options.seeds = "2-4";
  options.threads = 3;
  options.cell = 1;
  options.out = "somewhere else";
  options.features = "on-demand";
  options.split_mode = "segment";
  options.class_order = "shuffled";
  options.evaluate_on = "validation";
  options.selection = "test-oracle";
  options.data_root = "/data";
  options.cache_dir = "/cache";
  options.no_cache = true;
  options.no_stage_cache = true;
  options.save_embeddings = "0,9";
  options.save_model = true;
  options.max_memory = "4G";
  options.assignments = {"shot=3", "way=4"};
  options.quiet = true;
  std::vector<std::string> words = {"fscil-bench"};
  for (const auto& word : run_option_words(options)) words.push_back(word);
  std::vector<char*> argv;
  for (auto& word : words) argv.push_back(word.data());
  CLI::App app;
  RunOptions parsed;
  declare_run_options(app, parsed);
  app.parse(static_cast<int>(argv.size()), argv.data());
  EXPECT_EQ(run_option_words(parsed), run_option_words(options));
  EXPECT_EQ(parsed.threads, 0);
  EXPECT_EQ(parsed.cell, -1);
  EXPECT_EQ(parsed.max_memory, "4G");
  EXPECT_EQ(parsed.assignments, options.assignments);
  EXPECT_TRUE(parsed.no_cache && parsed.no_stage_cache && parsed.save_model && parsed.quiet);
  // An option a command always passes on is written even empty, so a cell refuses it as the command
  // would, rather than run with a default.
  RunOptions empty_selection = options;
  empty_selection.selection = "";
  const auto empty_words = run_option_words(empty_selection);
  const auto selection = std::find(empty_words.begin(), empty_words.end(), "--selection");
  ASSERT_NE(selection, empty_words.end());
  EXPECT_EQ(*(selection + 1), "");
  // Every row is a distinct option.
  std::set<std::string> names;
  for (const auto& row : run_option_table()) EXPECT_TRUE(names.insert(row.name).second) << row.name;
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
