#include "reports/summary_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "reports/report_error.h"
#include "reports/run_record.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

RunRecord record_of(const std::string& method, std::uint64_t seed, std::vector<double> accuracies) {
  RunRecord record;
  record.method = method;
  record.dataset = "simtex";
  record.profile = "fast";
  record.seed = seed;
  record.threads = 2;
  record.parameters = {{"pretrain_epochs", "8"}};
  record.machine = {{"host", "test"}, {"libtorch", "1.13.0"}};
  record.version = "0.1.0";
  record.git_commit = "abc";
  record.dataset_key = "0123";
  for (std::size_t s = 0; s < accuracies.size(); ++s) {
    SessionRecord session;
    session.session = static_cast<int>(s);
    session.seen_classes = 10 + 5 * static_cast<int>(s);
    session.accuracy.all = accuracies[s];
    session.accuracy.base = accuracies[s] + 1;
    session.accuracy.samples = 100;
    session.train_seconds = 1.5;
    record.sessions.push_back(session);
  }
  record.total_seconds = 12.5;
  record.peak_resident_bytes = 1 << 20;
  return record;
}

TEST(RunRecord, RoundTripsThroughJson) {
  const RunRecord original = record_of("cop-fscil/cpi+pspc", 3, {90, 80.5, 70.25});
  const RunRecord copy = run_record_from_json_text(to_json_text(original), "memory");
  EXPECT_EQ(copy.method, original.method);
  EXPECT_EQ(copy.seed, 3u);
  EXPECT_EQ(copy.parameters, original.parameters);
  EXPECT_EQ(copy.machine, original.machine);
  EXPECT_EQ(copy.version, "0.1.0");
  EXPECT_EQ(copy.git_commit, "abc");
  EXPECT_EQ(copy.session_accuracies(), original.session_accuracies());
  EXPECT_DOUBLE_EQ(copy.sessions[1].accuracy.base, 81.5);
  EXPECT_EQ(copy.peak_resident_bytes, 1 << 20);
  EXPECT_EQ(copy.replay_samples, 0);

  RunRecord replaying = original;
  replaying.replay_samples = 400;
  replaying.replay_bytes = 400 * 7680 * 4;
  const RunRecord replay_copy = run_record_from_json_text(to_json_text(replaying), "memory");
  EXPECT_EQ(replay_copy.replay_samples, 400);
  EXPECT_EQ(replay_copy.replay_bytes, 400 * 7680 * 4);

  RunRecord costed = original;
  costed.inference = {54'527'488, 5'216'576, 2'560, 2.5e-4, 128};
  const std::string costed_text = to_json_text(costed);
  EXPECT_NE(costed_text.find("\"flops\": 109054976"), std::string::npos);
  const RunRecord costed_copy = run_record_from_json_text(costed_text, "memory");
  EXPECT_EQ(costed_copy.inference.macs, 54'527'488);
  EXPECT_EQ(costed_copy.inference.parameters, 5'216'576);
  EXPECT_EQ(costed_copy.inference.trainable_parameters, 2'560);
  EXPECT_DOUBLE_EQ(costed_copy.inference.seconds_per_sample, 2.5e-4);
  EXPECT_EQ(costed_copy.inference.batch, 128);
  EXPECT_EQ(run_record_file_name(original), "cop-fscil_cpi_pspc__simtex__seed3.json");
}

// A diverged loss is NaN; JSON writes it as null, and the file must still read.
TEST(RunRecord, NanDiagnosticsSurviveTheResultFile) {
  RunRecord diverged = record_of("pits-sc", 1, {50, 40});
  diverged.sessions[1].diagnostics = {{"session_ce_mean", std::nan("")}, {"pspc_effective_shots", 4.5}};
  const RunRecord copy = run_record_from_json_text(to_json_text(diverged), "memory");
  EXPECT_TRUE(std::isnan(copy.sessions[1].diagnostics.at("session_ce_mean")));
  EXPECT_EQ(copy.sessions[1].diagnostics.at("pspc_effective_shots"), 4.5);
}

// Found by fuzzing: a count of 3e88 was converted to an integer with undefined behaviour.
TEST(RunRecord, CountsAreWholeNumbersInRange) {
  const std::string text = to_json_text(record_of("prototype", 1, {50, 40}));
  for (const auto& [from, to] : {std::pair{"\"peak_resident_bytes\": 1048576", "\"peak_resident_bytes\": 3.07e88"},
                                 {"\"threads\": 2", "\"threads\": 1.5"},
                                 {"\"seed\": 1", "\"seed\": -1"},
                                 {"\"test_samples\": 100", "\"test_samples\": 1e300"},
                                 {"\"session\": 1", "\"session\": 2147483648"}}) {
    std::string odd = text;
    ASSERT_NE(odd.find(from), std::string::npos) << from;
    odd.replace(odd.find(from), std::string(from).size(), to);
    try {
      run_record_from_json_text(odd, "odd.json");
      ADD_FAILURE() << to << " was accepted";
    } catch (const ReportError& error) {
      EXPECT_NE(std::string(error.what()).find("odd.json: "), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(", expected a whole number from "), std::string::npos) << error.what();
    }
  }
}

TEST(RunRecord, BadFilesNameThemselves) {
  TemporaryDirectory directory;
  save_run_record(directory.path(), record_of("prototype", 1, {50, 40}));
  EXPECT_EQ(load_run_records(directory.path()).size(), 1u);
  std::ofstream(directory.path() / "results" / "broken.json") << "{\"schema\": 1, \"method\": ";
  try {
    load_run_records(directory.path());
    FAIL() << "expected an error";
  } catch (const ReportError& error) {
    EXPECT_NE(std::string(error.what()).find("broken.json: not a valid result file"), std::string::npos);
  }
  EXPECT_THROW(load_run_records(directory.path() / "missing"), ReportError);
}

TEST(SummaryTable, AveragesSeedsAndComputesMetricsPerSeed) {
  const SummaryTable table = summarize_runs(
      {record_of("prototype", 1, {90, 80, 70}), record_of("prototype", 2, {80, 80, 60}), record_of("pits-sc", 1, {95, 90, 85})});
  ASSERT_EQ(table.rows.size(), 2u);
  const SummaryRow& prototype = table.rows[0];
  EXPECT_EQ(prototype.seeds, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_DOUBLE_EQ(prototype.session_accuracy[0].mean, 85.0);
  EXPECT_NEAR(prototype.session_accuracy[0].std, std::sqrt(50.0), 1e-12);
  // Two seeds: t_{0.975, 1} = 12.706 times s / sqrt(2) = 12.706 x 5.
  EXPECT_NEAR(prototype.session_accuracy[0].ci95, 12.7062 * 5.0, 1e-9);
  EXPECT_EQ(table.rows[1].session_accuracy[0].ci95, 0.0);  // one seed: no interval
  EXPECT_DOUBLE_EQ(prototype.average_accuracy.mean, (80.0 + 220.0 / 3) / 2);
  EXPECT_DOUBLE_EQ(prototype.performance_drop.mean, 20.0);
  const double adr_seed1 = 50.0 * (10.0 / 90 + 10.0 / 80), adr_seed2 = 50.0 * (0.0 + 20.0 / 80);
  EXPECT_NEAR(prototype.average_drop_rate.mean, (adr_seed1 + adr_seed2) / 2, 1e-12);
  EXPECT_TRUE(table.several_seeds());
  EXPECT_THROW(summarize_runs({record_of("prototype", 1, {90, 80}), record_of("prototype", 1, {90, 80})}), ReportError);
  EXPECT_THROW(summarize_runs({record_of("prototype", 1, {90, 80}), record_of("prototype", 2, {90, 80, 70})}), ReportError);
}

TEST(SummaryTable, CsvHoldsMeansStdAndConfidenceColumns) {
  const std::string csv = render_csv(summarize_runs({record_of("prototype", 1, {90, 80}), record_of("prototype", 2, {80, 70})}));
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header, "method,dataset,split,seeds,AA,PD,ADR,acc_0,acc_1,AA_std,PD_std,ADR_std,acc_0_std,acc_1_std,"
                    "AA_ci95,PD_ci95,ADR_ci95,acc_0_ci95,acc_1_ci95");
  EXPECT_NE(csv.find(",63.5310,63.5310\n"), std::string::npos) << csv;  // 12.7062 x 7.0711 / 1.4142
  EXPECT_NE(csv.find("prototype,simtex,test,1 2,80.0000,10.0000,"), std::string::npos);
  const std::string single = render_csv(summarize_runs({record_of("prototype", 1, {90, 80})}));
  EXPECT_EQ(single, "method,dataset,split,seeds,AA,PD,ADR,acc_0,acc_1\nprototype,simtex,test,1,85.0000,10.0000,11.1111,"
                    "90.0000,80.0000\n");
}

TEST(SummaryTable, SessionsCsvHoldsBaseNovelAndHarmonicMeanPerSession) {
  RunRecord first = record_of("orco", 1, {90, 80}), second = record_of("orco", 2, {80, 70});
  first.sessions[1].accuracy.novel = 40;
  first.sessions[1].accuracy.harmonic = 53.125;
  second.sessions[1].accuracy.novel = 60;
  second.sessions[1].accuracy.harmonic = 64.5;
  EXPECT_EQ(render_sessions_csv(summarize_runs({first, second})),
            "method,dataset,split,seeds,session,accuracy,accuracy_std,base,base_std,novel,novel_std,harmonic_mean,"
            "harmonic_mean_std\n"
            "orco,simtex,test,1 2,0,85.0000,7.0711,86.0000,7.0711,,,,\n"
            "orco,simtex,test,1 2,1,75.0000,7.0711,76.0000,7.0711,50.0000,14.1421,58.8125,8.0433\n");
}

TEST(SummaryTable, SaysWhichSplitWasScoredAndNeverMixesTestWithValidation) {
  RunRecord on_validation = record_of("prototype", 2, {80, 70});
  on_validation.evaluated_on = "validation";
  EXPECT_THROW(summarize_runs({record_of("prototype", 1, {90, 80}), on_validation}), ReportError);
  RunRecord other_seed = record_of("prototype", 3, {85, 75});
  other_seed.evaluated_on = "validation";
  const SummaryTable table = summarize_runs({on_validation, other_seed});
  EXPECT_EQ(table.evaluated_on, "validation");
  EXPECT_NE(render_csv(table).find("prototype,simtex,validation,2 3,"), std::string::npos);
  EXPECT_NE(render_markdown(table).find("### simtex, validation split"), std::string::npos);
  EXPECT_NE(render_latex(table).find("Comparison on simtex, validation split"), std::string::npos);
  // A result file says what it was scored on, and one that says nothing was scored on test.
  EXPECT_EQ(run_record_from_json_text(to_json_text(on_validation), "x").evaluated_on, "validation");
}

TEST(SummaryTable, LatexAndMarkdownMarkTheBestOfEachColumn) {
  const SummaryTable table = summarize_runs({record_of("prototype", 1, {90, 70}), record_of("pits-sc", 1, {95, 65})});
  const std::string latex = render_latex(table);
  EXPECT_NE(latex.find("pits-sc & \\textbf{95.00} & 65.00"), std::string::npos) << latex;
  EXPECT_NE(latex.find("prototype & 90.00 & \\textbf{70.00} & \\textbf{20.00} & \\textbf{80.00}"), std::string::npos) << latex;
  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| method | 0 | 1 | PD | AA | ADR |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| pits-sc | **95.00** | 65.00 | 30.00 | **80.00** |"), std::string::npos) << markdown;
}

TEST(SummaryTable, LatexEscapesNamesAndResultFilesRefuseNamesNoTableCanHold) {
  RunRecord lab = record_of("cop-fscil/cpi+pspc", 1, {90, 70});
  lab.dataset = "lab_2024";
  const std::string latex = render_latex(summarize_runs({lab}));
  EXPECT_NE(latex.find("Comparison on lab\\_2024, test split"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\ncop-fscil/cpi+pspc & "), std::string::npos) << latex;

  std::string text = to_json_text(record_of("prototype", 1, {90, 70}));
  text.replace(text.find("\"prototype\""), 11, "\"proto\\ntype & 100% best\"");
  try {
    run_record_from_json_text(text, "odd.json");
    FAIL() << "a method name with a newline and LaTeX specials was accepted";
  } catch (const ReportError& error) {
    EXPECT_STREQ(error.what(),
                 "odd.json: method 'proto\\ntype & 100% best', expected letters, digits, '_', '.', '+', '/' or '-'");
  }
}

}  // namespace
}  // namespace fscil
