// fscil-bench plan's time estimate: stages at measured rates, the runner's part, shared work
// counted once, each method's stages against hand counts, and the per-machine rate cache.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "core/parameter_set.h"
#include "methods/method_registry.h"
#include "methods/pan/pan_method.h"
#include "methods/pits_sc/pits_sc_method.h"
#include "methods/prototype/prototype_method.h"
#include "tests/temporary_directory.h"
#include "tools/fscil-bench/cells/time_estimate.h"

namespace fscil {
namespace {

RunSizes three_sessions() {
  RunSizes sizes;
  sizes.base_train = 200;
  sizes.base_validation = 50;
  sizes.base_classes = 10;
  sizes.way = 5;
  sizes.shot = 5;
  sizes.sessions = 3;
  sizes.sample_values = 5 * 64 * 24;
  sizes.scored = {40, 60, 200};
  return sizes;
}

TEST(RunSeconds, AddsEveryStageAtTheMeasuredRatesAndTheRunnersScoring) {
  MethodEntry entry{"example", "", nullptr};
  entry.work = [](const ParameterSet&, const RunSizes&) {
    return std::vector<StageWork>{{"pretraining", 100, 10, 0}, {"sessions", 0, 5, 20, false}};
  };
  entry.sessions_keep_embedding = true;
  const StepRate rates{0.5, 0.1, 0.01};
  std::set<std::string> stages;
  // 1.1 x (100 x 0.5 + (10 + 5 + 200 scored once + 8 x 128 timed) x 0.1 + 20 x 0.01): a run's
  // steps against the calibration's median.
  EXPECT_NEAR(run_seconds(entry, ParameterSet(), three_sessions(), rates, false, stages), 1.1 * 174.1, 1e-9);
  // Its base trained by another method of the cell: the sessions and the scoring only.
  EXPECT_NEAR(run_seconds(entry, ParameterSet(), three_sessions(), rates, true, stages), 1.1 * 123.1, 1e-9);
  // Scored samples embedded again in every session: 40 + 60 + 200 instead of 200.
  entry.sessions_keep_embedding = false;
  EXPECT_NEAR(run_seconds(entry, ParameterSet(), three_sessions(), rates, false, stages), 1.1 * 184.1, 1e-9);
  EXPECT_TRUE(stages.empty()) << "no stage of this entry is shared";
  // Under removal=fciac one of the two incremental sessions only removes classes: half the
  // sessions' work (2.5 inferred, 10 head steps), the base's and the scoring as they were.
  RunSizes removing = three_sessions();
  removing.removing_sessions = 1;
  EXPECT_NEAR(run_seconds(entry, ParameterSet(), removing, rates, false, stages), 1.1 * (184.1 - 0.25 - 0.1), 1e-9);
}

TEST(RunSeconds, ASharedStageIsCountedByTheFirstRunThatTrainsIt) {
  MethodEntry entry{"example", "", nullptr};
  entry.work = [](const ParameterSet&, const RunSizes&) {
    return std::vector<StageWork>{{"shared pretraining", 100, 0, 0}, {"own stage", 10, 0, 0}};
  };
  entry.shared_stages["shared pretraining"] = {};
  entry.sessions_keep_embedding = true;
  const StepRate rates{1, 0, 0};
  std::set<std::string> stages;
  EXPECT_DOUBLE_EQ(run_seconds(entry, ParameterSet(), three_sessions(), rates, false, stages), 1.1 * 110);
  EXPECT_EQ(stages, std::set<std::string>{"shared pretraining"});
  EXPECT_DOUBLE_EQ(run_seconds(entry, ParameterSet(), three_sessions(), rates, false, stages), 1.1 * 10);
}

// Under removal=fciac a removing session adds no class and the classes it removes leave what later
// sessions replay: the sizes count the classes present, not every session as an adding one.
TEST(CommandSizes, UnderRemovalCountTheClassesPresentBeforeEachSession) {
  RunOptions options;
  options.methods = "prototype";
  options.dataset = "simtex-mini";
  options.profile = "smoke";
  options.no_cache = true;
  options.assignments = {"removal=fciac", "sessions=4"};
  const RunSizes run = command_sizes(options).runs.begin()->second;
  // Sessions 1 and 3 add 5 classes each; session 2 removes one base and one novel class.
  EXPECT_EQ(run.removing_sessions, 1);
  EXPECT_EQ(run.total_classes(), run.base_classes + 10);
  EXPECT_EQ(run.classes_before(1), run.base_classes);
  EXPECT_EQ(run.classes_before(2), run.base_classes + 5);
  EXPECT_EQ(run.classes_before(3), run.base_classes + 3);
  EXPECT_EQ(run.base_classes_before(3), run.base_classes - 1);
  EXPECT_EQ(run.novel_classes_before(3), 4);
  options.assignments = {"sessions=3"};
  const RunSizes adding = command_sizes(options).runs.begin()->second;
  EXPECT_EQ(adding.total_classes(), adding.base_classes + 10);
  EXPECT_EQ(adding.classes_before(2), adding.base_classes + 5);
}

// The smoke profile's values as the methods read them on simtex-mini.
ParameterSet smoke(const std::string& method) {
  RunOptions options;
  options.methods = method;
  options.dataset = "simtex-mini";
  options.profile = "smoke";
  return method_parameters(options, method);
}

struct Totals {
  double trained = 0, inferred = 0, head_steps = 0;
};
Totals totals(const std::string& method) {
  Totals sum;
  for (const StageWork& stage : method_entry(method).work(smoke(method), three_sessions())) {
    sum.trained += stage.trained;
    sum.inferred += stage.inferred;
    sum.head_steps += stage.head_steps;
  }
  return sum;
}

TEST(MethodWork, PitsScAndItsCopVariantsCountTheirStagesAsTheyTrainThem) {
  // 3 pretraining epochs of 200, each scored on the 50 validation samples; 1 x 2 episodes of 6
  // kept and 2 mixed classes x (5 + 15), the epoch scored too; rows and validation after both
  // stages; 2 sessions of 25 shots, 20 classifier steps each.
  const Totals pits = totals("pits-sc");
  EXPECT_DOUBLE_EQ(pits.trained, 600 + 320);
  EXPECT_DOUBLE_EQ(pits.inferred, 3 * 50 + 50 + 2 * 250 + 50);
  EXPECT_DOUBLE_EQ(pits.head_steps, 40);
  const auto stages = method_entry("cop-fscil/cpi").work(smoke("cop-fscil/cpi"), three_sessions());
  EXPECT_EQ(stages.front().stage, PitsScMethod::kPretrainingStage) << "cpi can continue from pits-sc's";
  // PCQA's L_PIC embeds 2 probed copies of every trained sample; PSPC 10 probe views of every shot.
  const Totals cop = totals("cop-fscil");
  EXPECT_EQ(method_entry("cop-fscil").work(smoke("cop-fscil"), three_sessions()).front().stage, "pretraining");
  EXPECT_DOUBLE_EQ(cop.trained, 600 + 320);
  EXPECT_DOUBLE_EQ(cop.inferred, 2 * (600 + 320) + 3 * 50 + 50 + 2 * 250 + 50 * 11);
}

TEST(MethodWork, OtherMethodsCountTheirOwnStages) {
  const Totals prototype = totals("prototype");
  EXPECT_DOUBLE_EQ(prototype.trained, 600);
  EXPECT_DOUBLE_EQ(prototype.inferred, 3 * 50 + 250 + 50);  // validation after each epoch
  // Two masked views; assignment, 4 cached views and validation; 1 projector epoch of 2 batches;
  // sessions: 2 x 25 shots and validation, the 4 views of a memory of 50 + 25 s samples, and 10
  // projector epochs over that memory in batches of 64; a projector step is 7 head steps.
  const Totals orco = totals("orco");
  EXPECT_DOUBLE_EQ(orco.trained, 1200);
  EXPECT_DOUBLE_EQ(orco.inferred, 3 * 50 + 200 + 800 + 50 + (50 + 50 + 4 * 75) + (50 + 50 + 4 * 100));
  EXPECT_DOUBLE_EQ(orco.head_steps, 7 * (2 + 10 * 2 + 10 * 2));
  // ARP: every batch of 128 carries 8 x 5 supports, at 3.8 times a sample's cost: 2 batches per epoch.
  EXPECT_DOUBLE_EQ(totals("arp").trained, 3 * (200 + 3.8 * 2 * 40));
  // PAN: (a) on 6 of the 10 classes' share, (c) on all; 4 episodes of 2 x 5 x 20.
  EXPECT_DOUBLE_EQ(totals("pan").trained, 3 * 200 * 1.6 + 4 * 200);
  // pa-pct shares PAN's stages: both name them as the shared stage, so plan counts them once.
  for (const std::string method : {"pan", "pa-pct"}) {
    EXPECT_EQ(method_entry(method).work(smoke(method), three_sessions()).front().stage, PanMethod::kBaseStages);
    EXPECT_EQ(method_entry(method).shared_stages.count(PanMethod::kBaseStages), 1u) << method;
  }
  // AMFO: 10 epochs a session, each one batch: 10 draws of the 10 classes before it, 5 of each
  // new class and the 25 shots (150); then 10 x 15 + 50 (200); and 0.48 steps per earlier class.
  EXPECT_DOUBLE_EQ(totals("amfo").head_steps, 10 * (1 + 0.48 * 10) + 10 * (1 + 0.48 * 15));
  // ldc shares prototype's pretraining; its unit takes 20 smoke epochs of one step per base class,
  // 1.4 head steps each; its sessions 30 epochs over 25 shots and 5 draws of every seen class, in
  // batches of 50 with the last partial one kept: 100 samples (2 batches), then 125 (3).
  for (const std::string method : {"prototype", "ldc"}) {
    EXPECT_EQ(method_entry(method).work(smoke(method), three_sessions()).front().stage,
              PrototypeMethod::kPretrainingStage);
  }
  EXPECT_DOUBLE_EQ(totals("ldc").head_steps, 1.4 * 20 * 10 + 30 * (2 + 3));
  for (const auto& entry : method_registry()) EXPECT_TRUE(entry.work) << entry.name << " declares no work";
}

TEST(MachineRates, AreReadFromTheCacheFolderAndMeasuredWhereItHoldsNoneThatRead) {
  TemporaryDirectory cache;
  CommandSizes sizes;
  sizes.channels = 5;
  sizes.mel_bins = 64;
  sizes.frames = 24;
  sizes.threads = 1;
  sizes.pretraining_batch = 16;
  sizes.cache_dir = cache.path().string();
  const auto file = cache.path() / "step_rates.json";
  std::ofstream(file) << "{\"" << step_rates_key(sizes) << "\": {\"train_seconds_per_sample\": 0.002, "
                      << "\"infer_seconds_per_sample\": 0.0005, \"head_step_seconds\": 0.004}}";
  const Calibration from_file = machine_rates(sizes);
  const StepRate& stored = from_file.rates;
  EXPECT_TRUE(from_file.idle);
  EXPECT_NE(from_file.basis.find("rates stored in " + file.string()), std::string::npos) << from_file.basis;
  EXPECT_NE(from_file.basis.find("2.00 ms a sample trained"), std::string::npos) << from_file.basis;
  EXPECT_EQ(stored.train_seconds_per_sample, 0.002);
  EXPECT_EQ(stored.infer_seconds_per_sample, 0.0005);
  EXPECT_EQ(stored.head_step_seconds, 0.004);

  // Another thread count is another entry: measured (a training step costs more than inference).
  sizes.threads = 2;
  const StepRate measured = machine_rates(sizes).rates;
  EXPECT_GT(measured.train_seconds_per_sample, measured.infer_seconds_per_sample);
  EXPECT_GT(measured.infer_seconds_per_sample, 0);
  EXPECT_GT(measured.head_step_seconds, 0);
  sizes.threads = 1;
  EXPECT_EQ(machine_rates(sizes).rates.train_seconds_per_sample, 0.002) << "the stored entry is kept beside it";

  std::ofstream(file) << "{\"cut";  // a broken file is measured over
  EXPECT_GT(machine_rates(sizes).rates.train_seconds_per_sample, 0);
  sizes.cache_dir.clear();  // --no-cache: measured, nothing written
  std::filesystem::remove(file);
  EXPECT_GT(machine_rates(sizes).rates.train_seconds_per_sample, 0);
  EXPECT_FALSE(std::filesystem::exists(file));
}

// bf16 is another entry of the same file, beside fp32's.
TEST(MachineRates, APrecisionOtherThanFp32IsAnotherEntry) {
  CommandSizes sizes;
  sizes.threads = 1;
  const std::string fp32 = step_rates_key(sizes);
  sizes.precision = Precision::bf16;
  EXPECT_NE(step_rates_key(sizes), fp32);
  EXPECT_NE(step_rates_key(sizes).find("| bf16 |"), std::string::npos) << step_rates_key(sizes);
}

// Two cores, a ten-second calibration on two threads: whether other work held the cores meanwhile.
TEST(CalibrationLoad, IsIdleOnlyWhenOtherWorkHeldLessThanAFifthOfACoreAndItsThreadsRan) {
  const CalibrationLoad alone{10, 19.5, 20.1, 2, 2};
  EXPECT_NEAR(alone.others_cores(), 0.06, 1e-9);
  EXPECT_NEAR(alone.own_share(), 0.975, 1e-9);
  EXPECT_TRUE(alone.idle());
  // A neighbour on one core: our OpenMP threads spin while they wait, so their own share still
  // looks full; the machine's busy time shows the neighbour.
  const CalibrationLoad spinning_beside_a_neighbour{10, 19.0, 29.0, 2, 2};
  EXPECT_NEAR(spinning_beside_a_neighbour.others_cores(), 1.0, 1e-9);
  EXPECT_FALSE(spinning_beside_a_neighbour.idle());
  // A host taking the VM's time: our threads ran 60% of theirs, the rest is steal.
  EXPECT_FALSE((CalibrationLoad{10, 12.0, 20.1, 2, 2}.idle()));
  // /proc/stat unreadable: judged by its own share alone.
  EXPECT_TRUE((CalibrationLoad{10, 19.5, 0, 2, 2}.idle()));
  // Sixteen cores, two of them ours: six cores of other work leave ours alone.
  const CalibrationLoad on_a_larger_machine{10, 19.5, 80, 2, 16};
  EXPECT_NEAR(on_a_larger_machine.others_cores(), 6.05, 1e-9);
  EXPECT_EQ(on_a_larger_machine.contended_cores(), 0);
  EXPECT_TRUE(on_a_larger_machine.idle());
  // More threads than cores: its share counts the cores it could have had.
  EXPECT_TRUE((CalibrationLoad{10, 19.5, 20.1, 4, 2}.idle()));
}

}  // namespace
}  // namespace fscil
