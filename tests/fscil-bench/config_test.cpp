// --config files and rerun.
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

TEST(Cli, ConfigFileSetsRunOptionsAndTheCommandLineOverridesIt) {
  TemporaryDirectory folder;
  const auto config = folder.path() / "ablation.json";
  std::ofstream(config) << R"({"methods": "ablation", "dataset": "simtex-mini", "profile": "smoke", "seeds": "1-2",
                             "grid": {"shot": [1, 5]}})";
  const CommandResult planned = run_cli("plan --config " + config.string() + " --no-estimate");
  ASSERT_EQ(planned.exit_code, 0) << planned.output;
  EXPECT_NE(planned.output.find("12 cells"), std::string::npos) << planned.output;  // 3 groups x 2 seeds x 2 shots
  const CommandResult overridden = run_cli("plan --config " + config.string() + " --seeds 7 --no-estimate");
  ASSERT_EQ(overridden.exit_code, 0) << overridden.output;
  EXPECT_NE(overridden.output.find("6 cells"), std::string::npos) << overridden.output;
  EXPECT_NE(overridden.output.find("shot=5                        7"), std::string::npos) << overridden.output;
  expect_one_error_line(run_cli("--config " + config.string()), "\"grid\" needs the sweep, plan, run-cells or slurm subcommand");
  expect_one_error_line(run_cli("plan --config " + (folder.path() / "none.json").string()),
                        "none.json: cannot open (No such file or directory)");
  // A value the command line overrides is still the file's to get right: nonsense is never accepted silently.
  const auto nonsense = folder.path() / "nonsense.json";
  std::ofstream(nonsense) << R"({"methods": "prototype", "dataset": "simtex-mini", "threads": "many"})";
  expect_one_error_line(run_cli("plan --config " + nonsense.string() + " --threads 1 --no-estimate"),
                        "--config " + nonsense.string() + ": \"threads\"");
  // A named choice the file gets wrong is the file's, the registry's choices (--methods) included.
  const auto unknown = folder.path() / "unknown.json";
  std::ofstream(unknown) << R"({"methods": "nosuch", "dataset": "simtex-mini"})";
  const CommandResult unknown_method = run_cli("plan --config " + unknown.string() + " --no-estimate");
  EXPECT_EQ(unknown_method.exit_code, 2) << unknown_method.output;
  expect_one_error_line(unknown_method, "--config " + unknown.string() + ": \"methods\" 'nosuch': expected all,");
  // A folder is not a file: one line from the one file reader, a bad input (exit 1), not an abort.
  const CommandResult folder_given = run_cli("--config " + folder.path().string());
  EXPECT_EQ(folder_given.exit_code, 1) << folder_given.output;
  expect_one_error_line(folder_given, folder.path().string() + ": expected a file, found a folder");
}

TEST(Cli, RerunRepeatsARunFromItsResultFileExactly) {
  TemporaryDirectory folder;
  const auto first = folder.path() / "first";
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --seeds 2 --threads 1 --quiet --no-cache "
                    "--set shot=3 --class-order shuffled --out " + first.string()).exit_code, 0);
  const auto result = first / "results" / "prototype__simtex-mini__seed2.json";
  const auto again = folder.path() / "again";
  const CommandResult rerun = run_cli("rerun " + result.string() + " --quiet --no-cache --out " + again.string());
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  const auto repeated = again / "results" / "prototype__simtex-mini__seed2.json";
  EXPECT_EQ(accuracies_in(repeated), accuracies_in(result));
  // The same parameters, the shot and the class order included.
  const auto parameters = [](const std::filesystem::path& file) {
    const std::string text = read_text(file);
    const auto start = text.find("\"parameters\": {");
    return text.substr(start, text.find('}', start) - start);
  };
  EXPECT_EQ(parameters(repeated), parameters(result));
  EXPECT_NE(parameters(result).find("\"shot\": \"3\""), std::string::npos) << parameters(result);
  EXPECT_NE(read_text(repeated).find("\"threads\": 1,"), std::string::npos);  // not this machine's 2 cores
  expect_one_error_line(run_cli("rerun " + (folder.path() / "none.json").string()), "none.json");
  expect_one_error_line(run_cli("rerun " + result.string() + " --seeds 3"), "--seeds comes from the result file");
  // A thread count no machine here has is refused before a thread starts.
  std::string text = read_text(result);
  const std::string one = "\"threads\": 1,";
  ASSERT_NE(text.find(one), std::string::npos);
  text.replace(text.find(one), one.size(), "\"threads\": 100000,");
  const auto many = folder.path() / "many.json";
  std::ofstream(many) << text;
  expect_one_error_line(run_cli("rerun " + many.string() + " --quiet --no-cache --out " + (folder.path() / "many").string()),
                        "many.json: threads 100000, expected at most");
  // Round seven: a file lacking a value the run reads once ran with the default in its place.
  text = read_text(result);
  const std::string temperature = "\"temperature\": \"16\",";
  ASSERT_NE(text.find(temperature), std::string::npos) << text;
  text.erase(text.find(temperature), temperature.size());
  const auto lacking = folder.path() / "lacking.json";
  std::ofstream(lacking) << text;
  const auto lacking_out = folder.path() / "lacking";
  const CommandResult refused = run_cli("rerun " + lacking.string() + " --quiet --no-cache --out " + lacking_out.string());
  expect_one_error_line(refused, "lacking.json: field 'parameters.temperature' missing, expected every value the run reads");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(lacking_out / "results"));
}

}  // namespace
}  // namespace fscil
