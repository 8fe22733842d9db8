// --resume after SIGKILL and SIGTERM: the numbers of an uninterrupted run.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <csignal>
#include <thread>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "datasets/hdf5_file.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"
#include "tests/fscil-bench/cli_support.h"

namespace fscil {
namespace {

// A run killed with SIGKILL once its first cop-fscil checkpoint exists, i.e. during an
// incremental session of cop-fscil, after prototype had finished.
class KilledRun : public ::testing::Test {
 protected:
  static constexpr const char* kOptions =
      " --methods prototype,cop-fscil --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache";

  void SetUp() override {
    const std::string pid_file = (out.path() / "pid").string();
    ASSERT_EQ(std::system((built_program() + options + " --out " + out.path().string() +
                           " > /dev/null 2>&1 & echo $! > " + pid_file).c_str()), 0);
    const auto started = std::chrono::steady_clock::now();
    while (!std::filesystem::exists(checkpoint()) && std::chrono::steady_clock::now() - started < std::chrono::minutes(5)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    int pid = 0;
    std::ifstream(pid_file) >> pid;
    ASSERT_GT(pid, 0);
    ::kill(pid, SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // not our child: no waitpid, let it die
  }
  std::filesystem::path checkpoint() const {
    return out.path() / "checkpoints" / "cop-fscil__simtex-mini__seed1.ckpt";
  }
  std::filesystem::path result(const std::string& method) const {
    return out.path() / "results" / (method + "__simtex-mini__seed1.json");
  }
  std::string options = kOptions;
  TemporaryDirectory out;
};

// Issue 71: the same under class-variable sessions (simtex-mini: session 1 adds, 2 removes, 3
// adds), killed during cop-fscil's sessions: the resumed run goes through a removing session and
// an adding one after it.
class KilledClassVariableRun : public KilledRun {
 protected:
  KilledClassVariableRun() { options += " --set removal=fciac --set sessions=4"; }
};

TEST_F(KilledClassVariableRun, ResumeEndsWithExactlyTheResultsOfAnUninterruptedRun) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  ASSERT_FALSE(std::filesystem::exists(result("cop-fscil"))) << "the run finished before it was killed";
  const CommandResult resumed = run_cli(options + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  TemporaryDirectory uninterrupted;
  ASSERT_EQ(run_cli(options + " --out " + uninterrupted.path().string()).exit_code, 0);
  for (const std::string method : {"prototype", "cop-fscil"}) {
    const std::string expected = accuracies_in(uninterrupted.path() / "results" / (method + "__simtex-mini__seed1.json"));
    EXPECT_EQ(std::count(expected.begin(), expected.end(), ':'), 4);
    EXPECT_EQ(accuracies_in(result(method)), expected) << method;
  }
  const std::string sessions = read_text(result("cop-fscil"));
  EXPECT_NE(sessions.find("\"seen_classes\": 13"), std::string::npos) << "session 2 scored 13 classes";
  EXPECT_NE(sessions.find("\"seen_classes\": 18"), std::string::npos) << "session 3 scored 18";
}

TEST_F(KilledRun, ResumeEndsWithExactlyTheResultsOfAnUninterruptedRun) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  ASSERT_TRUE(std::filesystem::exists(result("prototype")));
  ASSERT_FALSE(std::filesystem::exists(result("cop-fscil"))) << "the run finished before it was killed";
  const CommandResult resumed = run_cli(std::string(kOptions) + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_FALSE(std::filesystem::exists(checkpoint())) << "a finished run leaves no checkpoint";

  TemporaryDirectory uninterrupted;
  ASSERT_EQ(run_cli(std::string(kOptions) + " --out " + uninterrupted.path().string()).exit_code, 0);
  for (const std::string method : {"prototype", "cop-fscil"}) {
    const std::string expected = accuracies_in(uninterrupted.path() / "results" / (method + "__simtex-mini__seed1.json"));
    EXPECT_EQ(std::count(expected.begin(), expected.end(), ':'), 3);
    EXPECT_EQ(accuracies_in(result(method)), expected) << method;
  }
}

TEST_F(KilledRun, AnEmptyResultsFolderStillResumesAndAMistypedResumePathIsRefused) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  expect_one_error_line(run_cli(std::string(kOptions) + " --resume " + (out.path() / "typo").string()),
                        "typo: no such folder, nothing to resume");
  // Another --set: the finished run's refusal says what differs (round seven: two hashes).
  expect_one_error_line(run_cli(std::string(kOptions) + " --set temperature=8 --resume " + out.path().string()),
                        "prototype__simtex-mini__seed1.json: a result of another run (temperature: 16 there, 8 here)");
  std::filesystem::remove(result("prototype"));  // results/ is now empty, the checkpoint still there
  std::string loud = kOptions;
  loud.erase(loud.find(" --quiet"), 8);
  const CommandResult resumed = run_cli(loud + " --resume " + out.path().string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("continuing after session"), std::string::npos) << resumed.output;
  EXPECT_TRUE(std::filesystem::exists(result("prototype")));
  EXPECT_TRUE(std::filesystem::exists(result("cop-fscil")));
}

TEST_F(KilledRun, ACorruptOrForeignCheckpointIsRefusedWithOneLine) {
  ASSERT_TRUE(std::filesystem::exists(checkpoint()));
  const auto size = std::filesystem::file_size(checkpoint());
  const auto saved = out.path() / "saved.ckpt";
  std::filesystem::copy_file(checkpoint(), saved);
  std::filesystem::resize_file(checkpoint(), size - 100);
  expect_one_error_line(run_cli(std::string(kOptions) + " --resume " + out.path().string()), "corrupt checkpoint");
  EXPECT_FALSE(std::filesystem::exists(result("cop-fscil")));

  // The same file under another seed's name: a checkpoint of another run. Resumed with --seeds 2
  // beside seed 1's checkpoint, the command would leave seed 1 behind: refused first.
  std::filesystem::rename(saved, out.path() / "checkpoints" / "cop-fscil__simtex-mini__seed2.ckpt");
  expect_one_error_line(run_cli(" --methods cop-fscil --dataset simtex-mini --profile smoke --threads 1 --quiet "
                                "--no-cache --seeds 2 --resume " + out.path().string()),
                        "cop-fscil__simtex-mini__seed1.ckpt is the checkpoint of a run this command does not make");
  std::filesystem::remove(checkpoint());
  // Stage progress the kill may have left beside it (a stop between the checkpoint and its removal).
  std::filesystem::remove_all(std::filesystem::path(checkpoint()).replace_extension(".progress"));
  expect_one_error_line(run_cli(" --methods cop-fscil --dataset simtex-mini --profile smoke --threads 1 --quiet "
                                "--no-cache --seeds 2 --resume " + out.path().string()),
                        "checkpoint of another run");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "results" / "cop-fscil__simtex-mini__seed2.json"));
}

// Every line of a result file but its times and memory: scores, diagnostics, the training log.
std::string all_but_times(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, kept;
  while (std::getline(in, line)) {
    if (line.find("seconds") == std::string::npos && line.find("resident") == std::string::npos) kept += line + "\n";
  }
  return kept;
}

// Starts `command` in the background and kills it (SIGKILL) once `file` exists; returns its output.
std::string kill_once_written(const std::string& command, const std::filesystem::path& file) {
  const std::filesystem::path output = file.parent_path().parent_path().parent_path().parent_path() / "output";
  const std::string script = fmt::format(
      "{} > {} 2>&1 & pid=$!; for i in $(seq 30000); do [ -f {} ] && break; kill -0 $pid || break; "
      "sleep 0.01; done; kill -KILL $pid; wait $pid",
      command, output.string(), file.string());
  std::system(("bash -c '" + script + "' 2> /dev/null").c_str());  // not bash's note of the kill
  return read_text(output);
}

// A long base stage keeps its progress (FSCIL_BENCH_KEEP_PROGRESS_SECONDS=0: every epoch), so a run
// killed within its pretraining, and again within its pseudo-incremental stage, continues each time
// from the last epoch kept, to a result file identical to an uninterrupted run's but for its times:
// scores, diagnostics and every epoch of the training log. The PCQA variant keeps its adapter too.
TEST(Cli, ARunKilledWithinItsBaseStagesContinuesFromTheLastKeptEpochToTheSameResult) {
  TemporaryDirectory folder;
  const std::string options = " --methods cop-fscil/cpi+pcqa --dataset simtex-mini --profile smoke --threads 1 "
                              "--no-cache --set pit_epochs=3";
  const std::string keep_every_epoch = "FSCIL_BENCH_KEEP_PROGRESS_SECONDS=0 ";
  const auto killed = folder.path() / "killed";
  const auto progress = killed / "checkpoints" / "cop-fscil_cpi_pcqa__simtex-mini__seed1.progress";
  const auto result = killed / "results" / "cop-fscil_cpi_pcqa__simtex-mini__seed1.json";

  kill_once_written(keep_every_epoch + built_program() + options + " --out " + killed.string(), progress / "pretrain.ckpt");
  ASSERT_TRUE(std::filesystem::exists(progress / "pretrain.ckpt"));
  ASSERT_FALSE(std::filesystem::exists(progress / "pseudo-incremental.ckpt")) << "killed after the pretraining";
  const auto from_cache = folder.path() / "from-cache";  // continued once the stage cache holds its base
  std::filesystem::copy(killed, from_cache, std::filesystem::copy_options::recursive);
  // Killed within the pretraining (3 epochs): the next process continues after epoch 1 or 2.
  const std::string second = kill_once_written(keep_every_epoch + built_program() + options + " --resume " +
                                                   killed.string(), progress / "pseudo-incremental.ckpt");
  const auto continued_after = [](const std::string& output, const std::string& stage) {
    const std::string note = stage + ": continuing after epoch ";
    const auto at = output.find(note);
    return at == std::string::npos ? -1 : std::atoi(output.c_str() + at + note.size());
  };
  EXPECT_GE(continued_after(second, "pretrain"), 1) << second;
  EXPECT_LE(continued_after(second, "pretrain"), 2) << "killed within the stage, not after it: " << second;
  ASSERT_FALSE(std::filesystem::exists(result)) << "the run finished before it was killed";
  const CommandResult resumed = run_cli(options + " --resume " + killed.string(), keep_every_epoch);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(continued_after(resumed.output, "pretrain"), 3) << resumed.output;
  EXPECT_GE(continued_after(resumed.output, "pseudo-incremental"), 1) << resumed.output;
  EXPECT_LE(continued_after(resumed.output, "pseudo-incremental"), 2) << resumed.output;
  EXPECT_FALSE(std::filesystem::exists(progress)) << "a finished base leaves no progress behind";

  // The uninterrupted run fills a stage cache (the cache changes no number).
  std::string cached = options;
  cached.replace(cached.find("--no-cache"), 10, "--cache-dir " + (folder.path() / "cache").string());
  const CommandResult whole = run_cli(cached + " --quiet --out " + (folder.path() / "whole").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const std::string expected = all_but_times(folder.path() / "whole" / "results" / result.filename());
  EXPECT_NE(expected.find("\"stage\": \"pseudo-incremental\""), std::string::npos) << expected;
  EXPECT_EQ(all_but_times(result), expected);

  // A run killed within its pretraining, continued once the cache holds its base, takes that base,
  // and its progress goes with the run it belonged to.
  const auto cached_progress = from_cache / "checkpoints" / progress.filename();
  ASSERT_TRUE(std::filesystem::exists(cached_progress / "pretrain.ckpt"));
  const CommandResult continued = run_cli(cached + " --quiet --resume " + from_cache.string());
  ASSERT_EQ(continued.exit_code, 0) << continued.output;
  std::string from_cached_base = all_but_times(from_cache / "results" / result.filename());
  const std::string noted = "    \"base_training\": \"from the stage cache\",\n";  // the one line it adds
  ASSERT_NE(from_cached_base.find(noted), std::string::npos) << from_cached_base;
  EXPECT_EQ(from_cached_base.erase(from_cached_base.find(noted), noted.size()), expected);
  EXPECT_FALSE(std::filesystem::exists(cached_progress)) << "a run whose base came from the cache left progress";

  expect_one_error_line(run_cli(options + " --out " + (folder.path() / "other").string(),
                                "FSCIL_BENCH_KEEP_PROGRESS_SECONDS=soon"),
                        "FSCIL_BENCH_KEEP_PROGRESS_SECONDS='soon': expected seconds between two keepings");
}

TEST(Cli, ARunStoppedBySigtermKeepsItsCheckpointAndResumesToTheSameNumbers) {
  TemporaryDirectory folder;
  const std::string options = " --methods cop-fscil --dataset simtex-mini --profile smoke --threads 1 --no-cache --quiet";
  const auto stopped = folder.path() / "stopped";
  const auto checkpoint = stopped / "checkpoints" / "cop-fscil__simtex-mini__seed1.ckpt";
  const std::string script = fmt::format(
      "{} {} --out {} 2> {}/stderr & pid=$!; for i in $(seq 6000); do [ -f {} ] && break; kill -0 $pid || break; "
      "sleep 0.02; done; kill -TERM $pid; wait $pid",
      built_program(), options, stopped.string(), folder.path().string(), checkpoint.string());
  const int status = std::system(("bash -c '" + script + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 143) << read_text(folder.path() / "stderr");
  EXPECT_NE(read_text(folder.path() / "stderr").find("fscil-bench: stopped by SIGTERM: finished sessions are kept"),
            std::string::npos);
  ASSERT_TRUE(std::filesystem::exists(checkpoint));
  EXPECT_FALSE(std::filesystem::exists(stopped / "results" / "cop-fscil__simtex-mini__seed1.json"));
  const CommandResult resumed = run_cli(options + " --resume " + stopped.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const CommandResult whole = run_cli(options + " --out " + (folder.path() / "whole").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_EQ(accuracies_in(stopped / "results" / "cop-fscil__simtex-mini__seed1.json"),
            accuracies_in(folder.path() / "whole" / "results" / "cop-fscil__simtex-mini__seed1.json"));
}

// The embeddings --save-embeddings keeps of every session, as `file` holds them.
std::vector<std::vector<float>> saved_sessions(const std::filesystem::path& file) {
  std::vector<std::vector<float>> sessions;
  for (const int session : read_hdf5_integers(file, "sessions")) {
    std::vector<float> values = read_hdf5_floats(file, fmt::format("session_{}_embeddings", session), 2).values;
    for (const int label : read_hdf5_integers(file, fmt::format("session_{}_labels", session))) {
      values.push_back(static_cast<float>(label));
    }
    sessions.push_back(std::move(values));
  }
  return sessions;
}

// A resumed run cannot embed again the sessions before the one it continues from: they were kept
// beside its checkpoint (once, the resumed file held only the sessions after the stop).
TEST(Cli, ARunStoppedAfterASessionKeepsTheEmbeddingsOfEverySessionWhenResumed) {
  TemporaryDirectory folder;
  const std::string options =
      " --methods orco --dataset simtex-mini --profile smoke --threads 1 --no-cache --save-embeddings all";
  const auto stopped = folder.path() / "stopped";
  const std::string script = fmt::format(
      "{} {} --out {} 2> {}/stderr & pid=$!; for i in $(seq 6000); do grep -q \"session 2/2\" {}/stderr && break; "
      "kill -0 $pid || break; sleep 0.02; done; kill -TERM $pid; wait $pid",
      built_program(), options, stopped.string(), folder.path().string(), folder.path().string());
  const int status = std::system(("bash -c '" + script + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 143) << read_text(folder.path() / "stderr");
  const auto checkpoints = stopped / "checkpoints";
  ASSERT_TRUE(std::filesystem::exists(checkpoints / "orco__simtex-mini__seed1.ckpt"));
  ASSERT_EQ(read_hdf5_integers(checkpoints / "orco__simtex-mini__seed1.embeddings.h5", "sessions"),
            (std::vector<std::int32_t>{0, 1}));

  const CommandResult resumed = run_cli(options + " --quiet --resume " + stopped.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(std::filesystem::is_empty(checkpoints)) << "a finished run leaves neither checkpoint nor embeddings";
  const CommandResult whole = run_cli(options + " --quiet --out " + (folder.path() / "whole").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto kept = saved_sessions(stopped / "embeddings" / "orco__simtex-mini__seed1.h5");
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept, saved_sessions(folder.path() / "whole" / "embeddings" / "orco__simtex-mini__seed1.h5"));
}

// A base from the stage cache is scored, not trained: its session's embeddings are kept all the same.
TEST(Cli, ABaseFromTheStageCacheKeepsItsSessionsEmbeddings) {
  TemporaryDirectory folder;
  const std::string options = " --methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet "
                              "--save-embeddings all --cache-dir " + (folder.path() / "cache").string();
  ASSERT_EQ(run_cli(options + " --out " + (folder.path() / "trained").string()).exit_code, 0);
  const CommandResult cached = run_cli(options + " --out " + (folder.path() / "cached").string());
  ASSERT_EQ(cached.exit_code, 0) << cached.output;
  EXPECT_NE(read_text(folder.path() / "cached" / "results" / "prototype__simtex-mini__seed1.json")
                .find("from the stage cache"), std::string::npos);
  const auto file = std::filesystem::path("embeddings") / "prototype__simtex-mini__seed1.h5";
  const auto kept = saved_sessions(folder.path() / "cached" / file);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept, saved_sessions(folder.path() / "trained" / file));
}

}  // namespace
}  // namespace fscil
