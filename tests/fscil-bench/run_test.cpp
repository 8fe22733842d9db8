// The run command: results and tables, shared bases and the stage cache, scoring on validation, determinism, protocols that never mix, features on demand, saved models.
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

TEST(Cli, SmokeRunWritesResultsAndReportRebuildsThem) {
  TemporaryDirectory out;
  // Where git sees no repository at run time, a result still names the commit its binary was built from.
  const CommandResult run = run_cli("--methods prototype --dataset simtex-mini --profile smoke --seeds 1,2 --threads 1 "
                                    "--quiet --no-cache --out " + out.path().string(),
                                    "GIT_DIR=/nonexistent");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("| prototype |"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed1.json"));
  std::ifstream result(out.path() / "results" / "prototype__simtex-mini__seed1.json");
  const std::string record(std::istreambuf_iterator<char>(result), {});
  EXPECT_NE(record.find(fmt::format("\"git_commit\": \"{}\"", built_commit())), std::string::npos) << record;
  EXPECT_NE(record.find(fmt::format("\"version\": \"{}\"", built_version())), std::string::npos) << record;
  EXPECT_NE(record.find("\"libtorch\": \"1."), std::string::npos) << record;
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed2.json"));
  std::ifstream csv(out.path() / "summary.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("method,dataset,split,selection,precision,seeds,AA,PD,ADR,acc_0,acc_1,acc_2,AA_std", 0), 0u) << header;
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
            "method,dataset,runs,mflops,params_m,session_trainable_m,it_ms,base_train_s,update_s,run_peak_mib,"
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

// A method we read without a runnable release (its registry entry's table_note) says so in its
// result file and beside its row in every table; a method run as its release runs it says nothing.
TEST(Cli, AMethodOfOurReadingIsMarkedInItsResultAndEveryTable) {
  TemporaryDirectory out;
  const CommandResult run = run_cli("--methods prototype,ldc --dataset simtex-mini --profile smoke --seeds 1 --threads 1 "
                                    "--quiet --no-cache --out " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto text_of = [](const std::filesystem::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_NE(text_of(out.path() / "results" / "ldc__simtex-mini__seed1.json").find("\"method_note\": \"our reading of LDC"),
            std::string::npos);
  EXPECT_EQ(text_of(out.path() / "results" / "prototype__simtex-mini__seed1.json").find("method_note"), std::string::npos);
  EXPECT_NE(run.output.find("| ldc ‡ |"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("| prototype |"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("‡ ldc: our reading of LDC"), std::string::npos) << run.output;
  EXPECT_NE(text_of(out.path() / "results.tex").find("ldc$^\\ddagger$"), std::string::npos);
  EXPECT_NE(text_of(out.path() / "summary.csv").find(",\"our reading of LDC"), std::string::npos);

  // A result file from before the note gets the one this program has for its method.
  const std::filesystem::path ldc_file = out.path() / "results" / "ldc__simtex-mini__seed1.json";
  std::string record = text_of(ldc_file);
  const std::size_t line = record.find("  \"method_note\"");
  ASSERT_NE(line, std::string::npos);
  record.erase(line, record.find('\n', line) + 1 - line);
  std::ofstream(ldc_file) << record;
  std::filesystem::remove(out.path() / "summary.csv");
  const CommandResult report = run_cli("report --results " + out.path().string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_NE(report.output.find("| ldc ‡ |"), std::string::npos) << report.output;
  EXPECT_NE(text_of(out.path() / "summary.csv").find(",\"our reading of LDC"), std::string::npos);
}

// Issue 70: an ETA per stage, none for the command.
TEST(Cli, ACommandSaysAfterEachRunHowManyAreDoneAndWhyItCannotSayHowLongIsLeftWithoutRates) {
  TemporaryDirectory out;
  const CommandResult run = run_cli("--methods prototype --seeds 1-2 --dataset simtex-mini --profile smoke --threads 1 "
                                    "--no-cache --out " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("[fscil-bench]   1 of 2 runs done in 0:00:"), std::string::npos) << run.output;
  // Without a cache there are no stored rates, and a run never calibrates for its progress line.
  EXPECT_NE(run.output.find("(no time to go: `fscil-bench plan` once stores this machine's rates)"), std::string::npos);
  EXPECT_NE(run.output.find("[fscil-bench]   2 of 2 runs done in 0:00:"), std::string::npos);
}

// Issue 71: the methods' test-oracle epoch scoring would let removed classes' rows compete.
TEST(Cli, ClassVariableSessionsRefuseEpochsChosenOnTest) {
  TemporaryDirectory out;
  const CommandResult run = run_cli("--methods prototype --seeds 1 --dataset simtex-mini --profile smoke --threads 1 "
                                    "--no-cache --set removal=fciac --selection test-oracle --out " + out.path().string());
  EXPECT_NE(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("--selection test-oracle cannot be combined with removal=fciac"), std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results")) << "nothing ran";
}

TEST(Cli, VariantsSharingABaseGiveTheAccuraciesOfTheirOwnRuns) {
  TemporaryDirectory together, alone;
  const std::string common = " --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out ";
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

TEST(Cli, ABaseFromTheStageCacheGivesTheScoresOfARunThatTrainedItAndAnyMethodParameterMissesIt) {
  TemporaryDirectory cache, cold, warm, sweep_cell, other_lr, uncached, after_damage;
  const auto stages = cache.path() / "stages";
  const std::string common = " --methods prototype --dataset simtex-mini --profile smoke --threads 1 --cache-dir " +
                             cache.path().string() + " --out ";
  const auto result = [](const TemporaryDirectory& out) { return out.path() / "results" / "prototype__simtex-mini__seed1.json"; };
  constexpr const char* kHit = "base session from the stage cache";

  const CommandResult first = run_cli(common + cold.path().string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_EQ(first.output.find(kHit), std::string::npos);
  ASSERT_EQ(files_in(stages), 2u);  // its base and its pretraining (ldc's too)
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
  EXPECT_EQ(files_in(stages), 4u);
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

// Issue 41, item 1: pits-sc's pretraining, filed in the stage cache, serves a later cpi command,
// to the numbers of a cpi that trained its own; a pretraining value misses it. (Sharing within a
// command is the same store: tests/methods/shared_stages_test.cpp, and the reference protocol's
// `--methods all` holds cpi's rows.)
TEST(Cli, PitsScsPretrainingServesALaterCpiToTheNumbersOfACpiThatTrainedIt) {
  TemporaryDirectory cold, cache, first, warm, other;
  const std::string common = " --dataset simtex-mini --profile smoke --threads 1 --quiet --out ";
  const std::string cached = " --cache-dir " + cache.path().string();
  const auto cpi_result = [](const TemporaryDirectory& out) {
    return out.path() / "results" / "cop-fscil_cpi__simtex-mini__seed1.json";
  };
  const auto base_training = [](const std::filesystem::path& file) {
    std::ifstream record(file);
    const std::string text(std::istreambuf_iterator<char>(record), {});
    const std::string key = "\"base_training\": \"";
    const std::size_t at = text.find(key);
    if (at == std::string::npos) return std::string();
    const std::size_t value = at + key.size();
    return text.substr(value, text.find('"', value) - value);
  };

  ASSERT_EQ(run_cli("--methods cop-fscil/cpi --no-cache" + common + cold.path().string()).exit_code, 0);
  const std::string trained = scores_in(cpi_result(cold));
  EXPECT_EQ(std::count(trained.begin(), trained.end(), ':'), 3 * 7);
  EXPECT_EQ(base_training(cpi_result(cold)), "");

  ASSERT_EQ(run_cli("--methods pits-sc" + cached + common + first.path().string()).exit_code, 0);
  EXPECT_EQ(files_in(cache.path() / "stages"), 2u);  // its base and its pretraining
  const CommandResult later = run_cli("--methods cop-fscil/cpi" + cached + common + warm.path().string());
  ASSERT_EQ(later.exit_code, 0) << later.output;
  EXPECT_EQ(scores_in(cpi_result(warm)), trained);
  EXPECT_EQ(base_training(cpi_result(warm)), "pits-sc pretraining from the stage cache");

  const CommandResult changed =
      run_cli("--methods cop-fscil/cpi --set pretrain_lr=0.05" + cached + common + other.path().string());
  ASSERT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_EQ(base_training(cpi_result(other)), "");
  EXPECT_NE(scores_in(cpi_result(other)), trained);
}

// Issue 42, item 1: a loss that is not finite fails the run in one line that says where and with
// what, keeps the runs finished before it, and leaves no base of it in the stage cache. A stage
// that ended well before the divergence (pits-sc's pretraining: pit_lr acts only after it) is
// filed as it ended, as any run with the same pretraining would file it (issue 68).
TEST(Cli, ADivergedTrainingFailsTheRunAndCachesNothingOfWhatDiverged) {
  TemporaryDirectory cache, out, hot;
  const std::string common = " --dataset simtex-mini --profile smoke --threads 1 --quiet --cache-dir " +
                             cache.path().string();
  const CommandResult diverged =
      run_cli("--methods prototype,pits-sc" + common + " --set pit_lr=1e30 --out " + out.path().string());
  expect_one_error_line(diverged, "pseudo-incremental epoch 1 of 1: training diverged (loss ");
  EXPECT_NE(diverged.output.find("lr 1e+30"), std::string::npos) << diverged.output;
  EXPECT_EQ(diverged.exit_code, 1);
  // prototype finished before pits-sc began: its result and its base stay; pits-sc's do not exist.
  EXPECT_TRUE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed1.json"));
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results" / "pits-sc__simtex-mini__seed1.json"));
  EXPECT_EQ(files_in(cache.path() / "stages"), 3u);  // prototype's base and pretraining, pits-sc's pretraining

  const CommandResult too_hot = run_cli("--methods prototype" + common + " --set temperature=1e30 --out " +
                                        hot.path().string());
  expect_one_error_line(too_hot, "epoch 1 of 3: training diverged (loss ");
  // Past float's range a value is refused by name before anything trains.
  expect_one_error_line(run_cli("--methods prototype" + common + " --set temperature=1e308 --out " +
                                hot.path().string()),
                        "parameter temperature='1e308': expected a number of at most 3.40282e+38 in magnitude");
  EXPECT_FALSE(std::filesystem::exists(hot.path() / "results" / "prototype__simtex-mini__seed1.json"));
  EXPECT_EQ(files_in(cache.path() / "stages"), 3u);
}

TEST(Cli, EvaluateOnValidationScoresEveryClassesValidationSplitAndSaysSoEverywhere) {
  TemporaryDirectory out, test_out;
  const std::string common = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache";
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
  EXPECT_EQ(row.rfind("cop-fscil,simtex-mini,validation,last,fp32,1,", 0), 0u) << row;
  // Validation-scored runs never stand beside the paper's test numbers or a test run.
  expect_one_error_line(run_cli("report --paper --results " + out.path().string()), "test-split numbers");
  ASSERT_EQ(run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out " +
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
  const std::string common = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache";
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

TEST(Cli, RunsOfAnotherProtocolNeverShareAnOutOrATable) {
  TemporaryDirectory out;
  const std::string common = " --dataset simtex-mini --profile smoke --quiet --no-cache --out " + out.path().string();
  ASSERT_EQ(run_cli("--methods prototype --threads 1" + common).exit_code, 0);
  const auto result = out.path() / "results" / "prototype__simtex-mini__seed1.json";
  std::ifstream in(result);
  const std::string written((std::istreambuf_iterator<char>(in)), {});
  ASSERT_NE(written.find("\"shot\": \"5\""), std::string::npos);

  expect_one_error_line(run_cli("--methods prototype --threads 1 --seeds 2 --set shot=2" + common),
                        "holds a run that cannot share a table with this one (shot=5 against shot=2)");
  expect_one_error_line(run_cli("--methods prototype --seeds 2 --threads 2" + common), "(threads 1 against 2)");
  expect_one_error_line(run_cli("--methods prototype,prototype --threads 1" + common), "'prototype' is named twice");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results" / "prototype__simtex-mini__seed2.json"));
  std::ifstream again(result);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), {}), written) << "an earlier result changed";

  // Mixed by hand: report refuses the folder rather than average a 5-shot and a 2-shot run.
  std::string other = written;
  for (const std::string from : {"\"shot\": \"5\"", "\"seed\": 1"}) {
    const std::string to = from == "\"seed\": 1" ? "\"seed\": 2" : "\"shot\": \"2\"";
    for (auto at = other.find(from); at != std::string::npos; at = other.find(from)) other.replace(at, from.size(), to);
  }
  std::ofstream(out.path() / "results" / "prototype__simtex-mini__seed2.json") << other;
  const CommandResult report = run_cli("report --results " + out.path().string());
  expect_one_error_line(report, "runs that cannot share a table (shot=5 against shot=2)");
}

// --precision bf16: other scores than fp32's, said in the result file and every table, never in
// one --out with fp32 runs, and what a rerun of its result file runs again.
TEST(Cli, Bf16IsARunOfItsOwnInEveryFileAndTable) {
  TemporaryDirectory bf16, fp32, again;
  const std::string common = " --methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache --threads 1";
  const auto result = [](const TemporaryDirectory& out) { return out.path() / "results" / "prototype__simtex-mini__seed1.json"; };
  expect_one_error_line(run_cli("--precision fp16" + common + " --out " + bf16.path().string()),
                        "--precision 'fp16': expected fp32 or bf16");
  ASSERT_EQ(run_cli("--precision bf16" + common + " --out " + bf16.path().string()).exit_code, 0);
  ASSERT_EQ(run_cli(common + " --out " + fp32.path().string()).exit_code, 0);
  EXPECT_NE(scores_in(result(bf16)), scores_in(result(fp32)));
  EXPECT_NE(read_text(result(bf16)).find("\"precision\": \"bf16\""), std::string::npos);
  EXPECT_EQ(read_text(result(fp32)).find("\"precision\""), std::string::npos) << "fp32 runs keep their identity";
  EXPECT_NE(read_text(bf16.path() / "summary.csv").find(",last,bf16,1,"), std::string::npos);
  EXPECT_NE(read_text(bf16.path() / "sessions.csv").find(",last,bf16,1,"), std::string::npos);
  EXPECT_NE(read_text(bf16.path() / "results.tex").find("test split, encoder in bf16"), std::string::npos);
  expect_one_error_line(run_cli(common + " --seeds 2 --out " + bf16.path().string()), "(made in bf16 against fp32)");

  ASSERT_EQ(run_cli("rerun " + result(bf16).string() + " --quiet --no-cache --out " + again.path().string()).exit_code, 0);
  EXPECT_EQ(scores_in(result(again)), scores_in(result(bf16))) << "the rerun ran in fp32?";
}

TEST(Cli, FeaturesOnDemandAndRecomputedActivationsGiveTheScoresOfTheDefaultRun) {
  TemporaryDirectory in_memory, on_demand, recomputed, limited;
  // pits-sc reads features by batch, the validation split and raw signals for its mixtures.
  const std::string common = " --methods pits-sc --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache";
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

TEST(Cli, SaveModelKeepsEachRunsStateForPythonsTorchLoad) {
  TemporaryDirectory out;
  const CommandResult run = run_cli("--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet "
                                    "--no-cache --save-model --out " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto model = out.path() / "models" / "prototype__simtex-mini__seed1.pt";
  ASSERT_TRUE(std::filesystem::exists(model));
  if (std::system(FSCIL_PYTHON " -c 'import torch' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << FSCIL_PYTHON << " has no torch (Debian python3-torch, installed by tools/bootstrap.sh)";
  }
  FILE* pipe = ::popen((std::string(FSCIL_PYTHON) + " -c \"import torch, sys; m = torch.load(sys.argv[1]); d = m['state']; "
                        "print(len(d), int(d['seen_classes.count']), tuple(d['encoder.conv1.weight'].shape), "
                        "all(isinstance(v, torch.Tensor) for v in d.values()), m['metadata']['method'], "
                        "m['metadata']['input_shape'], len(m['metadata']['class_order']))\" " + model.string() + " 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ASSERT_EQ(::pclose(pipe), 0) << output;
  // 127 tensors (ResNet-18 and the classifier); simtex-mini's 20 classes all seen; the 7 x 7 stem
  // over its 5 channels; what the model is, its 5 x 64 x 24 input and the class of each output.
  EXPECT_EQ(output, "127 20 (64, 5, 7, 7) True prototype [5, 64, 24] 20\n");
}

}  // namespace
}  // namespace fscil
