// The program as a whole: list, --version, one clear line for bad names and garbage, output that cannot be written.
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
#include <sstream>
#include <string>
#include <vector>

#include "datasets/hdf5_file.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"
#include "tests/fscil-bench/cli_support.h"

namespace fscil {
namespace {

TEST(Cli, ListsMethodsDatasetsAndProfiles) {
  const CommandResult result = run_cli("list");
  EXPECT_EQ(result.exit_code, 0);
  for (const char* name : {"prototype", "simtex", "simtex-lmt", "simtex-mini", "lmt108", "smoke", "fast", "paper"}) {
    EXPECT_NE(result.output.find(name), std::string::npos) << name;
  }
}

// The lines of `text` longer than `columns`.
std::vector<std::string> lines_wider_than(const std::string& text, std::size_t columns) {
  std::vector<std::string> wide;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.size() > columns) wide.push_back(line);
  }
  return wide;
}

TEST(Cli, HelpAndListingsFitAHundredColumnsWhateverColumnsSays) {
  for (const char* command : {"--help", "--help-all", "list", "plan --help", "sweep --help", "run-cells --help",
                              "slurm --help", "reproduce --help", "reproduce --list", "rerun --help", "report --help",
                              "logmel --help", "check --help"}) {
    const CommandResult result = run_cli(command, "COLUMNS=300");
    EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.output;
    EXPECT_EQ(lines_wider_than(result.output, 100), std::vector<std::string>()) << command;
  }
}

TEST(Cli, ASubcommandsHelpNamesTheRunOptionsItTakesAndListNamesTheReproductions) {
  for (const char* command : {"plan --help", "sweep --help", "run-cells --help", "slurm --help", "reproduce --help",
                              "rerun --help"}) {
    const std::string help = run_cli(command).output;
    for (const char* option : {"--methods", "--dataset", "--seeds", "--out", "--threads"}) {
      EXPECT_NE(help.find(option), std::string::npos) << command << " does not name " << option << ":\n" << help;
    }
  }
  const std::string listed = run_cli("list").output;
  EXPECT_NE(listed.find("\n  prototype              cosine classifier"), std::string::npos) << listed;  // aligned
  for (const char* reproduction : {"reproductions", "fewer-shot", "nps", "selection-bias"}) {
    EXPECT_NE(listed.find(reproduction), std::string::npos) << reproduction;
  }
}

TEST(Cli, VersionNamesTheReleaseTheCommitAndTheLibraries) {
  const CommandResult version = run_cli("--version");
  EXPECT_EQ(version.exit_code, 0) << version.output;
  EXPECT_EQ(version.output.rfind(fmt::format("fscil-bench {} (commit {})\n", built_version(), built_commit()), 0), 0u)
      << version.output;
  for (const char* library : {"  libtorch   1.", "  fftw       fftw-3.", "  hdf5       1.", "  libsndfile libsndfile-1.",
                              "  openblas   ", "  compiler   "}) {
    EXPECT_NE(version.output.find(library), std::string::npos) << library << " in\n" << version.output;
  }
}

// The kernels each library chose are named, and lowered by the variables the reference protocol
// sets (tools/reference_protocol.sh).
TEST(Cli, VersionNamesTheKernelsTheLibrariesChose) {
  const CommandResult lowered =
      run_cli("--version", "ATEN_CPU_CAPABILITY=default OPENBLAS_CORETYPE=Haswell ONEDNN_MAX_CPU_ISA=SSE41");
  EXPECT_EQ(lowered.exit_code, 0) << lowered.output;
  EXPECT_NE(lowered.output.find("  kernels    aten=NO_AVX openblas=Haswell onednn=sse41\n"), std::string::npos)
      << lowered.output;
  const CommandResult own = run_cli("--version");
  EXPECT_EQ(own.exit_code, 0) << own.output;
  EXPECT_NE(own.output.find("  kernels    aten=AVX"), std::string::npos) << own.output;
}

TEST(Cli, UnknownNamesAndGarbageGetOneClearLine) {
  TemporaryDirectory out;
  const std::string common = " --quiet --no-cache --out " + out.path().string();
  // A named choice's refusal names the option typed and the value, as a usage error (exit 2, as
  // --seeds and --threads are).
  const CommandResult no_such_method = run_cli("--methods nosuch --dataset simtex-mini" + common);
  expect_one_error_line(no_such_method, "--methods 'nosuch': expected all, ablation or one of prototype,");
  EXPECT_EQ(no_such_method.exit_code, 2);
  const CommandResult no_such_data = run_cli("--methods prototype --dataset nosuch --no-cache --out " + out.path().string());
  expect_one_error_line(no_such_data, "--dataset 'nosuch': expected one of simtex,");
  EXPECT_EQ(no_such_data.exit_code, 2);
  EXPECT_EQ(no_such_data.output.find("preparing dataset"), std::string::npos) << "no progress before the refusal";
  const std::pair<std::string, std::string> refused_choices[] = {
      {"--profile turbo", "--profile 'turbo': expected one of smoke, fast, paper"},
      {"--split-mode X", "--split-mode 'X': expected recording or segment"},
      {"--class-order Natural", "--class-order 'Natural': expected natural or shuffled"},
      {"--selection best", "--selection 'best': expected last, validation or test-oracle"},
      {"--precision fp16", "--precision 'fp16': expected fp32 or bf16"},
      {"--save-embeddings x", "--save-embeddings x: expected last, all or session numbers from 0"},
      {"--cell 2147483648", "--cell '2147483648': a whole number too large for this option"},
      {"--dataset unexpected", "--dataset 'unexpected': expected one of simtex,"}};
  for (const auto& [option, refusal] : refused_choices) {
    const bool dataset = option.rfind("--dataset", 0) == 0;
    const CommandResult refused =
        run_cli(std::string("--methods prototype ") + (dataset ? "" : "--dataset simtex-mini ") + option + common);
    expect_one_error_line(refused, refusal);
    EXPECT_EQ(refused.exit_code, 2) << option;
  }
  // A subcommand's missing argument points at that subcommand's help.
  expect_one_error_line(run_cli("report"), "--results is required (try: fscil-bench report --help)");
  expect_one_error_line(run_cli("sweep --grid"), "(try: fscil-bench sweep --help)");
  // A malformed option is a usage error (exit 2) whenever it is found, as CLI11's own are.
  const CommandResult bad_seeds = run_cli("--methods prototype --dataset simtex-mini --seeds 1,x" + common);
  expect_one_error_line(bad_seeds, "--seeds '1,x'");
  EXPECT_EQ(bad_seeds.exit_code, 2);
  expect_one_error_line(run_cli("--methods prototype --dataset haptex" + common), "needs --data-root");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set no_such_knob=3" + common),
                        "--set no_such_knob");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set pretrain_epochs=many" + common),
                        "pretrain_epochs='many': expected an integer");
  // Nonsense values are refused by their owner before anything trains.
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --set temperature=0" + common),
                        "temperature='0': expected a number > 0");
  expect_one_error_line(run_cli("--methods pits-sc --dataset simtex-mini --set lr_gamma=-1" + common),
                        "lr_gamma='-1': expected a number in (0, 1]");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --features disk" + common),
                        "--features 'disk': expected auto, memory or on-demand");
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --threads -1" + common),
                        "--threads: expected a number in [0, 256]");
  // Far above any machine's cores: refused before a thread starts, as a usage error.
  const CommandResult many_threads = run_cli("--methods prototype --dataset simtex-mini --threads 100000" + common);
  expect_one_error_line(many_threads, "--threads: expected a number in [0, 256]");
  EXPECT_EQ(many_threads.exit_code, 2);
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --max-memory 4X" + common),
                        "--max-memory '4X': expected a size such as 4G");
  expect_one_error_line(run_cli("logmel --input a.h5 --output b.h5 --sample-rate nan --n-fft 128 --hop 16 --n-mels 64"),
                        "--sample-rate: expected a number in (0, 10000000]");
  // CLI11's own complaints read like ours: one prefixed line, exit 2.
  const CommandResult unknown_flag = run_cli("--methods prototype --dataset simtex-mini --bogus" + common);
  EXPECT_EQ(unknown_flag.exit_code, 2);
  expect_one_error_line(unknown_flag, "--bogus");
  EXPECT_FALSE(std::filesystem::exists(out.path() / "summary.csv"));
  // A result file of raw bytes and terminal escapes: the error line spells them out.
  std::filesystem::create_directories(out.path() / "results");
  std::ofstream(out.path() / "results" / "odd.json") << "{\"method\": \"\xff\x1b[2J\x07" << std::string(5000, 'x');
  const CommandResult odd = run_cli("report --results " + out.path().string());
  expect_one_error_line(odd, "odd.json: not JSON (parse error at line 1, column 13");
  EXPECT_EQ(odd.output.find_first_of("\x1b\x07\xff"), std::string::npos) << odd.output;
}

TEST(Cli, OutputThatCannotBeWrittenIsAFailure) {
  // Tables to a full disk: stdout goes to /dev/full, stderr still to the pipe.
  const std::string command = built_program() + " list 2>&1 >/dev/full";
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 512> line{};
  const std::string said = fgets(line.data(), line.size(), pipe) != nullptr ? line.data() : "";
  const int status = pclose(pipe);
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(said, "fscil-bench: error: standard output: cannot write (No space left on device)\n");
}

}  // namespace
}  // namespace fscil
