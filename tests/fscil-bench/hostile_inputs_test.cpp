// Bad inputs and faults as a user or an attacker tries them, one row each: the command, its exit
// code, a fragment of its one error line, and the promise that it changed no file (nothing in
// --out, the cache or the user's files is written, replaced or removed). The next round of hostile
// inputs starts from this table.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "core/stable_hash.h"
#include "tests/fscil-bench/cli_support.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

struct HostileCase {
  const char* name;
  std::string arguments;  // {root} stands for a fresh folder holding out/ (with a user's file) and cache/
  int exit_code;
  const char* fragment;   // of the one error line
};

// Every file below `root` with a digest of its content: what must come out of a refused command
// exactly as it went in.
std::map<std::string, std::string> tree_of(const fs::path& root) {
  std::map<std::string, std::string> tree;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string name = fs::relative(entry.path(), root).string();
    tree[name] = entry.is_regular_file() ? stable_hash(read_text(entry.path())) : std::string("folder");
  }
  return tree;
}

std::string with_root(std::string arguments, const fs::path& root) {
  for (std::size_t at; (at = arguments.find("{root}")) != std::string::npos;) {
    arguments.replace(at, 6, root.string());
  }
  return arguments;
}

const std::string kRun = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet "
                         "--out {root}/out --cache-dir {root}/cache ";

const HostileCase kCases[] = {
    // A failed preparation writes no cache: simulator knobs have physical ranges.
    {"context_strength_far_out_of_range", kRun + "--set context_strength=1e300", 1, "context_strength"},
    {"context_strength_past_its_physical_range", kRun + "--set context_strength=1000", 1, "context_strength"},
    {"context_strength_negative", kRun + "--set context_strength=-1", 1, "context_strength"},
};

class HostileInput : public testing::TestWithParam<HostileCase> {};

TEST_P(HostileInput, FailsWithOneLineAndChangesNoFile) {
  const HostileCase& c = GetParam();
  TemporaryDirectory root;
  fs::create_directories(root.path() / "out");
  fs::create_directories(root.path() / "cache");
  std::ofstream(root.path() / "out" / "notes.txt") << "the user's own notes\n";
  const auto before = tree_of(root.path());

  const CommandResult result = run_cli(with_root(c.arguments, root.path()));
  expect_one_error_line(result, c.fragment);
  EXPECT_EQ(result.exit_code, c.exit_code) << result.output;
  EXPECT_EQ(tree_of(root.path()), before) << "files changed by: " << c.arguments;
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInput, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<HostileCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace fscil
