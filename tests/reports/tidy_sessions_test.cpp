#include "reports/tidy_sessions.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

// Two sessions of 10 and then 15 seen classes: the base session, and one that added 5 novel ones.
RunRecord two_sessions(const std::string& method, std::uint64_t seed, double base_accuracy, double novel_accuracy) {
  RunRecord record = run_with_accuracies(method, "simtex", seed, {base_accuracy, 0.75 * base_accuracy});
  record.sessions[0].seen_classes = 10;
  record.sessions[0].accuracy.base = base_accuracy;
  record.sessions[0].accuracy.current = base_accuracy;  // the base classes are session 0's own
  record.sessions[0].train_seconds = 12.5;
  record.sessions[0].test_seconds = 0.5;
  record.sessions[0].context_ratio_mean = 0.125;
  SessionOutcome& novel = record.sessions[1];
  novel.seen_classes = 15;
  novel.accuracy.base = base_accuracy;
  novel.accuracy.novel = novel_accuracy;
  novel.accuracy.current = novel_accuracy;
  novel.accuracy.harmonic = 2 * base_accuracy * novel_accuracy / (base_accuracy + novel_accuracy);
  novel.train_seconds = 1.25;
  novel.test_seconds = 0.25;  // R unknown (NaN)
  return record;
}

TEST(TidySessions, OneLinePerSeedAndSessionWithNovelCurrentAndHarmonicEmptyInTheBaseSession) {
  // Harmonic means: 2 x 80 x 40 / 120 = 53.3333 and 2 x 60 x 60 / 120 = 60.
  EXPECT_EQ(render_tidy_sessions_csv({two_sessions("orco", 1, 80, 40), two_sessions("orco", 2, 60, 60)}),
            "method,dataset,split,selection,precision,seed,session,seen_classes,accuracy,base,novel,current,harmonic_mean,"
            "train_seconds,test_seconds,R\n"
            "orco,simtex,test,last,fp32,1,0,10,80.0000,80.0000,,,,12.500,0.500,0.1250\n"
            "orco,simtex,test,last,fp32,1,1,15,60.0000,80.0000,40.0000,40.0000,53.3333,1.250,0.250,\n"
            "orco,simtex,test,last,fp32,2,0,10,60.0000,60.0000,,,,12.500,0.500,0.1250\n"
            "orco,simtex,test,last,fp32,2,1,15,45.0000,60.0000,60.0000,60.0000,60.0000,1.250,0.250,\n");
}

// A column per sweep key in order of first appearance, empty for a run outside that key; the
// split and the epoch selection of each run.
TEST(TidySessions, SweepCellsAreColumnsAndEachRunSaysHowItsEpochsWereChosen) {
  RunRecord oracle = two_sessions("orco", 1, 80, 40);
  oracle.grid = {{"shot", "5"}};
  oracle.selection = "test-oracle";
  RunRecord weighted = two_sessions("cop-fscil", 3, 60, 60);
  weighted.grid = {{"pic_weight", "0.1"}, {"shot", "1"}};
  weighted.evaluated_on = "validation";
  const std::string csv = render_tidy_sessions_csv({oracle, weighted, two_sessions("prototype", 1, 80, 40)});
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "method,dataset,shot,pic_weight,split,selection,precision,seed,session,seen_classes,accuracy,base,novel,current,"
            "harmonic_mean,train_seconds,test_seconds,R");
  EXPECT_NE(csv.find("\norco,simtex,5,,test,test-oracle,fp32,1,1,15,60.0000,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\ncop-fscil,simtex,1,0.1,validation,last,fp32,3,0,10,60.0000,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nprototype,simtex,,,test,last,fp32,1,1,15,60.0000,"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);  // header and 3 runs x 2 sessions
}

TEST(TidySessions, NoRunsIsTheHeaderAlone) {
  EXPECT_EQ(render_tidy_sessions_csv({}),
            "method,dataset,split,selection,precision,seed,session,seen_classes,accuracy,base,novel,current,harmonic_mean,"
            "train_seconds,test_seconds,R\n");
}

}  // namespace
}  // namespace fscil
