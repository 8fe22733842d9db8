#include "reports/summary_table.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>

#include "core/csv_text.h"
#include "core/error.h"
#include "metrics/convergence.h"
#include "reports/run_record.h"
#include "tests/reports/session_runs.h"
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
    SessionOutcome session;
    session.session = static_cast<int>(s);
    session.seen_classes = 10 + 5 * static_cast<int>(s);
    session.accuracy.all = accuracies[s];
    session.accuracy.base = accuracies[s] + (s == 0 ? 0 : 1);  // session 0 scores the base classes alone
    session.accuracy.current = s == 0 ? accuracies[s] : 0;
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

  // A method's note travels with its result file; a file without one (every method run as its
  // release runs it, and files from before the note) reads as none.
  EXPECT_EQ(to_json_text(original).find("method_note"), std::string::npos);
  RunRecord noted = original;
  noted.method_note = "our reading of X: no runnable release";
  EXPECT_EQ(run_record_from_json_text(to_json_text(noted), "memory").method_note, noted.method_note);
  EXPECT_EQ(copy.method_note, "");
  noted.method_note = "one\ntwo";
  EXPECT_THROW(run_record_from_json_text(to_json_text(noted), "memory"), ReportError);
}

TEST(RunRecord, ASweepCellKeepsTheKeyOrderOfTheGridThroughItsFile) {
  RunRecord swept = record_of("cop-fscil", 1, {90, 80});
  swept.grid = {{"shot", "5"}, {"pic_weight", "0.1"}};
  const std::string text = to_json_text(swept);
  const RunRecord copy = run_record_from_json_text(text, "cell.json");
  EXPECT_EQ(copy.grid, (GridCell{{"shot", "5"}, {"pic_weight", "0.1"}}));
  EXPECT_EQ(grid_cell_name(copy.grid), "shot=5+pic_weight=0.1");

  nlohmann::json older = nlohmann::json::parse(text);
  older.erase("grid_keys");  // as files written before the order was kept
  EXPECT_EQ(grid_cell_name(run_record_from_json_text(older.dump(), "old.json").grid), "pic_weight=0.1+shot=5");
  EXPECT_EQ(to_json_text(record_of("prototype", 1, {90, 80})).find("grid_keys"), std::string::npos)
      << "a run outside a sweep writes no key order";

  nlohmann::json odd = nlohmann::json::parse(text);
  odd["grid_keys"] = {"shot", "way"};
  try {
    run_record_from_json_text(odd.dump(), "odd.json");
    ADD_FAILURE() << "a key order naming another key was accepted";
  } catch (const ReportError& error) {
    EXPECT_EQ(std::string(error.what()),
              "odd.json: field 'grid_keys': expected the keys of grid (pic_weight, shot), found shot, way");
  }
}

TEST(RunRecord, CellsOfOneFolderShareOneKeyOrder) {
  const TemporaryDirectory folder;
  RunRecord first = record_of("cop-fscil", 1, {90, 80});
  first.grid = {{"shot", "5"}, {"pic_weight", "0.1"}};
  RunRecord older = record_of("cop-fscil", 2, {90, 80});
  older.grid = {{"pic_weight", "0.1"}, {"shot", "5"}};  // alphabetical, as a file without its key order
  save_run_record(folder.path(), first);
  save_run_record(folder.path(), older);
  const std::vector<RunRecord> records = load_run_records(folder.path());
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].grid, records[1].grid);
  EXPECT_EQ(grid_cell_name(records[1].grid), "shot=5+pic_weight=0.1");
  EXPECT_EQ(summarize_runs(records).rows.size(), 1u) << "one cell, one row";
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
      EXPECT_NE(std::string(error.what()).find("expected a whole number from "), std::string::npos) << error.what();
    }
  }
}

// Read as strictly as dataset.json (issue 69): a repeated or unknown key, a value of the wrong kind
// or out of its range is one message naming the file and the field, never tabulated.
TEST(RunRecord, ReadAsStrictlyAsDatasetJson) {
  const std::string text = to_json_text(record_of("prototype", 1, {50, 40}));
  const auto refusal = [](const std::string& odd) -> std::string {
    try {
      run_record_from_json_text(odd, "odd.json");
      return "accepted";
    } catch (const ReportError& error) {
      return error.what();
    }
  };
  const auto changed = [&](const std::string& from, const std::string& to) {
    std::string odd = text;
    EXPECT_NE(odd.find(from), std::string::npos) << from;
    return odd.replace(odd.find(from), from.size(), to);
  };
  EXPECT_EQ(refusal(changed("\"seed\": 1", "\"seed\": 1, \"seed\": 2")),
            "odd.json: field 'seed' given twice in one object; give it once");
  EXPECT_EQ(refusal(changed("\"seed\": 1", "\"seed\": 1, \"sede\": 2")).substr(0, 38),
            "odd.json: unknown field 'sede', expect");
  EXPECT_EQ(refusal(changed("\"method\": \"prototype\"", "\"method\": 7")),
            "odd.json: field 'method': expected a string, found 7");
  EXPECT_EQ(refusal(changed("\"train_seconds\": ", "\"train_seconds\": -")).find("train_seconds -"), 10u);
  EXPECT_NE(refusal(changed("\"train_seconds\": ", "\"train_seconds\": -"))
                .find("expected a number of seconds in [0, 1e+09]"),
            std::string::npos);
  EXPECT_EQ(refusal(changed("\"total_seconds\": ", "\"total_seconds\": -")).substr(0, 48),
            "odd.json: field 'total_seconds': expected a numb");
  EXPECT_EQ(refusal(changed("\"macs\": ", "\"macs\": 1, \"mac\": ")).substr(0, 41), "odd.json: unknown field 'inference.mac', ");
  // Written again as flops = 2 x macs: a count past 4e18 would overflow 64 bits there.
  EXPECT_EQ(refusal(std::regex_replace(text, std::regex("\"macs\": [0-9]+"), "\"macs\": 5000000000000000000"))
                .substr(0, 55),
            "odd.json: field 'inference.macs': expected an integer i");
  EXPECT_EQ(refusal(changed("\"sessions\": [", "\"sessions\": [1, ")), "odd.json: field 'sessions[0]': expected an object");
  EXPECT_EQ(refusal(changed("\"parameters\": {", "\"parameters\": {\"shot\": \"five\", ")),
            "odd.json: field 'parameters.shot': expected a whole number of at least 1, found 'five'");
  EXPECT_EQ(refusal(changed("\"parameters\": {", "\"parameters\": {\"lr\": 0.1, ")),
            "odd.json: field 'parameters.lr': expected a string, found 0.1");
  EXPECT_EQ(refusal(text), "accepted");
}

// Fields each well formed that contradict one another: not a run the program could have written.
TEST(RunRecord, AFileIsCheckedAsAWhole) {
  RunRecord three = record_of("prototype", 1, {50, 40, 30});
  three.protocol_parameters = {{"sessions", "3"}, {"shot", "5"}};
  EXPECT_EQ(run_record_from_json_text(to_json_text(three), "ok.json").sessions.size(), 3u);
  const auto refusal = [](const RunRecord& record) {
    try {
      run_record_from_json_text(to_json_text(record), "odd.json");
    } catch (const ReportError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  RunRecord swapped = three;
  std::swap(swapped.sessions[1], swapped.sessions[2]);
  EXPECT_EQ(refusal(swapped), "odd.json: session 2 recorded in place 1, expected sessions 0, 1, 2, ... in order");
  RunRecord shrinking = three;
  shrinking.sessions[2].seen_classes = 15;
  EXPECT_EQ(refusal(shrinking), "odd.json: session 2 has 15 seen classes, expected more than 15");
  shrinking.sessions[2].seen_classes = 13;  // the class-variable protocol: session 2 removed two
  shrinking.protocol_parameters["removal"] = "fciac";
  EXPECT_EQ(refusal(shrinking), "accepted");
  RunRecord no_classes = three;
  no_classes.sessions[0].seen_classes = 0;
  EXPECT_EQ(refusal(no_classes), "odd.json: session 0 has 0 seen classes, expected more than 0");
  RunRecord untested = three;
  untested.sessions[1].accuracy.samples = 0;
  EXPECT_EQ(refusal(untested), "odd.json: session 1 was tested on 0 samples, expected at least 1");
  RunRecord idle = three;
  idle.threads = 0;
  EXPECT_EQ(refusal(idle), "odd.json: threads 0, expected 1 or more");
  RunRecord large = three;
  large.threads = 512;  // --threads 0 on a 2 x 128-core node with SMT
  EXPECT_EQ(refusal(large), "accepted");
  RunRecord longer = three;
  longer.sessions.push_back(longer.sessions.back());
  longer.sessions.back().session = 3;
  longer.sessions.back().seen_classes = 25;
  EXPECT_EQ(refusal(longer), "odd.json: 4 sessions recorded, expected the protocol's 3");
  RunRecord shorter = three;  // its last session cut off: AA and PD would be over two sessions
  shorter.sessions.pop_back();
  EXPECT_EQ(refusal(shorter), "odd.json: 2 sessions recorded, expected the protocol's 3");
  RunRecord cell = three;
  cell.grid = {{"shot", "9"}};
  EXPECT_EQ(refusal(cell), "odd.json: grid cell shot=9 but the run used shot=5");
  cell.grid = {{"shot", "5"}, {"selection", "validation"}};
  EXPECT_EQ(refusal(cell), "odd.json: grid cell selection=validation but the run used selection=last");
  // Round six: what a probe's hand-edited files said and the runner never writes.
  RunRecord split = three;
  split.parameters["shot"] = "6";
  EXPECT_EQ(refusal(split), "odd.json: field 'parameters.shot' is '6' but 'protocol_parameters.shot' is '5', expected "
                            "the one value the run used");
  RunRecord not_finite = three;
  not_finite.parameters["temperature"] = "inf";
  EXPECT_EQ(refusal(not_finite), "odd.json: field 'parameters.temperature': 'inf', expected a finite number");
  RunRecord half = three;
  half.protocol_parameters["precision"] = "fp16";
  EXPECT_EQ(refusal(half), "odd.json: field 'protocol_parameters.precision': 'fp16', expected fp32 or bf16");
  RunRecord sometimes = three;
  sometimes.protocol_parameters["removal"] = "sometimes";
  EXPECT_EQ(refusal(sometimes), "odd.json: field 'protocol_parameters.removal': 'sometimes', expected none or fciac");
  RunRecord planned = three;
  planned.protocol_parameters["base_classes"] = "10";
  planned.protocol_parameters["way"] = "5";
  EXPECT_EQ(refusal(planned), "accepted");
  planned.sessions[1].seen_classes = 16;
  EXPECT_EQ(refusal(planned), "odd.json: session 1 has 16 seen classes, expected the protocol's 15 (10 base, 5 way)");
  RunRecord novel_at_first = three;
  novel_at_first.sessions[0].accuracy.novel = 20;
  EXPECT_EQ(refusal(novel_at_first).rfind("odd.json: session 0 has accuracy 50, base 50, current 50, novel 20", 0), 0u)
      << refusal(novel_at_first);
  RunRecord harmonic = three;
  harmonic.sessions[1].accuracy.novel = 30;
  harmonic.sessions[1].accuracy.harmonic = 30;  // 2 * 41 * 30 / 71 = 34.65
  EXPECT_EQ(refusal(harmonic).rfind("odd.json: session 1 has a harmonic mean of 30 with base 41 and novel 30, expected 34.6", 0), 0u)
      << refusal(harmonic);
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
    EXPECT_NE(std::string(error.what()).find("broken.json: not JSON"), std::string::npos);
  }
  EXPECT_THROW(load_run_records(directory.path() / "missing"), ReportError);
}

TEST(RunRecord, AnOutFolderIsReadFromItsResultsFoldersOnly) {
  TemporaryDirectory directory;
  save_run_record(directory.path(), record_of("prototype", 1, {50, 40}));
  // What a user keeps beside a run's results: its config file, an old copy under results/.
  std::ofstream(directory.path() / "run.json") << R"({"methods": "prototype", "threads": 1})";
  std::filesystem::create_directories(directory.path() / "results" / "old");
  std::ofstream(directory.path() / "results" / "old" / "x.json") << "{}";
  EXPECT_EQ(load_run_records(directory.path()).size(), 1u);
  // A folder of result files, not a run's --out, is read whole: a foreign file there is named.
  try {
    load_run_records(directory.path() / "results");
    FAIL() << "expected an error";
  } catch (const ReportError& error) {
    EXPECT_NE(std::string(error.what()).find("x.json"), std::string::npos) << error.what();
  }
}

// `record` written and read back, or the refusal naming the file.
std::string refusal_of(const RunRecord& record) {
  try {
    run_record_from_json_text(to_json_text(record), "odd.json");
  } catch (const ReportError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(RunRecord, SelectionSweepCellAndTrainingLogRoundTripThroughJson) {
  RunRecord original = record_of("orco", 1, {90, 80});
  original.selection = "test-oracle";
  original.grid = {{"shot", "5"}, {"pic_weight", "0.1"}};
  original.sessions[0].training_log = {
      {"pretrain", 1, {{"loss", 2.25}, {"lr", 0.1}}},
      {"pretrain", 2, {{"loss", std::nan("")}, {"lr", 0.05}, {"selection_score", 61.5}}}};  // diverged
  original.sessions[1].training_log = {{"session 1", 1, {{"loss", 0.125}, {"seconds", 3.5}}}};
  const RunRecord copy = run_record_from_json_text(to_json_text(original), "memory");
  EXPECT_EQ(copy.selection, "test-oracle");
  EXPECT_TRUE(selected_on_test(copy));
  EXPECT_EQ(copy.grid, original.grid);
  ASSERT_EQ(copy.sessions[0].training_log.size(), 2u);
  ASSERT_EQ(copy.sessions[1].training_log.size(), 1u);
  const EpochLog& first = copy.sessions[0].training_log[0];
  EXPECT_EQ(first.stage, "pretrain");
  EXPECT_EQ(first.epoch, 1);
  EXPECT_EQ(first.values, original.sessions[0].training_log[0].values);
  const EpochLog& diverged = copy.sessions[0].training_log[1];
  EXPECT_EQ(diverged.epoch, 2);
  ASSERT_EQ(diverged.values.size(), 3u);
  EXPECT_TRUE(std::isnan(diverged.values.at("loss")));
  EXPECT_EQ(diverged.values.at("lr"), 0.05);
  EXPECT_EQ(diverged.values.at("selection_score"), 61.5);
  EXPECT_EQ(copy.sessions[1].training_log[0].stage, "session 1");
  EXPECT_EQ(copy.sessions[1].training_log[0].epoch, 1);
  EXPECT_EQ(copy.sessions[1].training_log[0].values, original.sessions[1].training_log[0].values);

  for (const char* honest : {"last", "validation"}) {
    RunRecord chosen = original;
    chosen.selection = honest;
    const RunRecord chosen_copy = run_record_from_json_text(to_json_text(chosen), "memory");
    EXPECT_EQ(chosen_copy.selection, honest);
    EXPECT_FALSE(selected_on_test(chosen_copy)) << honest;
  }
}

// Result files written before sweeps, epoch selection and training logs read as what they were:
// the last epoch, outside any sweep cell, nothing logged.
TEST(RunRecord, OlderFilesWereChosenOnTheLastEpochOutsideASweepAndLoggedNothing) {
  RunRecord swept = record_of("orco", 1, {90, 80});
  swept.selection = "validation";
  swept.grid = {{"shot", "5"}};
  swept.sessions[0].training_log = {{"pretrain", 1, {{"loss", 1.5}}}};
  nlohmann::json document = nlohmann::json::parse(to_json_text(swept));
  document.erase("selection");
  document.erase("grid");
  document.erase("grid_keys");
  for (auto& session : document.at("sessions")) EXPECT_EQ(session.erase("training_log"), 1u);
  const RunRecord old = run_record_from_json_text(document.dump(), "old.json");
  EXPECT_EQ(old.selection, "last");
  EXPECT_FALSE(selected_on_test(old));
  EXPECT_TRUE(old.grid.empty());
  EXPECT_TRUE(old.sessions[0].training_log.empty());
  EXPECT_EQ(old.session_accuracies(), (std::vector<double>{90, 80}));
}

TEST(RunRecord, RefusesOtherSelectionsAndCellOrStageTextNoFolderOrCsvFieldCanHold) {
  RunRecord record = record_of("orco", 1, {90, 80});
  record.selection = "best";
  EXPECT_EQ(refusal_of(record), "odd.json: field 'selection': expected last, validation or test-oracle, found 'best'");
  for (const char* selection : {"", "Last", "oracle", "test"}) {
    record.selection = selection;
    EXPECT_NE(refusal_of(record).find("odd.json: field 'selection': "), std::string::npos) << selection;
  }
  record.selection = "last";

  record.grid = {{"shot", "1,2"}};
  EXPECT_EQ(refusal_of(record), "odd.json: field 'grid': expected letters, digits, '_', '.' or '-', found shot=1,2");
  for (const auto& [key, value] : {std::pair{"shot", ""}, {"", "5"}, {"pic weight", "1"}, {"cell", "../up"},
                                   {"shot", "5+way=3"}, {"lr", "1e-4\n"}}) {
    record.grid = {{key, value}};
    EXPECT_NE(refusal_of(record).find("odd.json: field 'grid': "), std::string::npos) << key << "=" << value;
  }
  record.grid = {{"pic_weight", "1e-4"}, {"cpi_reference", "farthest"}, {"Shot.Count", "-5"}};
  EXPECT_EQ(refusal_of(record), "accepted");
  record.grid.clear();

  record.sessions[1].training_log = {{"pre,train", 1, {{"loss", 1}}}};
  EXPECT_EQ(refusal_of(record),
            "odd.json: training log stage 'pre,train', expected text without commas, quotes or control characters");
  for (const char* stage : {"", "say \"when\"", "tab\tbed", "two\nlines", "carriage\rreturn"}) {
    record.sessions[1].training_log = {{stage, 1, {{"loss", 1}}}};
    EXPECT_NE(refusal_of(record).find("odd.json: training log stage '"), std::string::npos) << stage;
  }
  record.sessions[1].training_log = {{"session 1 (projector)", 1, {{"loss", 1}}}};
  EXPECT_EQ(refusal_of(record), "accepted");
  // Value names become CSV headers of the training log as they are.
  record.sessions[1].training_log = {{"pretrain", 1, {{"loss,ce", 1}}}};
  EXPECT_EQ(refusal_of(record),
            "odd.json: training log value 'loss,ce', expected a name without commas, quotes or control characters");
}

TEST(RunRecord, CellNamesJoinTheKeysInTheGridsOrderWithPlus) {
  EXPECT_EQ(grid_cell_name({{"shot", "5"}, {"pic_weight", "0.1"}}), "shot=5+pic_weight=0.1");
  EXPECT_EQ(grid_cell_name({{"pspc_probes", "50"}}), "pspc_probes=50");
  EXPECT_EQ(grid_cell_name({}), "");
  for (const char* name : {"last", "validation", "test-oracle"}) EXPECT_TRUE(is_selection_name(name)) << name;
  for (const char* name : {"", "Last", "best", "test", "oracle", "test_oracle"}) {
    EXPECT_FALSE(is_selection_name(name)) << name;
  }
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
  EXPECT_EQ(header, "method,dataset,split,selection,precision,seeds,AA,PD,ADR,acc_0,acc_1,AA_std,PD_std,ADR_std,acc_0_std,"
                    "acc_1_std,AA_ci95,PD_ci95,ADR_ci95,acc_0_ci95,acc_1_ci95,training,method_note");
  // Two seeds: no confidence interval (its t quantile is 12.7: it would say nothing).
  EXPECT_NE(csv.find(",7.0711,7.0711,,,,,,not recorded,\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("prototype,simtex,test,last,fp32,1 2,80.0000,10.0000,"), std::string::npos);
  const std::string three = render_csv(summarize_runs({record_of("prototype", 1, {90, 80}), record_of("prototype", 2, {80, 70}),
                                                       record_of("prototype", 3, {85, 75})}));
  EXPECT_NE(three.find(",12.4208,12.4208,not recorded,\n"), std::string::npos) << three;  // 4.3027 x 5 / sqrt(3)
  const std::string single = render_csv(summarize_runs({record_of("prototype", 1, {90, 80})}));
  EXPECT_EQ(single, "method,dataset,split,selection,precision,seeds,AA,PD,ADR,acc_0,acc_1,training,method_note\n"
                    "prototype,simtex,test,last,fp32,1,85.0000,10.0000,11.1111,90.0000,80.0000,not recorded,\n");
}

// A run whose base log scored base validation after each epoch of `stage`.
RunRecord with_base_validation(RunRecord record, const std::string& stage, const std::vector<double>& accuracy) {
  for (std::size_t e = 0; e < accuracy.size(); ++e) {
    record.sessions.front().training_log.push_back(
        {stage, static_cast<int>(e + 1), {{"loss", 2.0 / static_cast<double>(e + 1)}, {kBaseValidationKey, accuracy[e]}}});
  }
  return record;
}

TEST(SummaryTable, ARunWhoseBaseDidNotLearnIsMarkedAndWarned) {
  RunRecord flat = record_of("pits-sc", 1, {10, 8});
  for (int epoch = 1; epoch <= 4; ++epoch) {
    flat.sessions.front().training_log.push_back({"pretrain", epoch, {{"loss", 2.302585}, {kBaseValidationKey, 10.0}}});
  }
  const SummaryTable table = summarize_runs({flat});
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.rows[0].training, TrainingVerdict::not_learning);
  EXPECT_NE(render_csv(table).find(",not learning,\n"), std::string::npos) << render_csv(table);
  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| pits-sc † |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("pretrain: its loss stayed at 2.3026 over all its epochs, not learning"), std::string::npos)
      << markdown;
  EXPECT_EQ(unfinished_warning({flat}).rfind("warning: pits-sc, seed 1: a base stage ended without learning: ", 0), 0u)
      << unfinished_warning({flat});
}

TEST(SummaryTable, EveryRenderingMarksARunWhoseBaseTrainingWasStillRising) {
  const RunRecord finished = with_base_validation(record_of("prototype", 1, {90, 80}), "base", {50, 80, 90, 90, 90, 90});
  const RunRecord rising = with_base_validation(record_of("amfo", 1, {70, 60}), "base", {20, 30, 40, 50, 60, 70});
  const RunRecord rising_seed2 = with_base_validation(record_of("amfo", 2, {72, 61}), "base", {20, 30, 40, 50, 60, 61});
  const SummaryTable table = summarize_runs({finished, rising, rising_seed2, record_of("pan", 1, {88, 77})});
  ASSERT_EQ(table.rows.size(), 3u);
  EXPECT_EQ(table.rows[0].training, TrainingVerdict::converged);
  EXPECT_EQ(table.rows[1].training, TrainingVerdict::still_rising);
  EXPECT_EQ(table.rows[2].training, TrainingVerdict::not_recorded);
  // Seed 1 rose 70 - 40 = 30 points in its last 3 epochs; seed 2 21.
  ASSERT_EQ(table.rows[1].unfinished.size(), 2u);
  EXPECT_EQ(table.rows[1].unfinished[0],
            "seed 1, base: best of its last 3 of 6 epochs +30.00 points against the best before (20.0% -> 70.0%)");

  const std::string csv = render_csv(table);
  const auto line_of = [&](const std::string& method) {
    const std::size_t start = csv.find("\n" + method + ",") + 1;
    return csv.substr(start, csv.find('\n', start) - start);
  };
  const auto ends_with = [](const std::string& line, const std::string& end) {
    return line.size() >= end.size() && line.compare(line.size() - end.size(), end.size(), end) == 0;
  };
  EXPECT_TRUE(ends_with(line_of("prototype"), ",converged,")) << csv;
  EXPECT_TRUE(ends_with(line_of("amfo"), ",still rising,")) << csv;
  EXPECT_TRUE(ends_with(line_of("pan"), ",not recorded,")) << csv;
  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| amfo † |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| prototype |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("\n- amfo, seed 2, base: best of its last 3 of 6 epochs +21.00 points"), std::string::npos)
      << markdown;
  const std::string latex = render_latex(table);
  EXPECT_NE(latex.find("amfo$^\\dagger$"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\\par\\footnotesize $^\\dagger$ a base stage ended still rising"), std::string::npos) << latex;
  EXPECT_EQ(latex.find("prototype$^\\dagger$"), std::string::npos) << latex;
  // check and report --paper judge run by run: runs no table could hold (a repeated seed) still warn.
  const std::string warning = unfinished_warning({finished, rising, rising_seed2, rising});
  EXPECT_EQ(std::count(warning.begin(), warning.end(), '\n'), 3) << warning;
  EXPECT_EQ(warning.rfind("warning: amfo, seed 1: a base stage ended still rising on base validation, not at its "
                          "plateau: base: best of its last 3 of 6 epochs +30.00",
                          0),
            0u)
      << warning;
  EXPECT_EQ(unfinished_warning({finished}), "");
}

TEST(SummaryTable, EveryRenderingCarriesAMethodsNoteBesideItsRow) {
  RunRecord ours = record_of("ldc", 1, {80, 70});
  ours.method_note = "our reading of LDC: no runnable release, every gap ours";
  RunRecord ours_seed2 = record_of("ldc", 2, {82, 71});  // a file from before the note
  const SummaryTable table = summarize_runs({record_of("prototype", 1, {90, 80}), ours_seed2, ours});
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[1].method_note, ours.method_note);
  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| ldc ‡ |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| prototype |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("\n‡ ldc: our reading of LDC: no runnable release, every gap ours\n"), std::string::npos)
      << markdown;
  const std::string latex = render_latex(table);
  EXPECT_NE(latex.find("ldc$^\\ddagger$"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\\par\\footnotesize $^\\ddagger$ ldc: our reading of LDC: no runnable release, every gap ours."),
            std::string::npos)
      << latex;
  // The CSV's last field holds the note whole, commas and all, for the one reader to read back.
  const std::vector<std::string> lines = csv_lines(render_csv(table));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(csv_fields(lines[0]).back(), "method_note");
  EXPECT_EQ(csv_fields(lines[1]).back(), "");
  EXPECT_EQ(csv_fields(lines[2]).back(), ours.method_note);
  EXPECT_EQ(csv_fields(lines[2]).size(), csv_fields(lines[0]).size());

  // Seeds whose files word it differently keep both wordings; sweep cells of one note share one footnote.
  RunRecord reworded = record_of("ldc", 3, {81, 72});
  reworded.method_note = "our reading of LDC, reworded";
  EXPECT_EQ(summarize_runs({ours, ours_seed2, reworded}).rows[0].method_note, ours.method_note + "; " + reworded.method_note);
  const SummaryTable swept = summarize_runs({in_cell(ours, {{"shot", "1"}}), in_cell(ours, {{"shot", "5"}})});
  const std::string sweep_markdown = render_markdown(swept);
  EXPECT_NE(sweep_markdown.find("‡ ldc [shot=1], ldc [shot=5]: our reading of LDC"), std::string::npos) << sweep_markdown;
  EXPECT_EQ(sweep_markdown.find("our reading of LDC"), sweep_markdown.rfind("our reading of LDC")) << sweep_markdown;

  // A note is free text from a result file: LaTeX's specials print as text, none acts.
  RunRecord hostile = record_of("ldc", 1, {80, 70});
  hostile.method_note = "\\input{x} ~ ^ 100%";
  const std::string escaped = render_latex(summarize_runs({hostile}));
  EXPECT_NE(escaped.find("ldc: \\textbackslash{}input\\{x\\} \\textasciitilde{} \\textasciicircum{} 100\\%."),
            std::string::npos)
      << escaped;
}

TEST(SummaryTable, SaysWhichSplitWasScoredAndNeverMixesTestWithValidation) {
  RunRecord on_validation = record_of("prototype", 2, {80, 70});
  on_validation.evaluated_on = "validation";
  EXPECT_THROW(summarize_runs({record_of("prototype", 1, {90, 80}), on_validation}), ReportError);
  RunRecord other_seed = record_of("prototype", 3, {85, 75});
  other_seed.evaluated_on = "validation";
  const SummaryTable table = summarize_runs({on_validation, other_seed});
  EXPECT_EQ(table.evaluated_on, "validation");
  EXPECT_NE(render_csv(table).find("prototype,simtex,validation,last,fp32,2 3,"), std::string::npos);
  EXPECT_NE(render_markdown(table).find("### simtex, validation split"), std::string::npos);
  EXPECT_NE(render_latex(table).find("Comparison on simtex (simulated, standing in for HapTex), validation split"), std::string::npos);
  // A result file says what it was scored on, and one that says nothing was scored on test.
  EXPECT_EQ(run_record_from_json_text(to_json_text(on_validation), "x").evaluated_on, "validation");
}

// --precision bf16: other numbers, so never averaged or ranked with fp32 runs, and every
// rendering says so; fp32 tables read as they always did.
TEST(SummaryTable, SaysWhenTheEncoderRanInBf16AndNeverMixesItWithFp32) {
  RunRecord bf16 = record_of("prototype", 1, {80, 70});
  bf16.protocol_parameters["precision"] = "bf16";
  EXPECT_EQ(precision_of(bf16), "bf16");
  EXPECT_EQ(precision_of(record_of("prototype", 1, {80, 70})), "fp32") << "files without it are fp32";
  RunRecord other_dataset = record_of("orco", 1, {85, 75});
  other_dataset.dataset = "sf-instruments";
  EXPECT_THROW(summarize_runs({bf16, other_dataset}), ReportError) << "not even as rows of another dataset";
  RunRecord second_seed = record_of("prototype", 2, {82, 72});
  second_seed.protocol_parameters["precision"] = "bf16";
  const SummaryTable table = summarize_runs({bf16, second_seed});
  EXPECT_EQ(table.precision, "bf16");
  EXPECT_NE(render_csv(table).find("prototype,simtex,test,last,bf16,1 2,"), std::string::npos) << render_csv(table);
  EXPECT_NE(render_markdown(table).find("### simtex, test split, encoder in bf16"), std::string::npos);
  EXPECT_NE(render_latex(table).find("Comparison on simtex (simulated, standing in for HapTex), test split, encoder in bf16"), std::string::npos);
  const SummaryTable fp32 = summarize_runs({record_of("prototype", 1, {80, 70})});
  EXPECT_NE(render_markdown(fp32).find("### simtex, test split\n"), std::string::npos) << render_markdown(fp32);
  EXPECT_NE(render_csv(fp32).find(",test,last,fp32,1,"), std::string::npos) << render_csv(fp32);
}

// Issue 71: class-variable sessions are another protocol: the tables say so, and never mix them
// with add-only runs.
TEST(SummaryTable, SaysWhenSessionsRemovedClassesAndNeverMixesThemWithAddOnlyRuns) {
  RunRecord variable = record_of("prototype", 1, {80, 70});
  variable.protocol_parameters["removal"] = "fciac";
  const SummaryTable table = summarize_runs({variable});
  EXPECT_EQ(table.removal, "fciac");
  EXPECT_NE(render_markdown(table).find("### simtex, test split, class-variable sessions (removal=fciac)"),
            std::string::npos) << render_markdown(table);
  EXPECT_NE(render_latex(table).find("test split, class-variable sessions (removal=fciac)"), std::string::npos);
  RunRecord add_only = record_of("prototype", 2, {82, 72});
  add_only.protocol_parameters["sessions"] = "2";
  variable.protocol_parameters["sessions"] = "2";
  EXPECT_THROW(summarize_runs({variable, add_only}), ReportError);
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

// Issue 70: with two seeds every cell read "42.00 ± 31.11 [-237.54, 321.54]", bold, unclipped.
TEST(SummaryTable, BoldIsTheBestAndWhatAPairedTestCannotSeparateFromIt) {
  std::vector<RunRecord> runs;
  const auto add = [&](const char* method, std::vector<double> aa) {
    for (std::size_t s = 0; s < aa.size(); ++s) runs.push_back(record_of(method, s + 1, {aa[s], aa[s]}));
  };
  add("cop-fscil", {80, 82, 78});
  add("pits-sc", {79, 83, 76});    // differences 1, -1, 2: p = 0.53, not separable
  add("prototype", {70, 72, 68});  // 10 below in every seed: separable
  add("orco", {81, 75});           // two seeds: not tested, and its mean is below the best
  const std::string markdown = render_markdown(summarize_runs(runs));
  SCOPED_TRACE(markdown);
  EXPECT_NE(markdown.find("| cop-fscil | **80.00 ± 2.00 [75.03, 84.97]** |"), std::string::npos);
  EXPECT_NE(markdown.find("| pits-sc | **79.33 ± 3.51 [70.61, 88.06]** |"), std::string::npos);
  EXPECT_NE(markdown.find("| prototype | 70.00 ± 2.00 [65.03, 74.97] |"), std::string::npos);
  EXPECT_NE(markdown.find("| orco | 78.00 ± 4.24 |"), std::string::npos) << "two seeds: no interval";
  EXPECT_NE(markdown.find("paired t-test"), std::string::npos);
  EXPECT_NE(markdown.find("Holm"), std::string::npos);
  const std::string latex = render_latex(summarize_runs(runs));
  EXPECT_NE(latex.find("pits-sc & \\textbf{79.33$\\pm$3.51 {\\scriptsize[70.61, 88.06]}}"), std::string::npos) << latex;
}

// A table whose folder has runs still missing: one method of one seed beside methods of two. Its
// mean is over another set of seeds, so it was bold as "the best" with a spread of "± 0.00".
TEST(SummaryTable, AMeanOverFewerSeedsIsNeverTheBestAndOneSeedHasNoSpread) {
  std::vector<RunRecord> runs;
  const auto add = [&](const char* method, std::vector<double> aa) {
    for (std::size_t s = 0; s < aa.size(); ++s) runs.push_back(record_of(method, s + 1, {aa[s], aa[s]}));
  };
  add("pa-pct", {90});
  add("pan", {80, 82});
  add("prototype", {70, 74});
  const SummaryTable table = summarize_runs(runs);
  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| pa-pct | 90.00 ± - |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| pan | **81.00 ± 1.41** |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| prototype | 72.00 ± 2.83 |"), std::string::npos) << markdown;
  EXPECT_NE(render_latex(table).find("pa-pct & 90.00$\\pm$- &"), std::string::npos) << render_latex(table);
  const std::string csv = render_csv(table);
  EXPECT_NE(csv.find("pa-pct,simtex,test,last,fp32,1,90.0000,0.0000,0.0000,90.0000,90.0000,,,,,,,,,,,not recorded,\n"),
            std::string::npos) << csv;
  EXPECT_NE(csv.find("pan,simtex,test,last,fp32,1 2,81.0000,0.0000,0.0000,81.0000,81.0000,1.4142,"), std::string::npos)
      << csv;
}

TEST(SummaryTable, AnIntervalIsClippedToWhatTheMetricCanTake) {
  const std::string markdown = render_markdown(summarize_runs(
      {record_of("prototype", 1, {100, 100}), record_of("prototype", 2, {99, 99}), record_of("prototype", 3, {100, 100})}));
  EXPECT_NE(markdown.find("| prototype | 99.67 ± 0.58 [98.23, 100.00] |"), std::string::npos) << markdown;
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
                 "odd.json: field 'method': expected letters, digits, '_', '.', '+', '/' or '-', found 'proto\\ntype & "
                 "100% best'");
  }
}

TEST(SummaryTable, SweepCellsAndSelectionsAreRowsOfTheirOwn) {
  const SummaryTable table = summarize_runs({in_cell(record_of("cop-fscil", 1, {90, 70}), {{"pic_weight", "0.1"}}),
                                             in_cell(record_of("cop-fscil", 1, {90, 60}), {{"pic_weight", "1"}}),
                                             in_cell(record_of("cop-fscil", 2, {80, 70}), {{"pic_weight", "0.1"}}),
                                             in_cell(record_of("orco", 1, {95, 75}), {{"shot", "5"}}, "test-oracle"),
                                             in_cell(record_of("orco", 1, {95, 65}), {{"shot", "5"}}),
                                             in_cell(record_of("orco", 1, {95, 70}), {{"shot", "5"}}, "validation")});
  ASSERT_EQ(table.rows.size(), 5u);
  const SummaryRow& weight_01 = table.rows[0];
  EXPECT_EQ(weight_01.grid, (GridCell{{"pic_weight", "0.1"}}));
  EXPECT_EQ(weight_01.seeds, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_DOUBLE_EQ(weight_01.session_accuracy[0].mean, 85.0);  // (90 + 80) / 2
  EXPECT_DOUBLE_EQ(weight_01.average_accuracy.mean, 77.5);     // (80 + 75) / 2
  EXPECT_EQ(table.rows[1].seeds, (std::vector<std::uint64_t>{1}));
  EXPECT_DOUBLE_EQ(table.rows[1].average_accuracy.mean, 75.0);
  EXPECT_EQ(table.rows[2].selection, "test-oracle");
  EXPECT_DOUBLE_EQ(table.rows[2].average_accuracy.mean, 85.0);
  EXPECT_EQ(table.rows[3].selection, "last");
  EXPECT_DOUBLE_EQ(table.rows[3].average_accuracy.mean, 80.0);
  EXPECT_EQ(table.rows[4].selection, "validation");
  EXPECT_EQ(table.grid_keys(), (std::vector<std::string>{"pic_weight", "shot"}));
  EXPECT_EQ(row_label(table.rows[2]), "orco (selected on test (inflated))");
  EXPECT_EQ(row_label(table.rows[3]), "orco");
  EXPECT_EQ(row_label(table.rows[4]), "orco (selected on validation)");
  EXPECT_TRUE(summarize_runs({record_of("orco", 1, {90, 80})}).grid_keys().empty());
  // One seed twice within one cell and selection is still two files of one run.
  EXPECT_THROW(summarize_runs({in_cell(record_of("orco", 1, {95, 75}), {{"shot", "5"}}),
                               in_cell(record_of("orco", 1, {95, 65}), {{"shot", "5"}})}),
               ReportError);
}

// Grid keys are columns in order of first appearance (here shot before pic_weight), empty where a
// row's cell has no such key; the oracle row is labelled in Markdown and LaTeX.
// A sweep over selection (the selection-bias reproduction) has one selection column, not two.
TEST(SummaryTable, ASweepOverSelectionKeepsOneSelectionColumn) {
  const SummaryTable table =
      summarize_runs({in_cell(record_of("orco", 1, {95, 75}), {{"selection", "test-oracle"}}, "test-oracle"),
                      in_cell(record_of("orco", 1, {95, 65}), {{"selection", "last"}})});
  EXPECT_TRUE(table.grid_keys().empty());
  const std::string csv = render_csv(table);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "method,dataset,split,selection,precision,seeds,AA,PD,ADR,acc_0,acc_1,training,method_note");
  EXPECT_NE(csv.find("\norco,simtex,test,test-oracle,fp32,1,85.0000,"), std::string::npos) << csv;
}

TEST(SummaryTable, EveryRenderingHasAColumnPerGridKeyAndTheSelection) {
  const SummaryTable table = summarize_runs({in_cell(record_of("orco", 1, {95, 75}), {{"shot", "5"}}, "test-oracle"),
                                             in_cell(record_of("orco", 1, {95, 65}), {{"shot", "5"}}),
                                             in_cell(record_of("cop-fscil", 1, {90, 70}), {{"pic_weight", "0.1"}}),
                                             in_cell(record_of("cop-fscil", 1, {90, 60}), {{"pic_weight", "1"}})});
  // ADR of one step is 100 x drop / first: 20/95 = 21.0526%, 30/95 = 31.5789%, 20/90, 30/90.
  EXPECT_EQ(render_csv(table),
            "method,dataset,shot,pic_weight,split,selection,precision,seeds,AA,PD,ADR,acc_0,acc_1,training,method_note\n"
            "orco,simtex,5,,test,test-oracle,fp32,1,85.0000,20.0000,21.0526,95.0000,75.0000,not recorded,\n"
            "orco,simtex,5,,test,last,fp32,1,80.0000,30.0000,31.5789,95.0000,65.0000,not recorded,\n"
            "cop-fscil,simtex,,0.1,test,last,fp32,1,80.0000,20.0000,22.2222,90.0000,70.0000,not recorded,\n"
            "cop-fscil,simtex,,1,test,last,fp32,1,75.0000,30.0000,33.3333,90.0000,60.0000,not recorded,\n");

  const std::string markdown = render_markdown(table);
  EXPECT_NE(markdown.find("| shot | pic_weight | method | 0 | 1 | PD | AA | ADR |\n"
                          "|---|---|---|---:|---:|---:|---:|---:|\n"
                          "| 5 |  | orco (selected on test (inflated)) | "),
            std::string::npos)
      << markdown;
  // Rows chosen on test are never best, though orco's is higher here: the best are among the others.
  EXPECT_NE(markdown.find("\n| 5 |  | orco (selected on test (inflated)) | 95.00 | 75.00 | 20.00 | 85.00 | 21.05 |\n"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("\n|  | 0.1 | cop-fscil | 90.00 | **70.00** | **20.00** | **80.00** | **22.22** |\n"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("\n| 5 |  | orco | **95.00** | 65.00 | 30.00 | **80.00** | 31.58 |\n"), std::string::npos)
      << markdown;

  const std::string latex = render_latex(table);
  EXPECT_NE(latex.find("\\begin{tabular}{lllccccc}\n\\toprule\nshot & pic\\_weight & Method & \\multicolumn{2}{c}{"),
            std::string::npos)
      << latex;
  // The session numbers sit under the session columns 4 and 5, after two grid columns and the method.
  EXPECT_NE(latex.find("\\cmidrule(lr){4-5}\n    && & 0 & 1 & & & \\\\\n"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\n5 &  & orco (selected on test (inflated)) & "), std::string::npos) << latex;
  EXPECT_NE(latex.find("\n & 0.1 & cop-fscil & 90.00 & \\textbf{70.00} & \\textbf{20.00} & \\textbf{80.00} & "
                       "\\textbf{22.22} \\\\\n"),
            std::string::npos)
      << latex;
}

}  // namespace
}  // namespace fscil
