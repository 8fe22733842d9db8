#include "reports/paper_comparison.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

std::vector<PaperRow> paper() {
  return {{"results_haptex", "HapTex", "CoP-FSCIL", "ours", {90, 80, 70}, 20, 80, 11.11},
          {"results_lmt108", "LMT108", "CoP-FSCIL", "ours", {95, 85}, 10, 90, 10.53},
          {"ablation_haptex", "HapTex", "cop-fscil/cpi", "", {88, 78, 68}, 20, 78, 11.1}};
}

TEST(PaperComparison, OursBesideThePapersRowOfTheSameDatasetAndMethod) {
  const SummaryTable ours = summarize_runs({run_with_accuracies("cop-fscil", "haptex", 1, {80, 70, 66}),
                                            run_with_accuracies("cop-fscil", "haptex", 2, {82, 72, 62}),
                                            run_with_accuracies("cop-fscil/cpi", "simtex", 1, {60, 50, 40}),
                                            run_with_accuracies("prototype", "haptex", 1, {50, 40, 30}),
                                            run_with_accuracies("cop-fscil", "simtex-mini", 1, {50, 40, 30})});
  const auto rows = compare_with_paper(ours, paper());
  ASSERT_EQ(rows.size(), 2u);  // the paper reports no prototype and no simtex-mini
  EXPECT_EQ(rows[0].paper_table, "results_haptex");
  EXPECT_EQ(rows[0].paper_method, "CoP-FSCIL");
  EXPECT_FALSE(rows[0].simulated);
  EXPECT_EQ(rows[0].ours, (std::vector<double>{81, 71, 64, 17, 72, rows[0].ours[5]}));  // means over seeds
  EXPECT_EQ(rows[1].paper_table, "ablation_haptex");
  EXPECT_TRUE(rows[1].simulated);

  const std::string csv = render_paper_comparison_csv(rows);
  EXPECT_NE(csv.find("dataset,method,source,simulated,paper_dataset,paper_table,paper_method,acc_0,acc_1,acc_2,PD,AA,ADR,method_note\n"),
            std::string::npos) << csv;
  EXPECT_NE(csv.find("haptex,cop-fscil,ours,no,HapTex,results_haptex,CoP-FSCIL,81.00,71.00,64.00,17.00,72.00,"),
            std::string::npos) << csv;
  EXPECT_NE(csv.find("haptex,cop-fscil,ours-paper,no,HapTex,results_haptex,CoP-FSCIL,-9.00,-9.00,-6.00,-3.00,-8.00,"),
            std::string::npos) << csv;
  // Our rows of the simulator are simulated; the paper's own beside them are not.
  EXPECT_NE(csv.find("simtex,cop-fscil/cpi,ours,yes,HapTex,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("simtex,cop-fscil/cpi,paper,no,HapTex,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("simtex,cop-fscil/cpi,ours-paper,yes,HapTex,"), std::string::npos) << csv;
  const std::string markdown = render_paper_comparison_markdown(rows);
  EXPECT_NE(markdown.find("cop-fscil/cpi on simtex (simulated HapTex)"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("our data are simulated, the paper's real"), std::string::npos);
  EXPECT_NE(markdown.find("| ours - paper | -28.00 | -28.00 | -28.00 |"), std::string::npos) << markdown;
  EXPECT_EQ(markdown.find("‡"), std::string::npos) << "no method here carries a note";
}

// A method of our reading (its registry's table_note) says so beside the paper's row: on our CSV
// line and above the Markdown table.
TEST(PaperComparison, AMethodsNoteStandsOnOurLineOnly) {
  RunRecord ours = run_with_accuracies("cop-fscil", "haptex", 1, {80, 70, 66});
  ours.method_note = "our reading of X, as a test";
  const auto rows = compare_with_paper(summarize_runs({ours}), paper());
  ASSERT_EQ(rows.size(), 1u);
  const std::string csv = render_paper_comparison_csv(rows);
  EXPECT_NE(csv.find(",\"our reading of X, as a test\"\nhaptex,cop-fscil,paper,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("ours-paper,no,HapTex,results_haptex,CoP-FSCIL,-10.00,-10.00,-4.00,-6.00,-8.00,-2.00,\n"), std::string::npos)
      << csv;
  EXPECT_EQ(csv.back(), '\n');
  EXPECT_EQ(csv.substr(csv.rfind(',', csv.size() - 2)), ",\n") << "the difference line carries no note";
  EXPECT_NE(render_paper_comparison_markdown(rows).find("\n‡ ours: our reading of X, as a test.\n"), std::string::npos);
}

TEST(PaperComparison, Bf16RunsAreNotComparedWithThePapersFp32Numbers) {
  RunRecord bf16 = run_with_accuracies("cop-fscil", "haptex", 1, {80, 70, 66});
  bf16.protocol_parameters["precision"] = "bf16";
  EXPECT_THROW(compare_with_paper(summarize_runs({bf16}), paper()), ReportError);
}

// Issue 71: the paper's sessions only add classes.
TEST(PaperComparison, ClassVariableRunsAreNotComparedWithThePapersAddOnlySessions) {
  RunRecord variable = run_with_accuracies("cop-fscil", "haptex", 1, {80, 70, 66});
  variable.protocol_parameters["removal"] = "fciac";
  try {
    compare_with_paper(summarize_runs({variable}), paper());
    ADD_FAILURE() << "compared";
  } catch (const ReportError& error) {
    EXPECT_EQ(std::string(error.what()),
              "these runs' sessions also removed classes (removal=fciac); the paper's sessions only add them");
  }
}

TEST(PaperComparison, TheComparedMethodsStandBesideTheirRowsWhereThePaperHasThem) {
  std::vector<PaperRow> table = paper();
  table.push_back({"results_haptex", "HapTex", "ADBS", "AAAI25", {92.95, 83.83, 72.58}, 34, 70.38, 4.77});
  table.push_back({"results_ls100", "LS-100", "PAN", "TMM24", {91.83, 91.29, 90.70}, 12.59, 86.39, 1.82});
  table.push_back({"results_ns100", "NS-100", "DSN", "TPAMI23", {100.00, 98.05, 97.32}, 11.11, 93.76, 1.30});
  table.push_back({"results_lmt108", "LMT108", "Comp-FSCIL", "ICML24", {42.54, 20.47, 17.37}, 33.24, 16.21, 13.79});
  table.push_back({"results_ns100", "NS-100", "ARP", "Interspeech23", {99.96, 95.95, 93.60}, 20.27, 89.26, 2.48});
  table.push_back({"results_ls100", "LS-100", "AMFO", "TASLP24", {92.63, 92.25, 92.20}, 7.64, 89.24, 1.07});
  const auto rows = compare_with_paper(summarize_runs({run_with_accuracies("adbs", "haptex", 1, {80, 40, 20}),
                                                       run_with_accuracies("adbs", "ls100", 1, {80, 40, 20}),
                                                       run_with_accuracies("pan", "haptex", 1, {80, 40, 20}),
                                                       run_with_accuracies("pan", "ls100", 1, {80, 40, 20}),
                                                       run_with_accuracies("dsn", "haptex", 1, {80, 40, 20}),
                                                       run_with_accuracies("dsn", "ns100", 1, {80, 40, 20}),
                                                       run_with_accuracies("comp-fscil", "lmt108", 1, {80, 40, 20}),
                                                       run_with_accuracies("comp-fscil", "ls100", 1, {80, 40, 20}),
                                                       run_with_accuracies("arp", "lmt108", 1, {80, 40, 20}),
                                                       run_with_accuracies("arp", "ns100", 1, {80, 40, 20}),
                                                       run_with_accuracies("amfo", "haptex", 1, {80, 40, 20}),
                                                       run_with_accuracies("amfo", "ls100", 1, {80, 40, 20})}),
                                       table);
  // the paper's audio tables have no ADBS or Comp-FSCIL row, its tactile tables no PAN, DSN, ARP or AMFO row
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].paper_method, "ADBS");
  EXPECT_EQ(rows[0].paper, (std::vector<double>{92.95, 83.83, 72.58, 34, 70.38, 4.77}));
  EXPECT_EQ(rows[1].paper_method, "PAN");
  EXPECT_EQ(rows[1].paper, (std::vector<double>{91.83, 91.29, 90.70, 12.59, 86.39, 1.82}));
  EXPECT_EQ(rows[2].paper_method, "DSN");
  EXPECT_EQ(rows[2].paper, (std::vector<double>{100.00, 98.05, 97.32, 11.11, 93.76, 1.30}));
  EXPECT_EQ(rows[3].paper_method, "Comp-FSCIL");
  EXPECT_EQ(rows[3].paper, (std::vector<double>{42.54, 20.47, 17.37, 33.24, 16.21, 13.79}));
  EXPECT_EQ(rows[4].paper_method, "ARP");
  EXPECT_EQ(rows[4].paper, (std::vector<double>{99.96, 95.95, 93.60, 20.27, 89.26, 2.48}));
  EXPECT_EQ(rows[5].paper_method, "AMFO");
  EXPECT_EQ(rows[5].paper, (std::vector<double>{92.63, 92.25, 92.20, 7.64, 89.24, 1.07}));
}

// PA-PCT stands in both the tactile and the audio tables.
TEST(PaperComparison, PaPctStandsBesideItsRowsInBothTables) {
  std::vector<PaperRow> table = paper();
  table.push_back({"results_haptex", "HapTex", "PA-PCT", "Interspeech26", {95.68, 90.80, 86.86}, 24.86, 81.48, 3.28});
  table.push_back({"results_ns100", "NS-100", "PA-PCT", "Interspeech26", {99.98, 98.90, 97.96}, 8.82, 95.27, 1.02});
  const auto rows = compare_with_paper(summarize_runs({run_with_accuracies("pa-pct", "haptex", 1, {80, 40, 20}),
                                                       run_with_accuracies("pa-pct", "ns100", 1, {80, 40, 20})}),
                                       table);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].paper_method, "PA-PCT");
  EXPECT_EQ(rows[0].paper, (std::vector<double>{95.68, 90.80, 86.86, 24.86, 81.48, 3.28}));
  EXPECT_EQ(rows[1].paper_method, "PA-PCT");
  EXPECT_EQ(rows[1].paper, (std::vector<double>{99.98, 98.90, 97.96, 8.82, 95.27, 1.02}));
}

// ldc stands beside the paper's LDC rows (audio tables only in the paper).
TEST(PaperComparison, LdcStandsBesideItsRows) {
  std::vector<PaperRow> table = paper();
  table.push_back({"results_ls100", "LS-100", "LDC", "TPAMI23", {92.28, 90.95, 88.53}, 14.64, 84.54, 2.13});
  table.push_back({"results_ns100", "NS-100", "LDC", "TPAMI23", {99.71, 97.32, 94.09}, 14.84, 90.90, 1.77});
  const auto rows = compare_with_paper(summarize_runs({run_with_accuracies("ldc", "ls100", 1, {80, 40, 20}),
                                                       run_with_accuracies("ldc", "ns100", 1, {80, 40, 20})}),
                                       table);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].paper_method, "LDC");
  EXPECT_EQ(rows[0].paper, (std::vector<double>{92.28, 90.95, 88.53, 14.64, 84.54, 2.13}));
  EXPECT_EQ(rows[1].paper, (std::vector<double>{99.71, 97.32, 94.09, 14.84, 90.90, 1.77}));
}

TEST(PaperComparison, SessionsBeyondThePapersAreLeftOut) {
  const auto rows = compare_with_paper(summarize_runs({run_with_accuracies("cop-fscil", "lmt108", 1, {90, 80, 70})}), paper());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].sessions, 2u);
  EXPECT_EQ(rows[0].paper, (std::vector<double>{95, 85, 10, 90, 10.53}));
}

}  // namespace
}  // namespace fscil
