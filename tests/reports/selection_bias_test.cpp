#include "reports/selection_bias.h"

#include <gtest/gtest.h>

#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

// A run of the selection sweep (--grid selection=last,validation,test-oracle).
RunRecord chosen_by(const std::string& selection, const std::string& method, std::uint64_t seed,
                    const std::vector<double>& accuracies) {
  RunRecord record = run_with_accuracies(method, "simtex", seed, accuracies);
  record.grid = {{"selection", selection}};
  record.selection = selection;
  return record;
}

// orco: AA 80 on the last epoch, 81 chosen on validation, (84 + 83) / 2 = 83.5 chosen on test.
// prototype: AA 85 on the last epoch and 84 chosen on test (the test choice is made on the base
// session only, so it can lose). pits-sc was only run chosen on test: AA 70 and no gain.
std::vector<SelectionBiasRow> measured() {
  return measure_selection_bias(summarize_runs({
      chosen_by("test-oracle", "orco", 1, {92, 76}), chosen_by("test-oracle", "orco", 2, {92, 74}),
      chosen_by("last", "orco", 1, {90, 70}), chosen_by("last", "orco", 2, {88, 72}),
      chosen_by("validation", "orco", 1, {90, 72}), chosen_by("validation", "orco", 2, {90, 72}),
      chosen_by("test-oracle", "pits-sc", 1, {80, 60}),
      chosen_by("last", "prototype", 1, {90, 80}), chosen_by("test-oracle", "prototype", 1, {90, 78})}));
}

TEST(SelectionBias, ARowPerMethodWithTheAaOfEachSelection) {
  const auto rows = measured();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].method, "orco");
  EXPECT_EQ(rows[0].seeds, "1 2");
  EXPECT_TRUE(rows[0].has_last && rows[0].has_validation && rows[0].has_oracle);
  EXPECT_DOUBLE_EQ(rows[0].aa_last, 80);
  EXPECT_DOUBLE_EQ(rows[0].aa_validation, 81);
  EXPECT_DOUBLE_EQ(rows[0].aa_oracle, 83.5);
  EXPECT_EQ(rows[1].method, "pits-sc");
  EXPECT_FALSE(rows[1].has_last || rows[1].has_validation);
  EXPECT_TRUE(rows[1].has_oracle);
  EXPECT_EQ(rows[2].method, "prototype");
  EXPECT_FALSE(rows[2].has_validation);
}

TEST(SelectionBias, GainIsTestChosenMinusLastEpochAndEmptyWithoutBoth) {
  const auto rows = measured();
  EXPECT_EQ(render_selection_bias_csv(rows),
            "method,dataset,cell,seeds,AA_last,AA_validation,AA_test_oracle,gain_over_last,gain_over_validation\n"
            "orco,simtex,,1 2,80.0000,81.0000,83.5000,3.5000,2.5000\n"
            "pits-sc,simtex,,1,,,70.0000,,\n"
            "prototype,simtex,,1,85.0000,,84.0000,-1.0000,\n");
  const std::string markdown = render_selection_bias_markdown(rows);
  EXPECT_NE(markdown.find("| method | dataset | seeds | last epoch | best on validation | best on test (inflated) | "
                          "gain over last | gain over validation |\n"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("\n| orco | simtex | 1 2 | 80.00 | 81.00 | 83.50 | +3.50 | +2.50 |\n"), std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("\n| pits-sc | simtex | 1 |  |  | 70.00 |  |  |\n"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("\n| prototype | simtex | 1 | 85.00 |  | 84.00 | -1.00 |  |\n"), std::string::npos)
      << markdown;
  const std::string latex = render_selection_bias_latex(rows);
  EXPECT_NE(latex.find("\\begin{tabular}{llcccc}\n\\toprule\nMethod & Dataset & Last & Validation & Test (inflated) & "
                       "Gain \\\\\n\\midrule\norco & simtex & 80.00 & 81.00 & 83.50 & +3.50 \\\\\n"
                       "pits-sc & simtex &  &  & 70.00 &  \\\\\nprototype & simtex & 85.00 &  & 84.00 & -1.00 \\\\\n"
                       "\\bottomrule\n"),
            std::string::npos)
      << latex;
}

// A sweep over shot x selection keeps a row per shot: cells are never merged.
TEST(SelectionBias, OtherSweepKeysAreRowsOfTheirOwn) {
  std::vector<RunRecord> runs;
  for (const char* shot : {"1", "5"}) {
    for (const char* selection : {"last", "test-oracle"}) {
      RunRecord run = chosen_by(selection, "orco", 1, {90, std::string(shot) == "1" ? 60.0 : 70.0});
      run.grid.emplace_back("shot", shot);
      if (std::string(selection) == "test-oracle") run.sessions[1].accuracy.all += 2;
      runs.push_back(run);
    }
  }
  const auto rows = measure_selection_bias(summarize_runs(runs));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].cell, "shot=1");
  EXPECT_DOUBLE_EQ(rows[0].aa_last, 75);  // (90 + 60) / 2
  EXPECT_DOUBLE_EQ(rows[0].aa_oracle, 76);
  EXPECT_EQ(rows[1].cell, "shot=5");
  EXPECT_DOUBLE_EQ(rows[1].aa_last, 80);
  EXPECT_NE(render_selection_bias_markdown(rows).find("| orco [shot=5] | simtex |"), std::string::npos);
}

}  // namespace
}  // namespace fscil
