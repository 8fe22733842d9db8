#include "reports/cost_table.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

// A run whose base session took `base` seconds and each of its two sessions `update`.
RunRecord timed_run(const std::string& method, double base, double update, std::int64_t peak_mib,
                    std::int64_t replay_samples) {
  RunRecord record;
  record.method = method;
  record.dataset = "simtex";
  for (int s = 0; s < 3; ++s) {
    SessionOutcome session;
    session.session = s;
    session.train_seconds = s == 0 ? base : update;
    record.sessions.push_back(session);
  }
  record.peak_resident_bytes = peak_mib * 1024 * 1024;
  record.replay_samples = replay_samples;
  record.replay_bytes = replay_samples * 1024 * 256;  // a quarter MiB per sample
  record.inference.macs = 27'200'000;
  record.inference.parameters = 2'500'000;
  record.inference.trainable_parameters = 500'000;
  record.inference.seconds_per_sample = base / 1e5;
  return record;
}

// Issue 71: a removing session trains nothing; it is no update to average.
TEST(CostTable, TheUpdateTimeLeavesOutSessionsThatRemovedClasses) {
  RunRecord variable = timed_run("prototype", 50, 3, 700, 0);
  const int seen[] = {10, 15, 13};  // session 2 removed two classes, in no time
  for (int s = 0; s < 3; ++s) variable.sessions[s].seen_classes = seen[s];
  variable.sessions[2].train_seconds = 0;
  EXPECT_DOUBLE_EQ(summarize_costs({variable})[0].update_seconds, 3);
}

TEST(CostTable, AveragesTimesOverSeedsAndSessionsAndKeepsTheLargestMemory) {
  const std::vector<RunRecord> records = {timed_run("orco", 100, 2, 900, 400), timed_run("prototype", 50, 0, 700, 0),
                                          timed_run("orco", 120, 4, 950, 400)};
  const auto rows = summarize_costs(records);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].method, "orco");
  EXPECT_EQ(rows[0].runs, 2u);
  EXPECT_DOUBLE_EQ(rows[0].base_train_seconds, 110);
  EXPECT_DOUBLE_EQ(rows[0].update_seconds, 3);  // (2 + 2 + 4 + 4) / 4 sessions
  EXPECT_DOUBLE_EQ(rows[0].run_peak_mib, 950);
  EXPECT_EQ(rows[0].replay_samples, 400);
  EXPECT_DOUBLE_EQ(rows[0].replay_mib, 100);
  EXPECT_EQ(rows[1].replay_samples, 0);
  EXPECT_DOUBLE_EQ(rows[0].mega_flops, 54.4);  // 2 x 27.2 M MACs
  EXPECT_DOUBLE_EQ(rows[0].parameters_millions, 2.5);
  EXPECT_DOUBLE_EQ(rows[0].trainable_millions, 0.5);
  EXPECT_DOUBLE_EQ(rows[0].inference_ms_per_sample, 1.1);  // (1.0 + 1.2) / 2 ms

  EXPECT_EQ(render_cost_csv(rows),
            "method,dataset,runs,mflops,params_m,session_trainable_m,it_ms,base_train_s,update_s,run_peak_mib,replay_samples,"
            "replay_mib\n"
            "orco,simtex,2,54.4,2.500,0.500,1.100,110.0,3.00,950,400,100.00\n"
            "prototype,simtex,1,54.4,2.500,0.500,0.500,50.0,0.00,700,0,0.00\n");
  EXPECT_NE(render_cost_markdown(rows).find("| orco | simtex | 54.4 | 2.500 | 0.500 | 1.100 | 110.0 | 3.00 | 950 | 400 | 100.00 |"),
            std::string::npos);
  EXPECT_NE(render_cost_latex(rows).find("orco & simtex & 54.4 & 2.500 & 0.500 & 1.100 & 110.0 & 3.00 & 950 & 400 & 100.00 \\\\"),
            std::string::npos);
}

TEST(CostTable, MemoryIsWhatTheRunAddedToTheProcess) {
  RunRecord later = timed_run("adbs", 100, 2, 1300, 0);
  later.resident_at_start_bytes = 400LL << 20;  // the data and what earlier runs of the process still hold
  RunRecord older = timed_run("prototype", 100, 2, 900, 0);  // a file without the start: the process's peak
  const auto rows = summarize_costs({later, older});
  EXPECT_DOUBLE_EQ(rows[0].run_peak_mib, 900);
  EXPECT_DOUBLE_EQ(rows[1].run_peak_mib, 900);
}

RunRecord in_cell(RunRecord record, const std::string& probes) {
  record.grid = {{"pspc_probes", probes}};
  return record;
}

TEST(CostTable, SweepCellsAreRowsOfTheirOwnNamedInEveryRendering) {
  const std::vector<RunRecord> records = {in_cell(timed_run("orco", 100, 2, 900, 400), "5"),
                                          in_cell(timed_run("orco", 90, 6, 800, 400), "10"),
                                          timed_run("prototype", 50, 0, 700, 0),
                                          in_cell(timed_run("orco", 120, 4, 950, 400), "5")};
  const auto rows = summarize_costs(records);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(grid_cell_name(rows[0].grid), "pspc_probes=5");
  EXPECT_EQ(rows[0].runs, 2u);
  EXPECT_DOUBLE_EQ(rows[0].update_seconds, 3);  // (2 + 2 + 4 + 4) / 4 sessions; the 6 s of the other cell stay out
  EXPECT_DOUBLE_EQ(rows[0].run_peak_mib, 950);
  EXPECT_EQ(grid_cell_name(rows[1].grid), "pspc_probes=10");
  EXPECT_EQ(rows[1].runs, 1u);
  EXPECT_DOUBLE_EQ(rows[1].update_seconds, 6);
  EXPECT_TRUE(rows[2].grid.empty());
  EXPECT_EQ(render_cost_csv(rows),
            "method,dataset,cell,runs,mflops,params_m,session_trainable_m,it_ms,base_train_s,update_s,run_peak_mib,"
            "replay_samples,replay_mib\n"
            "orco,simtex,pspc_probes=5,2,54.4,2.500,0.500,1.100,110.0,3.00,950,400,100.00\n"
            "orco,simtex,pspc_probes=10,1,54.4,2.500,0.500,0.900,90.0,6.00,800,400,100.00\n"
            "prototype,simtex,,1,54.4,2.500,0.500,0.500,50.0,0.00,700,0,0.00\n");
  const std::string markdown = render_cost_markdown(rows);
  EXPECT_NE(markdown.find("\n| orco [pspc_probes=10] | simtex | 54.4 | 2.500 | 0.500 | 0.900 | 90.0 | 6.00 |"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("\n| prototype | simtex | 54.4 |"), std::string::npos) << markdown;
  const std::string latex = render_cost_latex(rows);
  EXPECT_NE(latex.find("\norco [pspc\\_probes=5] & simtex & 54.4 & 2.500 & 0.500 & 1.100 & 110.0 & 3.00 & 950 & 400 & "
                       "100.00 \\\\\n"),
            std::string::npos)
      << latex;
  EXPECT_NE(latex.find("\nprototype & simtex & 54.4 &"), std::string::npos) << latex;
}

}  // namespace
}  // namespace fscil
