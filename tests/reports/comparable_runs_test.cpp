#include "reports/comparable_runs.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "reports/run_record.h"
#include "tests/reports/session_runs.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

RunRecord run_of(const std::string& method, std::uint64_t seed, const std::string& shot = "5") {
  RunRecord record = run_with_accuracies(method, "simtex", seed, {50});
  record.profile = "fast";
  record.protocol_parameters = {{"context_strength", "1"}, {"shot", shot}, {"way", "5"}};
  record.parameters = record.protocol_parameters;
  record.parameters["pretrain_epochs"] = "8";
  record.dataset_key = "0123";
  record.source = method + "-" + std::to_string(seed) + ".json";
  return record;
}

std::string refusal(const std::vector<RunRecord>& records) {
  try {
    require_comparable_runs(records);
  } catch (const ReportError& error) {
    return error.what();
  }
  return "";
}

TEST(ComparableRuns, SeedsOfOneMethodAndMethodsOfOneProtocolShareATable) {
  RunRecord orco = run_of("orco", 1);
  orco.parameters["temperature"] = "16";  // a method's own parameters are its own business
  EXPECT_EQ(refusal({run_of("prototype", 1), run_of("prototype", 2), orco}), "");
  RunRecord other_dataset = run_of("prototype", 1, "3");
  other_dataset.dataset = "simtex-lmt";
  other_dataset.dataset_key = "4567";
  EXPECT_EQ(refusal({run_of("prototype", 1), other_dataset}), "") << "datasets are separate rows";
}

TEST(ComparableRuns, AnotherShotProfileSplitThreadCountOrDataIsRefusedNamingBothFiles) {
  EXPECT_EQ(refusal({run_of("prototype", 1), run_of("prototype", 2, "3")}),
            "prototype-1.json and prototype-2.json: runs that cannot share a table (shot=5 against shot=3); keep "
            "them in separate folders");
  EXPECT_NE(refusal({run_of("prototype", 1), run_of("orco", 1, "3")}).find("(shot=5 against shot=3)"),
            std::string::npos) << "another method is no excuse for another protocol";
  RunRecord smoke = run_of("prototype", 2);
  smoke.profile = "smoke";
  EXPECT_NE(refusal({run_of("prototype", 1), smoke}).find("(profile fast against smoke)"), std::string::npos);
  RunRecord validation = run_of("orco", 2);
  validation.evaluated_on = "validation";
  EXPECT_NE(refusal({run_of("prototype", 1), validation}).find("(scored on test against validation)"),
            std::string::npos);
  RunRecord one_thread = run_of("prototype", 2);
  one_thread.threads = 1;
  EXPECT_NE(refusal({run_of("prototype", 1), one_thread}).find("(threads 2 against 1)"), std::string::npos);
  RunRecord other_data = run_of("prototype", 2);
  other_data.dataset_key = "89ab";
  EXPECT_NE(refusal({run_of("prototype", 1), other_data}).find("(data 0123 against 89ab)"), std::string::npos);
}

TEST(ComparableRuns, OneMethodWithOtherParametersOrOneSeedTwiceIsRefused) {
  RunRecord longer = run_of("prototype", 2);
  longer.parameters["pretrain_epochs"] = "100";
  EXPECT_NE(refusal({run_of("prototype", 1), longer}).find("(pretrain_epochs=8 against pretrain_epochs=100)"),
            std::string::npos);
  RunRecord shared = run_of("prototype", 2);
  shared.parameters["base_training"] = "shared with pits-sc";
  EXPECT_EQ(refusal({run_of("prototype", 1), shared}), "") << "a shared base is the same base";
  EXPECT_NE(refusal({run_of("prototype", 1), run_of("prototype", 1)}).find("(prototype seed 1 twice)"),
            std::string::npos);
}

TEST(ComparableRuns, FilesWrittenBeforeProtocolParametersCompareOnTheirOtherFields) {
  RunRecord old_orco = run_of("orco", 1, "3");
  old_orco.protocol_parameters.clear();
  EXPECT_EQ(refusal({run_of("prototype", 1), old_orco}), "");
  old_orco.profile = "paper";
  EXPECT_NE(refusal({run_of("prototype", 1), old_orco}), "");
}

// A run of a sweep over `key`: its cell and the folder fscil-bench sweep gives the cell.
RunRecord in_cell(RunRecord record, const std::string& key, const std::string& value) {
  record.grid = {{key, value}};
  record.source = "cells/" + key + "=" + value + "/" + record.source;
  return record;
}

TEST(ComparableRuns, Bf16AndFp32RunsNeverShareATableEvenAsRowsOfOtherDatasets) {
  RunRecord bf16 = run_of("prototype", 1, "5");
  bf16.protocol_parameters["precision"] = "bf16";
  RunRecord elsewhere = run_of("orco", 1, "5");
  elsewhere.dataset = "sf-instruments";
  EXPECT_EQ(incomparability(bf16, elsewhere), "made in bf16 against fp32");
  EXPECT_EQ(incomparability(elsewhere, bf16), "made in fp32 against bf16");
}

TEST(ComparableRuns, RunsOfDifferentSweepCellsAreDifferentRowsAndNeverConflict) {
  // A sweep over shot: each cell's runs have the shot of their cell, and every cell has seed 1.
  const RunRecord five = in_cell(run_of("prototype", 1, "5"), "shot", "5");
  const RunRecord three = in_cell(run_of("prototype", 1, "3"), "shot", "3");
  EXPECT_EQ(incomparability(five, three), "");
  EXPECT_NE(incomparability(run_of("prototype", 1, "5"), run_of("prototype", 1, "3")), "") << "the same runs unswept";
  EXPECT_EQ(refusal({five, in_cell(run_of("prototype", 2, "5"), "shot", "5"), three,
                     in_cell(run_of("orco", 1, "3"), "shot", "3")}),
            "");
}

TEST(ComparableRuns, WithinOneSweepCellRunsAreCheckedAgainstThatCellsFirstRun) {
  const RunRecord five = in_cell(run_of("prototype", 1, "5"), "shot", "5");
  const RunRecord three = in_cell(run_of("prototype", 1, "3"), "shot", "3");
  EXPECT_EQ(refusal({five, three, in_cell(run_of("prototype", 1, "3"), "shot", "3")}),
            "cells/shot=3/prototype-1.json and cells/shot=3/prototype-1.json: runs that cannot share a table "
            "(prototype seed 1 twice); keep them in separate folders");
  // Differences inside the second cell, which the first cell's run cannot reveal.
  RunRecord smoke = in_cell(run_of("orco", 2, "3"), "shot", "3");
  smoke.profile = "smoke";
  EXPECT_EQ(refusal({five, three, smoke}),
            "cells/shot=3/prototype-1.json and cells/shot=3/orco-2.json: runs that cannot share a table (profile fast "
            "against smoke); keep them in separate folders");
  RunRecord longer = in_cell(run_of("prototype", 2, "3"), "shot", "3");
  longer.parameters["pretrain_epochs"] = "100";
  EXPECT_NE(refusal({five, three, longer}).find("(pretrain_epochs=8 against pretrain_epochs=100)"), std::string::npos);
}

TEST(ComparableRuns, LoadingAMixedFolderIsRefusedAndOutOfRangeAccuraciesToo) {
  TemporaryDirectory out;
  save_run_record(out.path(), run_of("prototype", 1));
  save_run_record(out.path() / "later", run_of("prototype", 2, "3"));
  try {
    load_run_records(out.path());
    FAIL() << "a 5-shot and a 3-shot run were loaded as seeds of one row";
  } catch (const ReportError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("later/results/prototype__simtex__seed2.json and " + out.path().string() +
                           "/results/prototype__simtex__seed1.json: runs that cannot share a table (shot=3 against "
                           "shot=5)"),
              std::string::npos)
        << message;
  }
  std::string text = to_json_text(run_of("prototype", 1));
  text.replace(text.find("\"accuracy\": 50"), 14, "\"accuracy\": 150");
  EXPECT_THROW(
      {
        try {
          run_record_from_json_text(text, "odd.json");
        } catch (const ReportError& error) {
          EXPECT_STREQ(error.what(), "odd.json: session 0 has an accuracy of 150, expected percentages in [0, 100]");
          throw;
        }
      },
      ReportError);
  // The joint accuracy weighs base and novel samples, so it lies between their accuracies.
  RunRecord two_sessions = run_with_accuracies("prototype", "simtex", 1, {60, 99});
  two_sessions.sessions[0].accuracy.base = 60;
  two_sessions.sessions[1].accuracy.base = 64;
  two_sessions.sessions[1].accuracy.novel = 60;
  try {
    run_record_from_json_text(to_json_text(two_sessions), "odd.json");
    FAIL() << "an accuracy above both of its groups' was read";
  } catch (const ReportError& error) {
    EXPECT_STREQ(error.what(), "odd.json: session 1 has an accuracy of 99 with base 64 and novel 60, expected one "
                               "between them");
  }
  two_sessions.sessions[1].accuracy.all = 62;
  two_sessions.sessions[1].accuracy.harmonic = 2 * 64.0 * 60 / 124;  // of base and novel
  EXPECT_NO_THROW(run_record_from_json_text(to_json_text(two_sessions), "odd.json"));
}

}  // namespace
}  // namespace fscil
