// check and reference: stored numbers against results, both ways.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <csignal>
#include <thread>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "datasets/hdf5_file.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"
#include "tests/fscil-bench/cli_support.h"

namespace fscil {
namespace {

TEST(Cli, CheckComparesResultsWithReferenceNumbersBothWays) {
  TemporaryDirectory out;
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out " +
                    out.path().string()).exit_code, 0);
  const std::string reference = (out.path() / "reference.csv").string();
  ASSERT_EQ(run_cli("reference --results " + out.path().string() + " --out " + reference).exit_code, 0);
  const CommandResult same = run_cli("check --results " + out.path().string() + " --reference " + reference);
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("all 6 reference values"), std::string::npos) << same.output;
  // Nudge one stored value up: the unchanged run now looks like a loss beyond tolerance.
  std::ifstream in(reference);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto at = text.find(",acc_1,");
  const auto value_end = text.find(',', at + 7);
  const double stored = std::stod(text.substr(at + 7, value_end - at - 7));
  text.replace(at + 7, value_end - at - 7, fmt::format("{:.4f}", stored + 5));
  std::ofstream(reference) << text;
  const CommandResult drifted = run_cli("check --results " + out.path().string() + " --reference " + reference);
  EXPECT_EQ(drifted.exit_code, 1);
  EXPECT_NE(drifted.output.find(fmt::format("FAIL prototype on simtex-mini seed 1 acc_1: expected {:.2f} +- 2.00, got {:.2f} (-5.00)",
                                            stored + 5, stored)), std::string::npos) << drifted.output;
  // A user's own file is made again by the command that wrote it, not by the repository's script.
  EXPECT_NE(drifted.output.find("regenerate with: fscil-bench reference --results " + out.path().string() + " --out " +
                                reference + "\n"),
            std::string::npos)
      << drifted.output;
}

// The repository's own reference files are made again by their script, which holds every library
// to the kernels they were made with; `check` says so whatever the files were checked against.
TEST(Cli, CheckTellsTheRepositorysReferencesToBeRegeneratedByTheirScript) {
  TemporaryDirectory out;
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out " +
                    out.path().string()).exit_code, 0);
  const std::string stored = (source_folder() / "reports" / "reference" / "simtex-mini-smoke.csv").string();
  const CommandResult checked = run_cli("check --results " + out.path().string() + " --reference " + stored);
  EXPECT_EQ(checked.exit_code, 1) << "1 thread against the stored 2";
  EXPECT_NE(checked.output.find("regenerate with: bash tools/reference_protocol.sh regenerate\n"), std::string::npos)
      << checked.output;
}

}  // namespace
}  // namespace fscil
