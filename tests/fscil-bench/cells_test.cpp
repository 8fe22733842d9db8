// plan, slurm and cells: one cell per base, seed and grid cell; scripts whose values are checked.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <thread>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "datasets/hdf5_file.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"
#include "tests/fscil-bench/cli_support.h"
#include "tests/reports/session_runs.h"

namespace fscil {
namespace {

TEST(Cli, PlanListsOneCellPerBaseSessionSeedAndGridCell) {
  const CommandResult ablation = run_cli("plan --methods ablation --dataset simtex-mini --profile smoke --seeds 1-2 --no-estimate");
  ASSERT_EQ(ablation.exit_code, 0) << ablation.output;
  // pits-sc, then the two pairs of cop-fscil variants that share a base, each for two seeds.
  EXPECT_NE(ablation.output.find("6 cells"), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("    2  cop-fscil/cpi,cop-fscil/cpi+pspc "), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("    5  cop-fscil/cpi+pcqa,cop-fscil "), std::string::npos) << ablation.output;
  EXPECT_NE(ablation.output.find("small (4 base epochs)"), std::string::npos) << ablation.output;
  const CommandResult sweep = run_cli("plan --grid shot=1,5 --methods pits-sc,orco --dataset simtex --seeds 3 --no-estimate");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_NE(sweep.output.find("4 cells"), std::string::npos) << sweep.output;
  EXPECT_NE(sweep.output.find("    3  orco"), std::string::npos) << sweep.output;
  EXPECT_NE(sweep.output.find("shot=5"), std::string::npos) << sweep.output;
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --seeds 1-2 --cell 2"),
                        "--cell 2: this command has 2 cells, 0 to 1 (see: fscil-bench plan)");
  expect_one_error_line(run_cli("plan --dataset simtex-mini"), "--methods and --dataset are required");
  EXPECT_EQ(sweep.output.find("estimate"), std::string::npos) << sweep.output;
  EXPECT_EQ(sweep.output.find("class-variable"), std::string::npos) << "its sessions only add";

  // Issue 71: the class-variable protocol's sessions in the plan.
  const CommandResult variable = run_cli("plan --methods prototype --dataset simtex-mini --profile smoke --seeds 1 "
                                         "--set removal=fciac --set sessions=4 --no-estimate");
  ASSERT_EQ(variable.exit_code, 0) << variable.output;
  EXPECT_NE(variable.output.find("class-variable sessions (removal=fciac): sessions 1, 3 add 5 classes each; session 2 "
                                 "removes 9, 14; 18 of 20 classes remain\n"),
            std::string::npos)
      << variable.output;
}

// The seconds plan estimates for each line's cell (its last column, H:MM:SS).
std::vector<double> estimates_in(const std::string& plan) {
  std::vector<double> seconds;
  std::istringstream lines(plan);
  for (std::string line; std::getline(lines, line);) {
    int hours = 0, minutes = 0, rest = 0;
    const auto last = line.rfind(' ');
    if (line.find("base epochs)") != std::string::npos &&
        std::sscanf(line.c_str() + last + 1, "%d:%d:%d", &hours, &minutes, &rest) == 3) {
      seconds.push_back(hours * 3600.0 + minutes * 60.0 + rest);
    }
  }
  return seconds;
}

TEST(Cli, PlanEstimatesEachCellWithSharedWorkCountedOnce) {
  // The fast profile: estimates of a minute or more, whole seconds apart.
  const std::string command = "plan --methods ablation --dataset simtex-mini --profile fast --seeds 1-2 --threads 1";
  const CommandResult plan = run_cli(command);
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("  estimate\n"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("for all cells one after another on this machine"), std::string::npos) << plan.output;
  // Cells: pits-sc, then cpi with cpi+pspc, then cpi+pcqa with cop-fscil; seeds 1 and 2 each.
  const std::vector<double> seconds = estimates_in(plan.output);
  ASSERT_EQ(seconds.size(), 6u) << plan.output;
  for (double cell : seconds) EXPECT_GT(cell, 0) << plan.output;
  // cpi+pcqa trains its own pretraining, and L_PIC's probes.
  EXPECT_GT(seconds[4], seconds[0]) << plan.output;

  // cpi continues from pits-sc's pretraining of its seed; under --no-stage-cache it trains its own,
  // so its cell costs more against pits-sc's (a ratio: each plan may time the step anew).
  const CommandResult alone = run_cli(command + " --no-stage-cache");
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  const std::vector<double> alone_seconds = estimates_in(alone.output);
  ASSERT_EQ(alone_seconds.size(), 6u) << alone.output;
  EXPECT_GT(alone_seconds[2] / alone_seconds[0], seconds[2] / seconds[0]) << plan.output << alone.output;
}

// Issue 66 item 5: a plan over a folder of finished cells puts each estimate beside the time its
// runs took (their result files' total seconds), and over those cells measured against estimated.
TEST(Cli, PlanPutsTheMeasuredTimeOfFinishedCellsBesideTheEstimate) {
  TemporaryDirectory folder;
  const std::string data = "--methods prototype --dataset simtex-mini --no-cache --out " + (folder.path() / "runs").string();
  const std::string command = data + " --profile smoke --threads 1";
  ASSERT_EQ(run_cli(command + " --seeds 1 --quiet").exit_code, 0);
  const CommandResult plan = run_cli("plan " + command + " --seeds 1-2");
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("  estimate  measured\n"), std::string::npos) << plan.output;
  // A line ending in a time is one measured; seed 2 has no result file, so its line ends in '-'.
  ASSERT_EQ(estimates_in(plan.output).size(), 1u) << plan.output;
  EXPECT_NE(plan.output.find("measured 0:"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find(" for the 1 of 2 cells whose result files --out holds"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find(": measured / estimated "), std::string::npos) << plan.output;

  // Runs of another command are not this plan's measure: other threads, profile, split or values.
  for (const std::string& other : {data + " --profile smoke --threads 2", data + " --profile fast --threads 1",
                                   command + " --evaluate-on validation", command + " --set shot=3",
                                   command + " --set pretrain_epochs=2"}) {
    const CommandResult another = run_cli("plan " + other + " --seeds 1-2 --no-estimate");
    ASSERT_EQ(another.exit_code, 0) << another.output;
    EXPECT_EQ(another.output.find("measured"), std::string::npos) << other << another.output;
  }
  // A result file that does not read is named, as report names it.
  std::ofstream(folder.path() / "runs" / "results" / "prototype__simtex-mini__seed1.json") << "{}";
  const CommandResult broken = run_cli("plan " + command + " --seeds 1 --no-estimate");
  EXPECT_EQ(broken.exit_code, 1) << broken.output;
  EXPECT_NE(broken.output.find("prototype__simtex-mini__seed1.json"), std::string::npos) << broken.output;
}

// Processes that keep every core of this machine busy while they live.
class BusyCores {
 public:
  BusyCores() {
    for (unsigned core = 0; core < std::max(1u, std::thread::hardware_concurrency()); ++core) {
      const pid_t child = fork();
      if (child == 0) {
        for (volatile unsigned long spin = 0;; spin = spin + 1) {
        }
      }
      if (child > 0) children_.push_back(child);
    }
  }
  ~BusyCores() {
    for (const pid_t child : children_) {
      kill(child, SIGKILL);
      waitpid(child, nullptr, 0);
    }
  }
  BusyCores(const BusyCores&) = delete;
  BusyCores& operator=(const BusyCores&) = delete;

 private:
  std::vector<pid_t> children_;
};

// A calibration while other work holds the cores estimates the machine as loaded: plan says so,
// and keeps nothing that a later plan would take for this machine's idle speed.
TEST(Cli, PlanCalibratedUnderLoadSaysSoAndStoresNothing) {
  TemporaryDirectory cache;
  CommandResult plan{};
  {
    const BusyCores load;
    plan = run_cli("plan --methods prototype --dataset simtex-mini --profile smoke --threads 1 --cache-dir " +
                   cache.path().string());
  }
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("estimate's basis: rates measured now UNDER LOAD (other work held "), std::string::npos)
      << plan.output;
  EXPECT_NE(plan.output.find("not idle, and the rates are not stored"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("--precision bf16: not timed by this plan (machine loaded"), std::string::npos)
      << "two loaded calibrations make no ratio: " << plan.output;
  EXPECT_FALSE(std::filesystem::exists(cache.path() / "step_rates.json")) << plan.output;
}

TEST(Cli, SlurmWritesAnArrayTaskPerCellAndAMergeJobAndMissingOnlyKeepsCellsWithoutResults) {
  TemporaryDirectory folder;
  const std::string out = (folder.path() / "runs").string();
  const std::string command =
      "slurm --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2 --max-parallel 3 "
      "--time 2:00:00 --sbatch-arg=--account=abc --out " + out;
  const CommandResult written = run_cli(command);
  ASSERT_EQ(written.exit_code, 0) << written.output;
  EXPECT_NE(written.output.find("4 of 4 cells"), std::string::npos) << written.output;
  const std::string array = read_text(folder.path() / "runs" / "slurm" / "array.sbatch");
  for (const char* line : {"#SBATCH --array=0-3%3\n", "#SBATCH --cpus-per-task=1\n", "#SBATCH --signal=B:TERM@120\n",
                           "#SBATCH --requeue\n", "#SBATCH --time=2:00:00\n", "#SBATCH --account=abc\n",
                           "--methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2",
                           "--cell \"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-1}\" &\n",
                           "trap 'stop=1; [ -n \"${child:-}\" ] && kill -TERM \"$child\" 2>/dev/null' TERM\n"}) {
    EXPECT_NE(array.find(line), std::string::npos) << line << " not in\n" << array;
  }
  const std::string merge = read_text(folder.path() / "runs" / "slurm" / "merge.sbatch");
  EXPECT_NE(merge.find("report --results " + out + " --methods prototype,cop-fscil\n"), std::string::npos) << merge;
  EXPECT_NE(merge.find(" plan --methods prototype,cop-fscil "), std::string::npos) << merge;
  EXPECT_NE(merge.find(" --missing-only\n"), std::string::npos) << merge;
  EXPECT_EQ(std::system(("bash -n " + (folder.path() / "runs" / "slurm" / "array.sbatch").string()).c_str()), 0);
  EXPECT_EQ(array.find("suggestion"), std::string::npos) << "a --time given is used as given";

  // Without --time: the plan's suggestion, said so in the script; never less than 10 minutes.
  TemporaryDirectory untimed;
  const CommandResult suggested = run_cli("slurm --methods prototype --dataset simtex-mini --profile smoke --out " +
                                          (untimed.path() / "runs").string());
  ASSERT_EQ(suggested.exit_code, 0) << suggested.output;
  EXPECT_NE(suggested.output.find("--time 0:10:00 suggested from the plan"), std::string::npos) << suggested.output;
  const std::string suggested_array = read_text(untimed.path() / "runs" / "slurm" / "array.sbatch");
  EXPECT_NE(suggested_array.find("#SBATCH --time=0:10:00\n"), std::string::npos) << suggested_array;
  EXPECT_NE(suggested_array.find("# --time was not given"), std::string::npos) << suggested_array;
  EXPECT_EQ(read_text(untimed.path() / "runs" / "slurm" / "merge.sbatch").find("--time"), std::string::npos);

  // Cells 0 (prototype, seed 1) and 3 (cop-fscil, seed 2) have their result files.
  std::filesystem::create_directories(folder.path() / "runs" / "results");
  const auto results = folder.path() / "runs" / "results";
  std::ofstream(results / "prototype__simtex-mini__seed1.json")
      << to_json_text(run_with_accuracies("prototype", "simtex-mini", 1, {90}));
  std::ofstream(results / "cop-fscil__simtex-mini__seed2.json")
      << to_json_text(run_with_accuracies("cop-fscil", "simtex-mini", 2, {90}));
  const CommandResult missing = run_cli(command + " --missing-only");
  ASSERT_EQ(missing.exit_code, 0) << missing.output;
  EXPECT_NE(missing.output.find("2 of 4 cells"), std::string::npos) << missing.output;
  EXPECT_NE(read_text(folder.path() / "runs" / "slurm" / "array.sbatch").find("#SBATCH --array=1-2%3\n"), std::string::npos);

  // plan --missing-only, the merge job's check: the same two cells, and a failure while there are any.
  const std::string plan = "plan --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1-2 --no-estimate --out " + out;
  const CommandResult still_missing = run_cli(plan + " --missing-only");
  EXPECT_EQ(still_missing.exit_code, 1) << still_missing.output;
  EXPECT_NE(still_missing.output.find("2 cells"), std::string::npos) << still_missing.output;
  EXPECT_NE(still_missing.output.find("    1  prototype"), std::string::npos) << still_missing.output;
  EXPECT_NE(still_missing.output.find("    2  cop-fscil"), std::string::npos) << still_missing.output;

  // A damaged result file is not a cell done: one error naming it, before any cell is counted.
  const std::string whole = read_text(results / "prototype__simtex-mini__seed1.json");
  std::ofstream(results / "prototype__simtex-mini__seed1.json") << whole.substr(0, whole.size() / 2);
  const CommandResult truncated = run_cli(plan + " --missing-only");
  expect_one_error_line(truncated, "prototype__simtex-mini__seed1.json");
  EXPECT_EQ(truncated.exit_code, 1) << truncated.output;
  expect_one_error_line(run_cli(command + " --missing-only"), "prototype__simtex-mini__seed1.json");
  std::ofstream(results / "prototype__simtex-mini__seed1.json") << whole;

  expect_one_error_line(run_cli(command + " --submit", "PATH=/nonexistent"), "sbatch --parsable");
  expect_one_error_line(run_cli(command + " --sbatch-arg=account=abc"), "expected one sbatch option on one line");
  expect_one_error_line(run_cli(command + " '--sbatch-arg=--account=a b'"), "expected one sbatch option on one line");
  // A newline is shown, not printed: the line would end before it says what is wrong.
  expect_one_error_line(run_cli(command + " \"$(printf -- '--sbatch-arg=--account=a\\nrm -rf /')\""),
                        "--sbatch-arg '--account=a\\nrm -rf /': expected one sbatch option on one line");
  // The array, threads and logs are the command's: neither an option nor its prefix may set them over.
  // Nor may one undo the SIGTERM-safe stop, the requeue, the error log or --time, --mem, --partition
  // (round seven: each added a second, contradicting #SBATCH line).
  for (const char* computed : {"--array=0-99", "--arr=1", "--cpus-per-task=64", "--output=/tmp/x", "--error=/tmp/x",
                               "--no-requeue", "--requeue", "--time=2:00:00", "--mem=1G", "--partition=b"}) {
    const CommandResult overridden = run_cli(command + " --sbatch-arg=" + computed);
    expect_one_error_line(overridden, "is fscil-bench's to set");
    EXPECT_EQ(overridden.exit_code, 2) << overridden.output;
  }
  for (const char* signal : {"--signal=KILL", "--signal=B:USR1@60", "--sig=TERM@60", "--signal=B:TERM@0",
                             "--signal=B:TERM@65536"}) {
    const CommandResult overridden = run_cli(command + " --sbatch-arg=" + signal);
    expect_one_error_line(overridden, "expected --signal=B:TERM@SECONDS, 60 to 65535, to move it (fscil-bench's is "
                                      "B:TERM@120)");
    EXPECT_EQ(overridden.exit_code, 2) << overridden.output;
  }
  EXPECT_EQ(run_cli(command + " --sbatch-arg=--account=abc --sbatch-arg=--qos=short --sbatch-arg=--job-name=mine "
                              "--sbatch-arg=--signal=B:TERM@300").exit_code, 0);
  // The signal moved: one --signal line, the user's.
  const std::string moved = read_text(folder.path() / "runs" / "slurm" / "array.sbatch");
  EXPECT_NE(moved.find("#SBATCH --signal=B:TERM@300\n"), std::string::npos) << moved;
  EXPECT_EQ(moved.find("--signal=", moved.find("--signal=") + 1), std::string::npos) << moved;
  // Values that reach #SBATCH lines are checked as what they are, before anything is written.
  TemporaryDirectory refused;
  const std::string elsewhere = "slurm --methods prototype --dataset simtex-mini --profile smoke --out " +
                                (refused.path() / "runs").string();
  for (const char* bad : {"'x; rm -rf /'", "'cpu\ntouch PWNED'", "'$(touch PWNED)'", "'`touch PWNED`'", "'a b'"}) {
    const CommandResult partition = run_cli(elsewhere + " --partition " + bad);
    expect_one_error_line(partition, "--partition");
    EXPECT_NE(partition.output.find("expected a Slurm partition name"), std::string::npos) << partition.output;
    EXPECT_EQ(partition.exit_code, 2);
    expect_one_error_line(run_cli(elsewhere + " --time " + bad), "expected a Slurm time limit");
    expect_one_error_line(run_cli(elsewhere + " --mem " + bad), "expected a Slurm memory size");
  }
  EXPECT_FALSE(std::filesystem::exists(refused.path() / "runs" / "slurm")) << "nothing written for a refused value";
  const CommandResult spaced = run_cli("slurm --methods prototype --dataset simtex-mini --profile smoke --out '" +
                                       (refused.path() / "o 3").string() + "'");
  expect_one_error_line(spaced, "an #SBATCH --output line cannot hold this path");
  // (A --time beside --partition and --mem spares each a calibration of the step for its suggestion.)
  for (const char* good : {"--partition gpu,cpu_long --time 1:00:00", "--time 1-12:00:00", "--time 90", "--mem 512M --time 1:00:00"}) {
    EXPECT_EQ(run_cli(elsewhere + " " + good).exit_code, 0) << good;
  }
  expect_one_error_line(run_cli(plan + " --cell 1"), "--cell: expected a run or sweep command");
}

}  // namespace
}  // namespace fscil
