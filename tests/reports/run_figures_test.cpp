#include "reports/run_figures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/error.h"
#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

using Values = std::vector<double>;

// Element-wise equality where NaN (a gap) equals NaN.
void expect_values(const Values& actual, const Values& expected, const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::isnan(expected[i])) {
      EXPECT_TRUE(std::isnan(actual[i])) << what << " [" << i << "] = " << actual[i];
    } else {
      EXPECT_DOUBLE_EQ(actual[i], expected[i]) << what << " [" << i << "]";
    }
  }
}

// orco on simtex, two seeds of three sessions: all 85, 75, 65 on average; base 1 point higher;
// novel 0 as recorded in session 0, then 50 and 40; harmonic 0, then 60 and 52.
RunRecord orco_seed(std::uint64_t seed, const Values& all, const Values& novel, const Values& harmonic) {
  RunRecord record = run_with_accuracies("orco", "simtex", seed, all);
  for (std::size_t s = 0; s < all.size(); ++s) {
    record.sessions[s].accuracy.base = all[s] + 1;
    record.sessions[s].accuracy.novel = novel[s];
    record.sessions[s].accuracy.harmonic = harmonic[s];
  }
  return record;
}

SummaryTable sessions_table(bool with_oracle) {
  std::vector<RunRecord> records = {orco_seed(1, {90, 80, 70}, {0, 40, 30}, {0, 55, 45}),
                                    orco_seed(2, {80, 70, 60}, {0, 60, 50}, {0, 65, 59}),
                                    run_with_accuracies("prototype", "simtex-lmt", 1, {50, 40, 30})};
  if (with_oracle) {
    records.push_back(in_cell(orco_seed(1, {95, 85, 75}, {0, 50, 40}, {0, 60, 50}), {}, "test-oracle"));
  }
  return summarize_runs(records);
}

TEST(RunFigures, SessionFigureDrawsTheSummaryMeansOfEachRowOfItsDataset) {
  const SummaryTable table = sessions_table(true);
  const Figure all = session_accuracy_figure(table, "simtex", SessionMetric::all);
  EXPECT_NO_THROW(require_valid_figure(all));
  EXPECT_EQ(all.name, "sessions_simtex_all");
  EXPECT_EQ(all.x_categories, (std::vector<std::string>{"0", "1", "2"}));
  ASSERT_EQ(all.series.size(), 2u) << "prototype ran on simtex-lmt";
  EXPECT_EQ(all.series[0].label, "orco");
  expect_values(all.series[0].x, {0, 1, 2}, "x");
  expect_values(all.series[0].y, {85, 75, 65}, "orco");
  const SummaryRow& orco = table.rows[0];
  for (std::size_t s = 0; s < 3; ++s) EXPECT_EQ(all.series[0].y[s], orco.session_accuracy[s].mean);
  EXPECT_EQ(all.series[1].label, "orco (selected on test (inflated))");
  expect_values(all.series[1].y, {95, 85, 75}, "oracle");
  expect_values(session_accuracy_figure(table, "simtex", SessionMetric::base).series[0].y, {86, 76, 66}, "base");
}

TEST(RunFigures, SessionZeroHasNoNovelAccuracyOrHarmonicMean) {
  const SummaryTable table = sessions_table(false);
  const Figure novel = session_accuracy_figure(table, "simtex", SessionMetric::novel);
  EXPECT_EQ(novel.name, "sessions_simtex_novel");
  ASSERT_EQ(novel.series.size(), 1u);
  expect_values(novel.series[0].y, {NAN, 50, 40}, "novel");  // (40 + 60) / 2, (30 + 50) / 2
  const Figure harmonic = session_accuracy_figure(table, "simtex", SessionMetric::harmonic);
  EXPECT_EQ(harmonic.name, "sessions_simtex_harmonic");
  expect_values(harmonic.series[0].y, {NAN, 60, 52}, "harmonic");  // (55 + 65) / 2, (45 + 59) / 2
  EXPECT_NO_THROW(require_valid_figure(novel));
  EXPECT_NO_THROW(require_valid_figure(harmonic));
}

TEST(RunFigures, AFigureWithARowChosenOnTestSaysItIsInflated) {
  const std::string whiskers = "whiskers: one standard deviation over seeds either side";  // orco's two seeds
  EXPECT_EQ(session_accuracy_figure(sessions_table(false), "simtex", SessionMetric::all).note, whiskers);
  EXPECT_EQ(session_accuracy_figure(sessions_table(true), "simtex", SessionMetric::all).note,
            "selected on test (inflated); " + whiskers);
  EXPECT_EQ(ablation_figure(sessions_table(true), "simtex", "ablation_simtex").note,
            "selected on test (inflated); " + whiskers);
  EXPECT_EQ(ablation_figure(sessions_table(false), "simtex", "ablation_simtex").note, whiskers);
  // The oracle run is of simtex: the simtex-lmt figure carries no caveat.
  EXPECT_EQ(session_accuracy_figure(sessions_table(true), "simtex-lmt", SessionMetric::all).note, "");
}

TEST(RunFigures, NamesAreFileStemsWhateverTheDatasetIsCalled) {
  RunRecord record = run_with_accuracies("cop-fscil/cpi+pspc", "Lab.2024", 1, {90, 80});
  const SummaryTable table = summarize_runs({record});
  for (const SessionMetric metric : {SessionMetric::all, SessionMetric::base, SessionMetric::novel,
                                     SessionMetric::harmonic}) {
    const Figure figure = session_accuracy_figure(table, "Lab.2024", metric);
    EXPECT_NO_THROW(require_valid_figure(figure)) << figure.name;
    EXPECT_EQ(figure.name.rfind("sessions_lab_2024_", 0), 0u) << figure.name;
  }
  const Figure ablation = ablation_figure(table, "Lab.2024", "Ablation Lab.2024");
  EXPECT_EQ(ablation.name, "ablation_lab_2024");
  EXPECT_NO_THROW(require_valid_figure(ablation));
  EXPECT_EQ(ablation.x_categories, (std::vector<std::string>{"cop-fscil/cpi+pspc"}));
  ASSERT_EQ(ablation.series.size(), 2u);
  expect_values(ablation.series[0].y, {85}, "AA");
  expect_values(ablation.series[1].y, {10}, "PD");
}

// A sweep over pic_weight with values 0, 0.1, 1: AA 84 at 0 and 75 at 1 for cop-fscil, 86 at 0.1
// for orco; cop-fscil with shot 5 besides is a line of its own.
SummaryTable lambda_sweep() {
  return summarize_runs({in_cell(run_with_accuracies("cop-fscil", "simtex", 1, {90, 60}), {{"pic_weight", "1"}}),
                         in_cell(run_with_accuracies("cop-fscil", "simtex", 1, {96, 72}), {{"pic_weight", "0"}}),
                         in_cell(run_with_accuracies("orco", "simtex", 1, {98, 74}), {{"pic_weight", "0.1"}}),
                         in_cell(run_with_accuracies("cop-fscil", "simtex", 1, {50, 50}), {{"pic_weight", "5"}}),
                         in_cell(run_with_accuracies("cop-fscil", "simtex", 1, {80, 70}),
                                 {{"pic_weight", "0"}, {"shot", "5"}}),
                         in_cell(run_with_accuracies("cop-fscil", "simtex-lmt", 1, {10, 5}), {{"pic_weight", "0.1"}}),
                         run_with_accuracies("prototype", "simtex", 1, {70, 60})});
}

TEST(RunFigures, GridFigurePutsEachCellAtItsValueWithALinePerMethod) {
  const std::vector<std::string> values = {"0", "0.1", "1"};
  const Figure figure = grid_metric_figure(lambda_sweep(), "simtex", "pic_weight", values, "AA", "lambda_AA",
                                           "AA against lambda");
  EXPECT_NO_THROW(require_valid_figure(figure));
  EXPECT_EQ(figure.name, "lambda_aa");
  EXPECT_EQ(figure.x_label, "pic_weight");
  EXPECT_EQ(figure.y_label, "AA (%)");
  EXPECT_TRUE(figure.x_categories.empty()) << "0, 0.1 and 1: a linear axis";
  EXPECT_FALSE(figure.x_log);
  EXPECT_EQ(figure.note, "");
  // pic_weight 5 is not among the values, simtex-lmt not the dataset, prototype not swept.
  ASSERT_EQ(figure.series.size(), 3u);
  EXPECT_EQ(figure.series[0].label, "cop-fscil");
  expect_values(figure.series[0].x, {0, 1}, "cop-fscil x");  // left to right, though 1 ran first
  expect_values(figure.series[0].y, {84, 75}, "cop-fscil AA");
  EXPECT_EQ(figure.series[1].label, "orco");
  expect_values(figure.series[1].x, {0.1}, "orco x");
  expect_values(figure.series[1].y, {86}, "orco AA");
  EXPECT_EQ(figure.series[2].label, "cop-fscil [shot=5]");
  expect_values(figure.series[2].x, {0}, "shot 5 x");
  expect_values(figure.series[2].y, {75}, "shot 5 AA");

  const Figure pd = grid_metric_figure(lambda_sweep(), "simtex", "pic_weight", values, "PD", "lambda_pd", "PD");
  expect_values(pd.series[0].y, {24, 30}, "PD");
  const Figure acc0 = grid_metric_figure(lambda_sweep(), "simtex", "pic_weight", values, "Acc0", "lambda_acc0", "");
  EXPECT_EQ(acc0.y_label, "session 0 accuracy (%)");
  expect_values(acc0.series[0].y, {96, 90}, "Acc0");
  const Figure adr = grid_metric_figure(lambda_sweep(), "simtex", "pic_weight", values, "ADR", "lambda_adr", "");
  EXPECT_EQ(adr.y_label, "ADR");
  expect_values(adr.series[0].y, {25, 100.0 * 30 / 90}, "ADR");
  EXPECT_THROW(grid_metric_figure(lambda_sweep(), "simtex", "pic_weight", values, "aa", "x", ""), ReportError);
}

TEST(RunFigures, GridFigureDrawsRowsChosenOnTestAsTheirOwnLineAndSaysSo) {
  const SummaryTable table = summarize_runs(
      {in_cell(run_with_accuracies("orco", "simtex", 1, {98, 74}), {{"pic_weight", "0.1"}}),
       in_cell(run_with_accuracies("orco", "simtex", 1, {99, 79}), {{"pic_weight", "0.1"}}, "test-oracle")});
  const Figure figure = grid_metric_figure(table, "simtex", "pic_weight", {"0", "0.1"}, "AA", "lambda_aa", "");
  EXPECT_EQ(figure.note, "selected on test (inflated)");
  ASSERT_EQ(figure.series.size(), 2u);
  EXPECT_EQ(figure.series[1].label, "orco (selected on test (inflated))");
  expect_values(figure.series[1].x, {0.1}, "oracle x");
  expect_values(figure.series[1].y, {89}, "oracle AA");
}

// In a sweep over selection the legend names the selection once, by the row's label.
TEST(RunFigures, LegendsOfASelectionSweepNameTheSelectionOnce) {
  const SummaryTable table = summarize_runs(
      {in_cell(run_with_accuracies("orco", "simtex", 1, {98, 74}), {{"selection", "last"}}),
       in_cell(run_with_accuracies("orco", "simtex", 1, {99, 79}), {{"selection", "test-oracle"}}, "test-oracle")});
  const Figure figure = session_accuracy_figure(table, "simtex", SessionMetric::all);
  ASSERT_EQ(figure.series.size(), 2u);
  EXPECT_EQ(figure.series[0].label, "orco");
  EXPECT_EQ(figure.series[1].label, "orco (selected on test (inflated))");
}

TEST(RunFigures, UpdateTimeFigureTakesEachCellsCostRowOneLinePerMethodAndOtherKeys) {
  const auto cost = [](const std::string& method, const std::string& dataset, const GridCell& cell, double seconds) {
    CostRow row{method, dataset, cell};
    row.update_seconds = seconds;
    return row;
  };
  const std::vector<CostRow> costs = {cost("cop-fscil", "simtex", {{"pspc_probes", "50"}}, 0.41),
                                      cost("cop-fscil", "simtex", {{"pspc_probes", "5"}}, 0.10),
                                      cost("orco", "simtex", {{"pspc_probes", "5"}}, 0.3),
                                      cost("cop-fscil", "simtex", {{"pspc_probes", "5"}, {"shot", "1"}}, 9),
                                      cost("cop-fscil", "simtex-lmt", {{"pspc_probes", "10"}}, 9),
                                      cost("prototype", "simtex", {}, 9)};
  const Figure figure = grid_update_time_figure(costs, "simtex", "pspc_probes", {"5", "10", "50"}, "nps_time", "N_ps");
  EXPECT_NO_THROW(require_valid_figure(figure));
  ASSERT_EQ(figure.series.size(), 3u);
  EXPECT_FALSE(figure.x_log) << "5 to 50: a linear axis";
  EXPECT_TRUE(figure.x_categories.empty());
  EXPECT_EQ(figure.series[0].label, "cop-fscil");
  expect_values(figure.series[0].x, {5, 50}, "cop-fscil x");
  expect_values(figure.series[0].y, {0.10, 0.41}, "cop-fscil seconds");
  EXPECT_EQ(figure.series[1].label, "orco");
  expect_values(figure.series[1].x, {5}, "orco x");
  EXPECT_EQ(figure.series[2].label, "cop-fscil [shot=1]");
  expect_values(figure.series[2].y, {9}, "cop-fscil at shot 1");
}

// Issue 70: the N_ps figure spaced 5 ... 1000 as equal categories.
TEST(RunFigures, GridValuesSitAtTheirNumbersOnALogAxisWhereTheySpanDecadesAndAsCategoriesWhereNotNumbers) {
  std::vector<RunRecord> runs;
  for (const char* probes : {"1000", "5", "100"}) {
    runs.push_back(in_cell(run_with_accuracies("cop-fscil", "simtex", 1, {90, 80}), {{"pspc_probes", probes}}));
  }
  const std::vector<std::string> probes = {"5", "100", "1000"};
  const Figure nps = grid_metric_figure(summarize_runs(runs), "simtex", "pspc_probes", probes, "AA", "nps_aa", "");
  EXPECT_NO_THROW(require_valid_figure(nps));
  EXPECT_TRUE(nps.x_log);
  EXPECT_TRUE(nps.x_categories.empty());
  expect_values(nps.series[0].x, {5, 100, 1000}, "N_ps");

  const Figure shots = grid_metric_figure(summarize_runs({in_cell(runs[0], {{"shot", "1"}}), in_cell(runs[1], {{"shot", "5"}})}),
                                          "simtex", "shot", {"1", "5"}, "AA", "shot_aa", "");
  EXPECT_FALSE(shots.x_log);
  EXPECT_TRUE(shots.x_categories.empty());
  expect_values(shots.series[0].x, {1, 5}, "shots");

  const std::vector<std::string> spaces = {"raw", "standardised"};
  const std::vector<std::string> weights = {"0", "0.0001", "0.1", "1"};  // lambda: 0 beside four decades
  const Figure lambda = grid_metric_figure(summarize_runs({in_cell(runs[0], {{"pic_weight", "0.1"}})}), "simtex",
                                           "pic_weight", weights, "AA", "lambda_aa", "");
  EXPECT_EQ(lambda.x_categories, weights);
  expect_values(lambda.series[0].x, {2}, "0.1");

  const Figure named = grid_metric_figure(summarize_runs({in_cell(runs[0], {{"cpi_space", "raw"}})}), "simtex",
                                          "cpi_space", spaces, "AA", "space_aa", "");
  EXPECT_EQ(named.x_categories, spaces);
  expect_values(named.series[0].x, {0}, "raw");
}

// Issue 70: figures plotted means only.
TEST(RunFigures, EveryPointOfTwoOrMoreSeedsCarriesTheirStandardDeviationAndTheFigureSaysSo) {
  const SummaryTable table = sessions_table(false);
  const Figure all = session_accuracy_figure(table, "simtex", SessionMetric::all);
  ASSERT_EQ(all.series.size(), 1u);
  // orco's seeds: 90 and 80, 80 and 70, 70 and 60: a sample standard deviation of 7.0711 each.
  expect_values(all.series[0].y_spread, {std::sqrt(50.0), std::sqrt(50.0), std::sqrt(50.0)}, "orco spread");
  EXPECT_EQ(all.note, "whiskers: one standard deviation over seeds either side");
  const Figure novel = session_accuracy_figure(table, "simtex", SessionMetric::novel);
  EXPECT_TRUE(std::isnan(novel.series[0].y_spread[0])) << "session 0 has no novel classes";
  const Figure one_seed = session_accuracy_figure(table, "simtex-lmt", SessionMetric::all);
  EXPECT_FALSE(has_spread(one_seed));
  EXPECT_EQ(one_seed.note, "") << "prototype ran one seed: nothing to say";

  const Figure ablation = ablation_figure(table, "simtex", "ablation_simtex");
  // AA 80 and 70 (std 7.0711); PD 20 both.
  expect_values(ablation.series[0].y_spread, {std::sqrt(50.0)}, "AA spread");
  expect_values(ablation.series[1].y_spread, {0}, "PD spread");
}

TEST(RunFigures, ContextRatioIsTheMeanOverSeedsPerSessionAndNoFigureWithoutIt) {
  RunRecord first = run_with_accuracies("orco", "simtex", 1, {90, 80});
  RunRecord second = run_with_accuracies("orco", "simtex", 2, {90, 80});
  first.sessions[0].context_ratio_mean = 0.5;
  first.sessions[1].context_ratio_mean = 0.7;
  second.sessions[0].context_ratio_mean = 0.3;  // its session 1 unknown
  const RunRecord unmeasured = run_with_accuracies("prototype", "simtex", 1, {90, 80});
  const Figure figure = context_ratio_figure({first, unmeasured, second}, "simtex");
  EXPECT_NO_THROW(require_valid_figure(figure));
  EXPECT_EQ(figure.name, "context_ratio_simtex");
  ASSERT_EQ(figure.series.size(), 1u) << "prototype measured no R";
  EXPECT_EQ(figure.series[0].label, "orco");
  expect_values(figure.series[0].y, {0.4, 0.7}, "R");
  EXPECT_TRUE(context_ratio_figure({unmeasured}, "simtex").series.empty());
  EXPECT_DOUBLE_EQ(figure.y_floor, 0) << "R is a ratio of dispersions";
  expect_values(figure.series[0].y_spread, {std::sqrt(0.02), std::nan("")}, "R's spread over seeds 1 and 2");
  EXPECT_EQ(figure.note, "whiskers: one standard deviation over seeds either side");
  EXPECT_EQ(context_ratio_figure({first}, "simtex").note, "");
  RunRecord one_context = first;  // simtex-mini's test split: one recording per class
  for (auto& session : one_context.sessions) session.context_ratio_mean = 0;
  EXPECT_EQ(context_ratio_figure({one_context}, "simtex").note,
            "R is 0 throughout: the scored split holds one context per class");
  EXPECT_TRUE(context_ratio_figure({first}, "simtex-lmt").series.empty());
  EXPECT_EQ(context_ratio_figure({in_cell(first, {}, "test-oracle")}, "simtex").note, "selected on test (inflated)");
}

TEST(RunFigures, EfficiencyFiguresAreThreeBarPanelsOneBarPerMethodAndCell) {
  CostRow orco{"orco", "simtex", {}}, probes{"cop-fscil", "simtex", {{"pspc_probes", "5"}}}, elsewhere{"orco", "lmt108", {}};
  orco.mega_flops = 54.4;
  orco.parameters_millions = 2.5;
  orco.inference_ms_per_sample = 1.1;
  probes.mega_flops = 60;
  const auto figures = efficiency_figures({orco, elsewhere, probes}, "simtex");
  ASSERT_EQ(figures.size(), 3u);
  EXPECT_EQ(figures[0].name, "efficiency_simtex_flops");
  EXPECT_EQ(figures[1].name, "efficiency_simtex_params");
  EXPECT_EQ(figures[2].name, "efficiency_simtex_it");
  for (const Figure& figure : figures) {
    EXPECT_NO_THROW(require_valid_figure(figure)) << figure.name;
    EXPECT_EQ(figure.kind, FigureKind::bars);
    // "cop-fscil [pspc_probes=5]" is wider than a category label: the key is abbreviated, and spelt out.
    EXPECT_EQ(figure.x_categories, (std::vector<std::string>{"orco", "cop-fscil [psp=5]"})) << figure.name;
    EXPECT_EQ(figure.note, "psp = pspc_probes") << figure.name;
  }
  expect_values(figures[0].series.at(0).y, {54.4, 60}, "MFLOPs");
  expect_values(figures[1].series.at(0).y, {2.5, 0}, "NP");
  expect_values(figures[2].series.at(0).y, {1.1, 0}, "IT");
}

}  // namespace
}  // namespace fscil
