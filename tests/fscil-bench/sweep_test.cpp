// sweep and reproduce: a run per grid cell, epochs chosen on test labelled, the paper layout.
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

TEST(Cli, SweepRunsEveryCellApartAndTablesThemWithAColumnPerKey) {
  TemporaryDirectory out, plain;
  const std::string common = " --methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache";
  const CommandResult sweep = run_cli("sweep --grid shot=3,5" + common + " --out " + out.path().string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_NE(sweep.output.find("| shot | method |"), std::string::npos) << sweep.output;
  const auto summary = lines_of(out.path() / "summary.csv");
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[0].rfind("method,dataset,shot,split,selection,precision,seeds,AA,", 0), 0u) << summary[0];
  EXPECT_EQ(summary[1].rfind("prototype,simtex-mini,3,test,last,fp32,1,", 0), 0u) << summary[1];
  EXPECT_EQ(summary[2].rfind("prototype,simtex-mini,5,test,last,fp32,1,", 0), 0u) << summary[2];
  // Tidy: a line per cell, seed and session.
  const auto sessions = lines_of(out.path() / "sessions.csv");
  ASSERT_EQ(sessions.size(), 1u + 2 * 3);
  EXPECT_EQ(sessions[0].rfind("method,dataset,shot,split,selection,precision,seed,session,seen_classes,accuracy,base,novel,", 0),
            0u);
  // A cell is the run command with its values: the same numbers as that command on its own.
  const CommandResult alone = run_cli(common.substr(1) + " --set shot=5 --out " + plain.path().string());
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  const auto cell_result = out.path() / "cells" / "shot=5" / "results" / "prototype__simtex-mini__seed1.json";
  EXPECT_EQ(scores_in(cell_result), scores_in(plain.path() / "results" / "prototype__simtex-mini__seed1.json"));
  EXPECT_NE(lines_of(cell_result).size(), 0u);
  // Each run's training log, in its cell's folder and, by cell, in the sweep's.
  EXPECT_TRUE(std::filesystem::exists(out.path() / "cells" / "shot=3" / "logs" / "prototype__simtex-mini__seed1.csv"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "logs" / "shot=3" / "prototype__simtex-mini__seed1.csv"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "figures" / "sessions_simtex-mini_all.svg"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "index.html"));

  // Resuming a finished sweep keeps every cell and gives the same tables.
  const CommandResult resumed = run_cli("sweep --grid shot=3,5" + common + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(lines_of(out.path() / "summary.csv"), summary);

  expect_one_error_line(run_cli("sweep --grid shot=3,5 --set shot=3" + common + " --out " + out.path().string()),
                        "--set shot=3 and --grid shot");
  expect_one_error_line(run_cli("sweep --grid shot=3,,5" + common + " --out " + out.path().string()), "--grid");
  expect_one_error_line(run_cli("sweep --grid selection=last,best" + common + " --out " + out.path().string()),
                        "--grid selection 'best': expected last, validation or test-oracle");
}

// Issue 70: the grid's order is the order of every table, folder and legend, and a legend that
// must be shortened says what it left out instead of cutting labels into look-alikes.
TEST(Cli, ASweepKeepsTheGridsOrderInItsColumnsFoldersAndLegends) {
  TemporaryDirectory out;
  const CommandResult sweep = run_cli("sweep --grid shot=5,3 --grid context_strength=1 --methods prototype --dataset "
                                      "simtex-mini --profile smoke --threads 1 --quiet --no-cache --out " +
                                      out.path().string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_NE(sweep.output.find("| shot | context_strength | method |"), std::string::npos) << sweep.output;
  const auto summary = lines_of(out.path() / "summary.csv");
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[0].rfind("method,dataset,shot,context_strength,split,", 0), 0u) << summary[0];
  EXPECT_EQ(summary[1].rfind("prototype,simtex-mini,5,1,", 0), 0u) << "the values in the order given";
  EXPECT_EQ(summary[2].rfind("prototype,simtex-mini,3,1,", 0), 0u);
  EXPECT_TRUE(std::filesystem::is_directory(out.path() / "cells" / "shot=5+context_strength=1"));
  EXPECT_NE(lines_of(out.path() / "costs.csv").at(1).find("prototype,simtex-mini,shot=5+context_strength=1,"),
            std::string::npos);
  std::ifstream figure_file(out.path() / "figures" / "sessions_simtex-mini_all.svg");
  const std::string figure((std::istreambuf_iterator<char>(figure_file)), std::istreambuf_iterator<char>());
  // "prototype [shot=5+context_strength=1]" is wider than a legend entry: what both share goes under the title.
  EXPECT_NE(figure.find(">shot=5</text>"), std::string::npos) << figure;
  EXPECT_NE(figure.find(">shot=3</text>"), std::string::npos);
  EXPECT_NE(figure.find("prototype; context_strength=1"), std::string::npos);
  EXPECT_EQ(figure.find("\xE2\x80\xA6"), std::string::npos) << "no label cut with an ellipsis";
}

TEST(Cli, EpochsChosenOnTestAreLabelledInflatedAndNeverShareAnOutWithHonestRuns) {
  TemporaryDirectory out;
  const std::string common = " --methods pits-sc --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache "
                             "--out " + out.path().string();
  const CommandResult oracle = run_cli("--selection test-oracle" + common);
  ASSERT_EQ(oracle.exit_code, 0) << oracle.output;
  EXPECT_NE(oracle.output.find("| pits-sc (selected on test (inflated)) |"), std::string::npos) << oracle.output;
  std::ifstream file(out.path() / "results" / "pits-sc__simtex-mini__seed1.json");
  const std::string record(std::istreambuf_iterator<char>(file), {});
  EXPECT_NE(record.find("\"selection\": \"test-oracle\""), std::string::npos);
  EXPECT_NE(record.find("\"pretraining_kept_epoch\""), std::string::npos);
  EXPECT_NE(record.find("\"pseudo_incremental_kept_epoch\""), std::string::npos);
  // Every scored epoch is in the training log with its score.
  const auto log = lines_of(out.path() / "logs" / "pits-sc__simtex-mini__seed1.csv");
  ASSERT_GE(log.size(), 2u);
  EXPECT_NE(log[0].find("selection_score"), std::string::npos) << log[0];
  EXPECT_EQ(log[1].rfind("0,pretrain,1,", 0), 0u) << log[1];
  expect_one_error_line(run_cli(common.substr(1)), "selection=test-oracle");
  expect_one_error_line(run_cli("--selection best" + common), "--selection 'best'");
}

TEST(Cli, ReproduceListsThePapersTablesAndWritesOneInItsLayoutWithItsFigures) {
  const CommandResult list = run_cli("reproduce --list");
  ASSERT_EQ(list.exit_code, 0) << list.output;
  for (const char* name : {"results", "ablation", "efficiency", "lambda", "reference-selection", "cpi-coverage",
                           "fewer-shot", "nps", "context", "embedding", "selection-bias"}) {
    EXPECT_NE(("\n" + list.output).find(fmt::format("\n{} ", name)), std::string::npos) << name;
  }
  TemporaryDirectory out;
  const CommandResult embedding = run_cli("reproduce embedding --dataset simtex-mini --profile smoke --threads 1 --quiet "
                                          "--no-cache --out " + out.path().string());
  ASSERT_EQ(embedding.exit_code, 0) << embedding.output;
  for (const char* file : {"embedding.md", "index.html", "embeddings/pits-sc__simtex-mini__seed1.h5",
                           "figures/embedding_pits-sc_seed1.svg", "figures/embedding_cop-fscil_seed1.tex",
                           "figures/embedding_cop-fscil_seed1.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(out.path() / file)) << file;
  }
  // The last session's embeddings of every seen class: 20 classes x 5 test samples of simtex-mini.
  const auto labels = read_hdf5_integers(out.path() / "embeddings" / "pits-sc__simtex-mini__seed1.h5", "session_2_labels");
  EXPECT_EQ(labels.size(), 100u);
  // 5 base and 5 novel classes, every point on the unit circle.
  const auto points = lines_of(out.path() / "figures" / "embedding_pits-sc_seed1.csv");
  ASSERT_EQ(points.size(), 1u + 10 * 5);
  for (std::size_t i = 1; i < points.size(); ++i) {
    const auto y_at = points[i].rfind(','), x_at = points[i].rfind(',', y_at - 1);
    const double x = std::stod(points[i].substr(x_at + 1, y_at - x_at - 1)), y = std::stod(points[i].substr(y_at + 1));
    EXPECT_NEAR(x * x + y * y, 1.0, 1e-4) << points[i];
  }
  expect_one_error_line(run_cli("reproduce lambda --methods prototype --dataset simtex-mini"), "runs its own methods");
  expect_one_error_line(run_cli("reproduce tables --dataset simtex-mini"), "no such reproduction");
}

}  // namespace
}  // namespace fscil
