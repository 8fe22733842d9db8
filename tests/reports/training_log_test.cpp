#include "reports/training_log.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

TEST(TrainingLog, CsvHasAColumnPerValueNameSortedAndEmptyWhereAnEpochHasNoneOrNan) {
  RunRecord record = run_with_accuracies("cop-fscil", "simtex", 3, {90, 80});
  record.sessions[0].training_log = {
      {"pretrain", 1, {{"loss", 2.5}, {"lr", 0.1}, {"ce", 2.0}}},
      {"pretrain", 2, {{"loss", std::nan("")}, {"lr", 0.05}}},  // diverged
      {"pseudo-incremental", 1, {{"loss", 1.25}, {"selection_score", 61.5}}}};
  record.sessions[1].training_log = {{"session 1", 1, {{"loss", 0.000123456789}, {"lr", 1e-5}, {"seconds", 3.5}}}};
  // Six significant digits: 0.000123456789 is 0.000123457, and 1e-5 stays 1e-05.
  EXPECT_EQ(render_training_log_csv(record),
            "session,stage,epoch,ce,loss,lr,seconds,selection_score\n"
            "0,pretrain,1,2,2.5,0.1,,\n"
            "0,pretrain,2,,,0.05,,\n"
            "0,pseudo-incremental,1,,1.25,,,61.5\n"
            "1,session 1,1,,0.000123457,1e-05,3.5,\n");
}

TEST(TrainingLog, ARunThatLoggedNothingIsTheHeaderAlone) {
  EXPECT_EQ(render_training_log_csv(run_with_accuracies("prototype", "simtex", 1, {90, 80})), "session,stage,epoch\n");
}

TEST(TrainingLog, LogsGoBelowLogsAndTheirSweepCellsFolder) {
  RunRecord record = run_with_accuracies("cop-fscil/cpi+pspc", "simtex", 3, {90});
  EXPECT_EQ(training_log_path(record, false), std::filesystem::path("logs/cop-fscil_cpi_pspc__simtex__seed3.csv"));
  record.grid = {{"shot", "5"}, {"pic_weight", "0.1"}};
  // A cell's own folder holds its runs alone; a sweep's folder holds every cell's, named in the grid's key order.
  EXPECT_EQ(training_log_path(record, false), std::filesystem::path("logs/cop-fscil_cpi_pspc__simtex__seed3.csv"));
  EXPECT_EQ(training_log_path(record, true),
            std::filesystem::path("logs/shot=5+pic_weight=0.1/cop-fscil_cpi_pspc__simtex__seed3.csv"));
}

}  // namespace
}  // namespace fscil
