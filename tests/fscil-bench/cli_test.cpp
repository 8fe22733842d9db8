// Runs the fscil-bench executable as a user would and checks exit codes, messages and files.
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
#include "fscil_build_info.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// `environment`: assignments the shell puts before the command, for this run only.
CommandResult run_cli(const std::string& arguments, const std::string& environment = "") {
  const std::string command = environment + " " + std::string(FSCIL_BENCH_EXECUTABLE) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 512> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The error contract: exactly one line, starting with the program name, non-zero exit.
void expect_one_error_line(const CommandResult& result, const std::string& fragment) {
  EXPECT_NE(result.exit_code, 0) << result.output;
  const auto line_start = result.output.find("fscil-bench: error: ");
  ASSERT_NE(line_start, std::string::npos) << result.output;
  const std::string line = result.output.substr(line_start, result.output.find('\n', line_start) - line_start);
  EXPECT_NE(line.find(fragment), std::string::npos) << line;
  EXPECT_EQ(result.output.find("fscil-bench: error: ", line_start + 1), std::string::npos) << result.output;
}

TEST(Cli, ListsMethodsDatasetsAndProfiles) {
  const CommandResult result = run_cli("list");
  EXPECT_EQ(result.exit_code, 0);
  for (const char* name : {"prototype", "simtex", "simtex-lmt", "simtex-mini", "lmt108", "smoke", "fast", "paper"}) {
    EXPECT_NE(result.output.find(name), std::string::npos) << name;
  }
}

TEST(Cli, VersionNamesTheReleaseTheCommitAndTheLibraries) {
  const CommandResult version = run_cli("--version");
  EXPECT_EQ(version.exit_code, 0) << version.output;
  EXPECT_EQ(version.output.rfind(fmt::format("fscil-bench {} (commit {})\n", FSCIL_VERSION, FSCIL_SOURCE_COMMIT), 0), 0u)
      << version.output;
  for (const char* library : {"  libtorch   1.", "  fftw       fftw-3.", "  hdf5       1.", "  libsndfile libsndfile-1.",
                              "  openblas   ", "  compiler   "}) {
    EXPECT_NE(version.output.find(library), std::string::npos) << library << " in\n" << version.output;
  }
}

// The kernels each library chose are named, and lowered by the variables the reference protocol
// sets (tools/reference_protocol.sh).
TEST(Cli, VersionNamesTheKernelsTheLibrariesChose) {
  const CommandResult lowered =
      run_cli("--version", "ATEN_CPU_CAPABILITY=default OPENBLAS_CORETYPE=Haswell ONEDNN_MAX_CPU_ISA=SSE41");
  EXPECT_EQ(lowered.exit_code, 0) << lowered.output;
  EXPECT_NE(lowered.output.find("  kernels    aten=NO_AVX openblas=Haswell onednn=sse41\n"), std::string::npos)
      << lowered.output;
  const CommandResult own = run_cli("--version");
  EXPECT_EQ(own.exit_code, 0) << own.output;
  EXPECT_NE(own.output.find("  kernels    aten=AVX"), std::string::npos) << own.output;
}

TEST(Cli, UnknownNamesAndGarbageGetOneClearLine) {
  TemporaryDirectory out;
  const std::string common = " --quiet --no-cache --out " + out.path().string();
  expect_one_error_line(run_cli("--methods nosuch --dataset simtex-mini" + common), "unknown method 'nosuch'");
  expect_one_error_line(run_cli("--methods prototype --dataset nosuch" + common), "unknown dataset 'nosuch'");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --profile turbo" + common),
                        "unknown profile 'turbo'");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --seeds 1,x" + common), "--seeds '1,x'");
  expect_one_error_line(run_cli("--methods prototype --dataset haptex" + common), "needs --data-root");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set no_such_knob=3" + common),
                        "--set no_such_knob");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set pretrain_epochs=many" + common),
                        "pretrain_epochs='many': expected an integer");
  // Nonsense values are refused by their owner before anything trains.
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set temperature=0" + common),
                        "temperature='0': expected a number > 0");
  expect_one_error_line(run_cli("--methods pits-sc --dataset simtex-mini --set lr_gamma=-1" + common),
                        "lr_gamma='-1': expected a number in (0, 1]");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --features disk" + common),
                        "feature storage 'disk': expected auto, memory or on-demand");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --threads -1" + common),
                        "--threads: expected a number >= 0");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --max-memory 4X" + common),
                        "--max-memory '4X': expected a size such as 4G");
  expect_one_error_line(run_cli("logmel --input a.h5 --output b.h5 --sample-rate nan --n-fft 128 --hop 16 --n-mels 64"),
                        "--sample-rate: expected a number > 0");
  // CLI11's own complaints read like ours: one prefixed line, exit 2.
  const CommandResult unknown_flag = run_cli("--methods prototype --dataset simtex-mini --bogus" + common);
  EXPECT_EQ(unknown_flag.exit_code, 2);
  expect_one_error_line(unknown_flag, "--bogus");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "summary.csv"));
  // A result file of raw bytes and terminal escapes: the error line spells them out.
  std::filesystem::create_directories(out.path() / "results");
  std::ofstream(out.path() / "results" / "odd.json") << "{\"method\": \"\xff\x1b[2J\x07" << std::string(5000, 'x');
  const CommandResult odd = run_cli("report --results " + out.path().string());
  expect_one_error_line(odd, "odd.json: not a valid result file");
  EXPECT_EQ(odd.output.find_first_of("\x1b\x07\xff"), std::string::npos) << odd.output;
}

TEST(Cli, OutputThatCannotBeWrittenIsAFailure) {
  // Tables to a full disk: stdout goes to /dev/full, stderr still to the pipe.
  const std::string command = std::string(FSCIL_BENCH_EXECUTABLE) + " list 2>&1 >/dev/full";
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 512> line{};
  const std::string said = fgets(line.data(), line.size(), pipe) != nullptr ? line.data() : "";
  const int status = pclose(pipe);
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(said, "fscil-bench: error: standard output: cannot write (No space left on device)\n");
}

TEST(Cli, SmokeRunWritesResultsAndReportRebuildsThem) {
  TemporaryDirectory out;
  // Where git sees no repository at run time, a result still names the commit its binary was built from.
  const CommandResult run = run_cli("--methods prototype --dataset simtex-mini --profile smoke --seeds 1,2 --threads 2 "
                                    "--quiet --no-cache --out " + out.path().string(),
                                    "GIT_DIR=/nonexistent");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("| prototype |"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed1.json"));
  std::ifstream result(out.path() / "results" / "prototype__simtex-mini__seed1.json");
  const std::string record(std::istreambuf_iterator<char>(result), {});
  EXPECT_NE(record.find(fmt::format("\"git_commit\": \"{}\"", FSCIL_SOURCE_COMMIT)), std::string::npos) << record;
  EXPECT_NE(record.find(fmt::format("\"version\": \"{}\"", FSCIL_VERSION)), std::string::npos) << record;
  EXPECT_NE(record.find("\"libtorch\": \"1."), std::string::npos) << record;
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed2.json"));
  std::ifstream csv(out.path() / "summary.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("method,dataset,split,selection,seeds,AA,PD,ADR,acc_0,acc_1,acc_2,AA_std", 0), 0u) << header;
  const std::string first_summary = std::string(std::istreambuf_iterator<char>(csv), {});

  std::filesystem::remove(out.path() / "summary.csv");
  const CommandResult report = run_cli("report --results " + out.path().string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  std::ifstream rebuilt(out.path() / "summary.csv");
  std::getline(rebuilt, header);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(rebuilt), {}), first_summary);
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results.tex"));
  std::ifstream costs(out.path() / "costs.csv");
  std::getline(costs, header);
  EXPECT_EQ(header,
            "method,dataset,runs,mflops,params_m,session_trainable_m,it_ms,base_train_s,update_s,peak_rss_mib,"
            "replay_samples,replay_mib");
  std::string prototype_costs;
  std::getline(costs, prototype_costs);
  // 5x64x24 inputs: ResNet-18 54.5 M MACs + the cosine against 15 classes, x 2; the encoder's
  // 5.217 M parameters + 15 x 256 rows; sessions train none of them.
  EXPECT_EQ(prototype_costs.rfind("prototype,simtex-mini,2,109.1,5.222,0.000,", 0), 0u) << prototype_costs;
  EXPECT_NE(report.output.find("### costs"), std::string::npos);

  // simtex-mini knows its contexts, so every session records R and analyze tabulates it. Its
  // test split holds one recording (one context) per class, so R is exactly 0 there.
  const CommandResult analyze = run_cli("analyze --results " + out.path().string());
  ASSERT_EQ(analyze.exit_code, 0) << analyze.output;
  EXPECT_NE(analyze.output.find("| prototype | simtex-mini |"), std::string::npos) << analyze.output;
  std::ifstream context_csv(out.path() / "context_analysis.csv");
  std::string line;
  int rows = 0;
  std::getline(context_csv, line);
  EXPECT_EQ(line, "method,dataset,seeds,AA,session,R_mean,R_max");
  while (std::getline(context_csv, line)) {
    ++rows;
    const double r_mean = std::stod(line.substr(line.rfind(',', line.rfind(',') - 1) + 1));
    EXPECT_EQ(r_mean, 0.0) << line;
  }
  EXPECT_EQ(rows, 3);
}

// The accuracies recorded in one result file, as written.
std::string accuracies_in(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, accuracies;
  while (std::getline(in, line)) {
    if (line.find("\"accuracy\"") != std::string::npos) accuracies += line;
  }
  return accuracies;
}

TEST(Cli, VariantsSharingABaseGiveTheAccuraciesOfTheirOwnRuns) {
  TemporaryDirectory together, alone;
  const std::string common = " --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache --out ";
  ASSERT_EQ(run_cli("--methods cop-fscil/cpi+pcqa,cop-fscil" + common + together.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli("--methods cop-fscil" + common + alone.path().string()).exit_code, 0);
  const auto file = std::filesystem::path("results") / "cop-fscil__simtex-mini__seed1.json";
  const std::string shared = accuracies_in(together.path() / file);
  EXPECT_EQ(std::count(shared.begin(), shared.end(), ':'), 3);  // acc_0..acc_2
  EXPECT_EQ(shared, accuracies_in(alone.path() / file));
  std::ifstream record(together.path() / file);
  EXPECT_NE(std::string(std::istreambuf_iterator<char>(record), {}).find("\"base_training\": \"shared with cop-fscil/cpi+pcqa\""),
            std::string::npos);
}

// Every score of a result file (accuracies all/base/novel/current/harmonic, context ratios), not
// its timings.
std::string scores_in(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, scores;
  while (std::getline(in, line)) {
    if (line.find("accuracy\"") != std::string::npos || line.find("\"harmonic_mean\"") != std::string::npos ||
        line.find("\"context_ratio_") != std::string::npos) {
      scores += line;
    }
  }
  return scores;
}

std::size_t files_in(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) return 0;
  const std::filesystem::directory_iterator entries(folder);
  return static_cast<std::size_t>(std::distance(begin(entries), end(entries)));
}

TEST(Cli, ABaseFromTheStageCacheGivesTheScoresOfARunThatTrainedItAndAnyMethodParameterMissesIt) {
  TemporaryDirectory cache, cold, warm, sweep_cell, other_lr, uncached, after_damage;
  const auto stages = cache.path() / "stages";
  const std::string common = " --methods prototype --dataset simtex-mini --profile smoke --threads 2 --cache-dir " +
                             cache.path().string() + " --out ";
  const auto result = [](const TemporaryDirectory& out) { return out.path() / "results" / "prototype__simtex-mini__seed1.json"; };
  constexpr const char* kHit = "base session from the stage cache";

  const CommandResult first = run_cli(common + cold.path().string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_EQ(first.output.find(kHit), std::string::npos);
  ASSERT_EQ(files_in(stages), 1u);
  const std::string trained = scores_in(result(cold));
  EXPECT_EQ(std::count(trained.begin(), trained.end(), ':'), 3 * 7);  // 3 sessions x 7 scores

  const CommandResult second = run_cli(common + warm.path().string());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(second.output.find(kHit), std::string::npos) << second.output;
  EXPECT_EQ(scores_in(result(warm)), trained);
  std::ifstream record(result(warm));
  EXPECT_NE(std::string(std::istreambuf_iterator<char>(record), {}).find("\"base_training\": \"from the stage cache\""),
            std::string::npos);

  // A protocol value the base never sees (the novel classes' shots) shares it; a method's own does not.
  const CommandResult cell = run_cli(common + sweep_cell.path().string() + " --set shot=3");
  ASSERT_EQ(cell.exit_code, 0) << cell.output;
  EXPECT_NE(cell.output.find(kHit), std::string::npos) << cell.output;
  const CommandResult changed = run_cli(common + other_lr.path().string() + " --set pretrain_lr=0.05");
  ASSERT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_EQ(changed.output.find(kHit), std::string::npos) << changed.output;
  EXPECT_EQ(files_in(stages), 2u);
  EXPECT_NE(scores_in(result(other_lr)), trained);

  const CommandResult off = run_cli(common + uncached.path().string() + " --no-stage-cache");
  ASSERT_EQ(off.exit_code, 0) << off.output;
  EXPECT_EQ(off.output.find(kHit), std::string::npos);
  EXPECT_EQ(scores_in(result(uncached)), trained);

  // A damaged entry is dropped and the base trained again, to the same scores.
  for (const auto& entry : std::filesystem::directory_iterator(stages)) {
    std::filesystem::resize_file(entry.path(), std::filesystem::file_size(entry.path()) - 100);
  }
  const CommandResult damaged = run_cli(common + after_damage.path().string());
  ASSERT_EQ(damaged.exit_code, 0) << damaged.output;
  EXPECT_NE(damaged.output.find("stage cache entry dropped, the base is trained again"), std::string::npos) << damaged.output;
  EXPECT_EQ(scores_in(result(after_damage)), trained);
}

// The lines of a text file.
std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(Cli, SweepRunsEveryCellApartAndTablesThemWithAColumnPerKey) {
  TemporaryDirectory out, plain;
  const std::string common = " --methods prototype --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache";
  const CommandResult sweep = run_cli("sweep --grid shot=3,5" + common + " --out " + out.path().string());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_NE(sweep.output.find("| shot | method |"), std::string::npos) << sweep.output;
  const auto summary = lines_of(out.path() / "summary.csv");
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[0].rfind("method,dataset,shot,split,selection,seeds,AA,", 0), 0u) << summary[0];
  EXPECT_EQ(summary[1].rfind("prototype,simtex-mini,3,test,last,1,", 0), 0u) << summary[1];
  EXPECT_EQ(summary[2].rfind("prototype,simtex-mini,5,test,last,1,", 0), 0u) << summary[2];
  // Tidy: a line per cell, seed and session.
  const auto sessions = lines_of(out.path() / "sessions.csv");
  ASSERT_EQ(sessions.size(), 1u + 2 * 3);
  EXPECT_EQ(sessions[0].rfind("method,dataset,shot,split,selection,seed,session,seen_classes,accuracy,base,novel,", 0),
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
                        "--selection best");
}

TEST(Cli, EpochsChosenOnTestAreLabelledInflatedAndNeverShareAnOutWithHonestRuns) {
  TemporaryDirectory out;
  const std::string common = " --methods pits-sc --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache "
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
  expect_one_error_line(run_cli("--selection best" + common), "--selection best");
}

TEST(Cli, ReproduceListsThePapersTablesAndWritesOneInItsLayoutWithItsFigures) {
  const CommandResult list = run_cli("reproduce --list");
  ASSERT_EQ(list.exit_code, 0) << list.output;
  for (const char* name : {"results", "ablation", "efficiency", "lambda", "reference-selection", "cpi-coverage",
                           "fewer-shot", "nps", "context", "embedding", "selection-bias"}) {
    EXPECT_NE(("\n" + list.output).find(fmt::format("\n{} ", name)), std::string::npos) << name;
  }
  TemporaryDirectory out;
  const CommandResult embedding = run_cli("reproduce embedding --dataset simtex-mini --profile smoke --threads 2 --quiet "
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

TEST(Cli, EvaluateOnValidationScoresEveryClassesValidationSplitAndSaysSoEverywhere) {
  TemporaryDirectory out, test_out;
  const std::string common = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache";
  const CommandResult run = run_cli(common + " --evaluate-on validation --out " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("### simtex-mini, validation split"), std::string::npos) << run.output;
  std::ifstream result_file(out.path() / "results" / "cop-fscil__simtex-mini__seed1.json");
  const std::string result(std::istreambuf_iterator<char>(result_file), {});
  EXPECT_NE(result.find("\"evaluated_on\": \"validation\""), std::string::npos);
  // What the method reported while training: base validation accuracy after each stage, its
  // loss terms, and PSPC's effective number of shots in each incremental session.
  for (const char* diagnostic : {"base_validation_after_pretraining", "base_validation_after_pseudo_incremental",
                                 "pretraining_ce_mean", "pretraining_side_loss_mean", "pspc_effective_shots"}) {
    EXPECT_NE(result.find(diagnostic), std::string::npos) << diagnostic;
  }
  std::ifstream csv(out.path() / "summary.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(row.rfind("cop-fscil,simtex-mini,validation,last,1,", 0), 0u) << row;
  // Validation-scored runs never stand beside the paper's test numbers or a test run.
  expect_one_error_line(run_cli("report --paper --results " + out.path().string()), "test-split numbers");
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache --out " +
                    test_out.path().string())
                .exit_code,
            0);
  std::filesystem::copy(test_out.path() / "results" / "prototype__simtex-mini__seed1.json",
                        out.path() / "results" / "prototype__simtex-mini__seed1.json");
  expect_one_error_line(run_cli("report --results " + out.path().string()), "scored on validation against test");
  // Under a device shift simtex-mini's novel classes have one held-out recording left for their
  // shots and none for validation: refused before any training.
  expect_one_error_line(run_cli(common + " --evaluate-on validation --set context_shift=device --out " +
                                out.path().string() + "/shifted"),
                        "have no validation recordings in their test contexts");
  expect_one_error_line(run_cli(common + " --evaluate-on train --out " + out.path().string() + "/bad"),
                        "--evaluate-on 'train': expected test or validation");
}

TEST(Cli, TheSameSeedAndThreadsReproduceAccuraciesExactlyAndAnotherSeedDoesNot) {
  TemporaryDirectory first, second, other;
  // cop-fscil draws from every source: splits, shots, CutMix, episodes, probes, initialisation.
  const std::string common = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache";
  ASSERT_EQ(run_cli(common + " --seeds 3 --out " + first.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli(common + " --seeds 3 --out " + second.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli(common + " --seeds 4 --out " + other.path().string()).exit_code, 0);
  const auto file = [](std::uint64_t seed) {
    return std::filesystem::path("results") / fmt::format("cop-fscil__simtex-mini__seed{}.json", seed);
  };
  const std::string once = accuracies_in(first.path() / file(3));
  EXPECT_EQ(std::count(once.begin(), once.end(), ':'), 3);
  EXPECT_EQ(once, accuracies_in(second.path() / file(3)));
  EXPECT_NE(once, accuracies_in(other.path() / file(4)));
}

TEST(Cli, CheckComparesResultsWithReferenceNumbersBothWays) {
  TemporaryDirectory out;
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache --out " +
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
  EXPECT_NE(drifted.output.find("regenerate with: bash tools/reference_protocol.sh regenerate"), std::string::npos);
}

// A run killed with SIGKILL once its first cop-fscil checkpoint exists, i.e. during an
// incremental session of cop-fscil, after prototype had finished.
class KilledRun : public ::testing::Test {
 protected:
  static constexpr const char* kOptions =
      " --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache";

  void SetUp() override {
    const std::string pid_file = (out.path() / "pid").string();
    ASSERT_EQ(std::system((std::string(FSCIL_BENCH_EXECUTABLE) + kOptions + " --out " + out.path().string() +
                           " > /dev/null 2>&1 & echo $! > " + pid_file).c_str()), 0);
    const auto started = std::chrono::steady_clock::now();
    while (!std::filesystem::exists(checkpoint()) && std::chrono::steady_clock::now() - started < std::chrono::minutes(5)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    int pid = 0;
    std::ifstream(pid_file) >> pid;
    ASSERT_GT(pid, 0);
    ::kill(pid, SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // not our child: no waitpid, let it die
  }
  std::filesystem::path checkpoint() const {
    return out.path() / "checkpoints" / "cop-fscil__simtex-mini__seed1.ckpt";
  }
  std::filesystem::path result(const std::string& method) const {
    return out.path() / "results" / (method + "__simtex-mini__seed1.json");
  }
  TemporaryDirectory out;
};

TEST_F(KilledRun, ResumeEndsWithExactlyTheResultsOfAnUninterruptedRun) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  ASSERT_TRUE(std::filesystem::exists(result("prototype")));
  ASSERT_FALSE(std::filesystem::exists(result("cop-fscil"))) << "the run finished before it was killed";
  const CommandResult resumed = run_cli(std::string(kOptions) + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_FALSE(std::filesystem::exists(checkpoint())) << "a finished run leaves no checkpoint";

  TemporaryDirectory uninterrupted;
  ASSERT_EQ(run_cli(std::string(kOptions) + " --out " + uninterrupted.path().string()).exit_code, 0);
  for (const std::string method : {"prototype", "cop-fscil"}) {
    const std::string expected = accuracies_in(uninterrupted.path() / "results" / (method + "__simtex-mini__seed1.json"));
    EXPECT_EQ(std::count(expected.begin(), expected.end(), ':'), 3);
    EXPECT_EQ(accuracies_in(result(method)), expected) << method;
  }
}

TEST_F(KilledRun, AnEmptyResultsFolderStillResumesAndAMistypedResumePathIsRefused) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  expect_one_error_line(run_cli(std::string(kOptions) + " --resume " + (out.path() / "typo").string()),
                        "typo: no such folder, nothing to resume");
  std::filesystem::remove(result("prototype"));  // results/ is now empty, the checkpoint still there
  std::string loud = kOptions;
  loud.erase(loud.find(" --quiet"), 8);
  const CommandResult resumed = run_cli(loud + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("continuing after session"), std::string::npos) << resumed.output;
  EXPECT_TRUE(std::filesystem::exists(result("prototype")));
  EXPECT_TRUE(std::filesystem::exists(result("cop-fscil")));
}

TEST_F(KilledRun, ACorruptOrForeignCheckpointIsRefusedWithOneLine) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  const auto size = std::filesystem::file_size(checkpoint());
  const auto saved = out.path() / "saved.ckpt";
  std::filesystem::copy_file(checkpoint(), saved);
  std::filesystem::resize_file(checkpoint(), size - 100);
  expect_one_error_line(run_cli(std::string(kOptions) + " --resume " + out.path().string()), "corrupt checkpoint");
  EXPECT_FALSE(std::filesystem::exists(result("cop-fscil")));

  // The same file under another seed's name: a checkpoint of another run.
  std::filesystem::rename(saved, out.path() / "checkpoints" / "cop-fscil__simtex-mini__seed2.ckpt");
  expect_one_error_line(run_cli(" --methods cop-fscil --dataset simtex-mini --profile smoke --threads 2 --quiet "
                                "--no-cache --seeds 2 --resume " + out.path().string()),
                        "checkpoint of another run");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results" / "cop-fscil__simtex-mini__seed2.json"));
}

TEST(Cli, RunsOfAnotherProtocolNeverShareAnOutOrATable) {
  TemporaryDirectory out;
  const std::string common = " --dataset simtex-mini --profile smoke --quiet --no-cache --out " + out.path().string();
  ASSERT_EQ(run_cli("--methods prototype --threads 2" + common).exit_code, 0);
  const auto result = out.path() / "results" / "prototype__simtex-mini__seed1.json";
  std::ifstream in(result);
  const std::string written((std::istreambuf_iterator<char>(in)), {});
  ASSERT_NE(written.find("\"shot\": \"5\""), std::string::npos);

  expect_one_error_line(run_cli("--methods prototype --threads 2 --seeds 2 --set shot=2" + common),
                        "holds a run that cannot share a table with this one (shot=5 against shot=2)");
  expect_one_error_line(run_cli("--methods prototype --seeds 2 --threads 1" + common), "(threads 2 against 1)");
  expect_one_error_line(run_cli("--methods prototype,prototype --threads 2" + common), "'prototype' is named twice");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed2.json"));
  std::ifstream again(result);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), {}), written) << "an earlier result changed";

  // Mixed by hand: report refuses the folder rather than average a 5-shot and a 2-shot run.
  std::string other = written;
  for (const std::string from : {"\"shot\": \"5\"", "\"seed\": 1"}) {
    const std::string to = from == "\"seed\": 1" ? "\"seed\": 2" : "\"shot\": \"2\"";
    for (auto at = other.find(from); at != std::string::npos; at = other.find(from)) other.replace(at, from.size(), to);
  }
  std::filesystem::create_directories(out.path() / "copied");
  std::ofstream(out.path() / "copied" / "prototype__simtex-mini__seed2.json") << other;
  const CommandResult report = run_cli("report --results " + out.path().string());
  expect_one_error_line(report, "runs that cannot share a table (shot=2 against shot=5)");
}

TEST(Cli, FeaturesOnDemandAndRecomputedActivationsGiveTheScoresOfTheDefaultRun) {
  TemporaryDirectory in_memory, on_demand, recomputed, limited;
  // pits-sc reads features by batch, the validation split and raw signals for its mixtures.
  const std::string common = " --methods pits-sc --dataset simtex-mini --profile smoke --threads 2 --quiet --no-cache";
  ASSERT_EQ(run_cli(common + " --features memory --out " + in_memory.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli(common + " --features on-demand --out " + on_demand.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli(common + " --set recompute=stages --out " + recomputed.path().string()).exit_code, 0);
  // A budget below what the process already holds: every training pass recomputes.
  ASSERT_EQ(run_cli(common + " --max-memory 1M --out " + limited.path().string()).exit_code, 0);
  const auto file = std::filesystem::path("results") / "pits-sc__simtex-mini__seed1.json";
  const std::string kept = scores_in(in_memory.path() / file);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), ':'), 3 * 7);
  EXPECT_EQ(kept, scores_in(on_demand.path() / file));
  EXPECT_EQ(kept, scores_in(recomputed.path() / file));
  EXPECT_EQ(kept, scores_in(limited.path() / file));
  const auto text_of = [](const std::filesystem::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string limited_record = text_of(limited.path() / file);
  EXPECT_NE(limited_record.find("\"max_memory\": \"1048576\""), std::string::npos) << limited_record;
  const std::string passes_key = "\"max_memory_recomputed_passes\": ";
  const auto passes = limited_record.find(passes_key);
  ASSERT_NE(passes, std::string::npos) << limited_record;
  EXPECT_GT(std::stod(limited_record.substr(passes + passes_key.size())), 0) << "the base session's passes";
  EXPECT_EQ(text_of(in_memory.path() / file).find("max_memory"), std::string::npos);
}

TEST(Cli, LogMelConvertsAndRejectsBadFilesWithoutWritingOutput) {
  TemporaryDirectory directory;
  const auto input = directory.path() / "in.h5";
  const auto output = directory.path() / "out.h5";
  FloatArray signal({3, 8000});
  for (std::int64_t i = 0; i < signal.size(); ++i) signal.values[i] = static_cast<float>(std::sin(0.01 * i * (1 + i % 3)));
  Hdf5Contents contents;
  contents.floats["signal"] = &signal;
  write_hdf5_atomically(input, contents);
  const std::string settings = " --sample-rate 10000 --n-fft 128 --hop 16 --n-mels 64";
  const CommandResult ok = run_cli("logmel --input " + input.string() + " --output " + output.string() + settings);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("Mel filters are empty"), std::string::npos) << "LMT108 settings leave filters empty";
  EXPECT_EQ(read_hdf5_floats(output, "logmel", 3).shape, (std::vector<std::int64_t>{3, 64, 493}));

  const auto wrong_rank = directory.path() / "rank.h5";
  FloatArray cube({2, 2, 100});
  Hdf5Contents cube_contents;
  cube_contents.floats["signal"] = &cube;
  write_hdf5_atomically(wrong_rank, cube_contents);
  const auto truncated = directory.path() / "truncated.h5";
  std::filesystem::copy_file(input, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(input) / 3);
  const auto nan_file = directory.path() / "nan.h5";
  signal.values[4321] = std::nanf("");
  write_hdf5_atomically(nan_file, contents);
  const auto absent = directory.path() / "absent.h5";

  const struct {
    std::filesystem::path file;
    const char* fragment;
  } cases[] = {{wrong_rank, "has 3 dimensions, expected 2"},
               {truncated, "truncated"},
               {nan_file, "finite values expected"},
               {absent, "no such file"}};
  for (const auto& bad : cases) {
    const auto target = directory.path() / ("out-" + bad.file.stem().string() + ".h5");
    expect_one_error_line(run_cli("logmel --input " + bad.file.string() + " --output " + target.string() + settings),
                          bad.fragment);
    EXPECT_NE(run_cli("logmel --input " + bad.file.string() + " --output " + target.string() + settings).output.find(
                  bad.file.string()),
              std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(target)) << "no output may be written for " << bad.file;
  }
  // The input named as the output, however spelled, is refused before it is read or replaced.
  const auto before = std::filesystem::file_size(input);
  expect_one_error_line(run_cli("logmel --input " + input.string() + " --output " + directory.path().string() +
                                "/./in.h5" + settings),
                        "is the input file");
  EXPECT_EQ(std::filesystem::file_size(input), before);
  // A folder in the output's place: one line, and no temporary left beside it.
  const auto folder = directory.path() / "folder.h5";
  std::filesystem::create_directory(folder);
  expect_one_error_line(run_cli("logmel --input " + input.string() + " --output " + folder.string() + settings),
                        folder.string() + ": is a directory, a file was expected");
  EXPECT_TRUE(std::filesystem::is_empty(folder));
  for (const auto& entry : std::filesystem::directory_iterator(directory.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

// A full smoke protocol on each real-data adapter's fixture tree, as a user would run it.
class RealDatasetSmokeRun : public ::testing::Test {
 protected:
  // Not --quiet: the progress lines show the input shape.
  CommandResult run(const std::string& dataset, const std::string& protocol) {
    return run_cli("--methods prototype --dataset " + dataset + " --data-root " + data.path().string() +
                   " --profile smoke --threads 2 --no-cache --out " + out.path().string() + " " + protocol);
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

namespace fscil {
namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(Cli, PlanListsOneCellPerBaseSessionSeedAndGridCell) {
  const CommandResult ablation = run_cli("plan --methods ablation --dataset simtex-mini --profile smoke --seeds 1-2");
  ASSERT_EQ(ablation.exit_code, 0) << ablation.output;
  // pits-sc, then the two pairs of cop-fscil variants that share a base, each for two seeds.
  EXPECT_NE(ablation.output.find("6 cells"), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("    2  cop-fscil/cpi,cop-fscil/cpi+pspc "), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("    5  cop-fscil/cpi+pcqa,cop-fscil "), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("small (4 base epochs)"), std::string::npos) << ablation.output;
  const CommandResult sweep = run_cli("plan --grid shot=1,5 --methods pits-sc,orco --dataset simtex --seeds 3");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_NE(sweep.output.find("4 cells"), std::string::npos) << sweep.output;
  EXPECT_NE(sweep.output.find("    3  orco"), std::string::npos) << sweep.output;
  EXPECT_NE(sweep.output.find("shot=5"), std::string::npos) << sweep.output;
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --seeds 1-2 --cell 2"),
                        "--cell 2: this command has 2 cells, 0 to 1 (see: fscil-bench plan)");
  expect_one_error_line(run_cli("plan --dataset simtex-mini"), "--methods and --dataset are required");
}

TEST(Cli, SlurmWritesAnArrayTaskPerCellAndAMergeJobAndMissingOnlyKeepsCellsWithoutResults) {
  TemporaryDirectory folder;
  const std::string out = (folder.path() / "runs").string();
  const std::string command =
      "slurm --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2 --max-parallel 3 "
      "--time 2:00:00 --sbatch-arg=--account=abc --out " + out;
  const CommandResult written = run_cli(command);
  ASSERT_EQ(written.exit_code, 0) << written.output;
  EXPECT_NE(written.output.find("4 of 4 cells"), std::string::npos) << written.output;
  const std::string array = read_text(folder.path() / "runs" / "slurm" / "array.sbatch");
  for (const char* line : {"#SBATCH --array=0-3%3\n", "#SBATCH --cpus-per-task=1\n", "#SBATCH --signal=B:TERM@120\n",
                           "#SBATCH --requeue\n", "#SBATCH --time=2:00:00\n", "#SBATCH --account=abc\n",
                           "--methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2",
                           "--cell \"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-1}\" &\n",
                           "trap 'stop=1; [ -n \"${child:-}\" ] && kill -TERM \"$child\" 2>/dev/null' TERM\n"}) {
    EXPECT_NE(array.find(line), std::string::npos) << line << " not in\n" << array;
  }
  const std::string merge = read_text(folder.path() / "runs" / "slurm" / "merge.sbatch");
  EXPECT_NE(merge.find("report --results " + out + " --methods prototype,cop-fscil\n"), std::string::npos) << merge;
  EXPECT_NE(merge.find(" plan --methods prototype,cop-fscil "), std::string::npos) << merge;
  EXPECT_NE(merge.find(" --missing-only\n"), std::string::npos) << merge;
  EXPECT_EQ(std::system(("bash -n " + (folder.path() / "runs" / "slurm" / "array.sbatch").string()).c_str()), 0);

  // Cells 0 (prototype, seed 1) and 3 (cop-fscil, seed 2) have their result files.
  std::filesystem::create_directories(folder.path() / "runs" / "results");
  std::ofstream(folder.path() / "runs" / "results" / "prototype__simtex-mini__seed1.json") << "{}";
  std::ofstream(folder.path() / "runs" / "results" / "cop-fscil__simtex-mini__seed2.json") << "{}";
  const CommandResult missing = run_cli(command + " --missing-only");
  ASSERT_EQ(missing.exit_code, 0) << missing.output;
  EXPECT_NE(missing.output.find("2 of 4 cells"), std::string::npos) << missing.output;
  EXPECT_NE(read_text(folder.path() / "runs" / "slurm" / "array.sbatch").find("#SBATCH --array=1-2%3\n"), std::string::npos);

  // plan --missing-only, the merge job's check: the same two cells, and a failure while there are any.
  const std::string plan = "plan --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2 --out " + out;
  const CommandResult still_missing = run_cli(plan + " --missing-only");
  EXPECT_EQ(still_missing.exit_code, 1) << still_missing.output;
  EXPECT_NE(still_missing.output.find("2 cells"), std::string::npos) << still_missing.output;
  EXPECT_NE(still_missing.output.find("    1  prototype"), std::string::npos) << still_missing.output;
  EXPECT_NE(still_missing.output.find("    2  cop-fscil"), std::string::npos) << still_missing.output;

  expect_one_error_line(run_cli(command + " --submit", "PATH=/nonexistent"), "sbatch --parsable");
  expect_one_error_line(run_cli(command + " --sbatch-arg=account=abc"), "expected one sbatch option on one line");
  expect_one_error_line(run_cli(plan + " --cell 1"), "--cell: expected a run or sweep command");
}

TEST(Cli, ARunStoppedBySigtermKeepsItsCheckpointAndResumesToTheSameNumbers) {
  TemporaryDirectory folder;
  const std::string options = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 2 --no-cache --quiet";
  const auto stopped = folder.path() / "stopped";
  const auto checkpoint = stopped / "checkpoints" / "cop-fscil__simtex-mini__seed1.ckpt";
  const std::string script = fmt::format(
      "{} {} --out {} 2> {}/stderr & pid=$!; for i in $(seq 6000); do [ -f {} ] && break; kill -0 $pid || break; "
      "sleep 0.02; done; kill -TERM $pid; wait $pid",
      FSCIL_BENCH_EXECUTABLE, options, stopped.string(), folder.path().string(), checkpoint.string());
  const int status = std::system(("bash -c '" + script + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 143) << read_text(folder.path() / "stderr");
  EXPECT_NE(read_text(folder.path() / "stderr").find("fscil-bench: stopped by SIGTERM: finished sessions are kept"),
            std::string::npos);
  ASSERT_TRUE(std::filesystem::exists(checkpoint));
  EXPECT_FALSE(std::filesystem::exists(stopped / "results" / "cop-fscil__simtex-mini__seed1.json"));
  const CommandResult resumed = run_cli(options + " --resume " + stopped.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const CommandResult whole = run_cli(options + " --out " + (folder.path() / "whole").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_EQ(accuracies_in(stopped / "results" / "cop-fscil__simtex-mini__seed1.json"),
            accuracies_in(folder.path() / "whole" / "results" / "cop-fscil__simtex-mini__seed1.json"));
}

}  // namespace
}  // namespace fscil

namespace fscil {
namespace {

TEST(Cli, SaveModelKeepsEachRunsStateForPythonsTorchLoad) {
  TemporaryDirectory out;
  const CommandResult run = run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 2 --quiet "
                                    "--no-cache --save-model --out " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto model = out.path() / "models" / "prototype__simtex-mini__seed1.pt";
  ASSERT_TRUE(std::filesystem::exists(model));
  if (std::system(FSCIL_PYTHON " -c 'import torch' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << FSCIL_PYTHON << " has no torch (Debian python3-torch, installed by tools/bootstrap.sh)";
  }
  FILE* pipe = ::popen((std::string(FSCIL_PYTHON) + " -c \"import torch, sys; d = torch.load(sys.argv[1]); "
                        "print(len(d), int(d['seen_classes']), tuple(d['encoder.conv1.weight'].shape), "
                        "all(isinstance(v, torch.Tensor) for v in d.values()))\" " + model.string() + " 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ASSERT_EQ(::pclose(pipe), 0) << output;
  // 127 tensors (ResNet-18 and the classifier); simtex-mini's 20 classes all seen; the 7 x 7 stem
  // over its 5 channels.
  EXPECT_EQ(output, "127 20 (64, 5, 7, 7) True\n");
}

}  // namespace
}  // namespace fscil

namespace fscil {
namespace {

TEST(Cli, ConfigFileSetsRunOptionsAndTheCommandLineOverridesIt) {
  TemporaryDirectory folder;
  const auto config = folder.path() / "ablation.json";
  std::ofstream(config) << R"({"methods": "ablation", "dataset": "simtex-mini", "profile": "smoke", "seeds": "1-2",
                             "grid": {"shot": [1, 5]}})";
  const CommandResult planned = run_cli("plan --config " + config.string());
  ASSERT_EQ(planned.exit_code, 0) << planned.output;
  EXPECT_NE(planned.output.find("12 cells"), std::string::npos) << planned.output;  // 3 groups x 2 seeds x 2 shots
  const CommandResult overridden = run_cli("plan --config " + config.string() + " --seeds 7");
  ASSERT_EQ(overridden.exit_code, 0) << overridden.output;
  EXPECT_NE(overridden.output.find("6 cells"), std::string::npos) << overridden.output;
  EXPECT_NE(overridden.output.find("shot=5                        7"), std::string::npos) << overridden.output;
  expect_one_error_line(run_cli("--config " + config.string()), "\"grid\" needs the sweep, plan, run-cells or slurm subcommand");
  expect_one_error_line(run_cli("plan --config " + (folder.path() / "none.json").string()), "cannot read the file");
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
}

}  // namespace
}  // namespace fscil
