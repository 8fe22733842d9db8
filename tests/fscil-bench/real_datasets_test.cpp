// The smoke protocol on each real-data adapter's fixture tree, as a user would run it.
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

// A full smoke protocol on each real-data adapter's fixture tree, as a user would run it.
class RealDatasetSmokeRun : public ::testing::Test {
 protected:
  // Not --quiet: the progress lines show the input shape.
  CommandResult run(const std::string& dataset, const std::string& protocol) {
    return run_cli("--methods prototype --dataset " + dataset + " --data-root " + data.path().string() +
                   " --profile smoke --threads 1 --no-cache --out " + out.path().string() + " " + protocol);
  }
  // Session accuracies of the run's result file, which must exist.
  std::vector<double> accuracies(const std::string& dataset) {
    const auto file = out.path() / "results" / ("prototype__" + dataset + "__seed1.json");
    std::ifstream in(file);
    EXPECT_TRUE(in.good()) << file;
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    std::vector<double> values;
    for (auto at = text.find("\"accuracy\": "); at != std::string::npos; at = text.find("\"accuracy\": ", at + 1)) {
      values.push_back(std::stod(text.substr(at + 12)));
    }
    return values;
  }
  // The fixture's classes are tones at distinct frequencies: a pipeline that keeps files, labels
  // and splits aligned gets every test segment right in every session.
  static void expect_all_correct(const std::vector<double>& accuracies, std::size_t sessions) {
    EXPECT_EQ(accuracies.size(), sessions);
    for (double accuracy : accuracies) EXPECT_EQ(accuracy, 100.0);
  }
  TemporaryDirectory data, out;
};

TEST_F(RealDatasetSmokeRun, Lmt108) {
  write_lmt108_fixture(data.path(), {});
  const CommandResult result = run("lmt108", "--set base_classes=2 --set way=1 --set sessions=2 --set shot=2");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("30 segments of shape 3x64x493"), std::string::npos) << result.output;
  expect_all_correct(accuracies("lmt108"), 2);
}

TEST_F(RealDatasetSmokeRun, Haptex) {
  write_haptex_fixture(data.path(), {});
  const CommandResult result = run("haptex", "--set base_classes=2 --set way=1 --set sessions=3 --set shot=2");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("32 segments of shape 5x64x24"), std::string::npos) << result.output;
  expect_all_correct(accuracies("haptex"), 3);
}

TEST_F(RealDatasetSmokeRun, Ls100) {
  write_ls100_fixture(data.path(), {});
  const CommandResult result = run("ls100", "--set base_classes=2 --set way=1 --set sessions=3");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("32 segments of shape 3x128x178"), std::string::npos) << result.output;
  expect_all_correct(accuracies("ls100"), 3);
}

TEST_F(RealDatasetSmokeRun, Ls100WithFeaturesOnDemand) {
  write_ls100_fixture(data.path(), {});  // mono audio: the channel repeat applies to computed batches too
  const CommandResult result = run("ls100", "--set base_classes=2 --set way=1 --set sessions=3 --features on-demand");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("32 segments of shape 3x128x178"), std::string::npos) << result.output;
  expect_all_correct(accuracies("ls100"), 3);
}

TEST_F(RealDatasetSmokeRun, Ns100) {
  write_ns100_fixture(data.path(), {});
  const CommandResult result = run("ns100", "--set base_classes=2 --set way=1 --set sessions=3");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("32 segments of shape 3x128x63"), std::string::npos) << result.output;
  expect_all_correct(accuracies("ns100"), 3);
}

TEST_F(RealDatasetSmokeRun, TooFewRecordingsForTheShotsIsOneLineNamingDatasetAndClass) {
  HaptexFixture fixture;
  fixture.recordings = 3;  // one trains, one validates, one tests: two segments, not five shots
  write_haptex_fixture(data.path(), fixture);
  expect_one_error_line(run("haptex", "--set base_classes=2 --set way=1 --set sessions=3"),
                        "dataset haptex in " + data.path().string() + ", 1-way 5-shot: class fabric02: 2 training "
                        "segments, 5 shots needed");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "summary.csv"));
}

TEST_F(RealDatasetSmokeRun, MalformedDataIsOneErrorLineAndNoResults) {
  write_ls100_fixture(data.path(), {});
  write_wav(data.path() / "101/101-0009.wav", std::vector<float>(100, 0.1f), 16000, 32000);
  expect_one_error_line(run("ls100", ""), "101-0009.wav: truncated");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results"));
}

}  // namespace
}  // namespace fscil
