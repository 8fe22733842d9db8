#include "tools/fscil-bench/commands/slurm_command.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>

#include "core/atomic_file.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "core/error.h"
#include "core/shown_text.h"
#include "tools/fscil-bench/cells/command_arguments.h"
#include "tools/fscil-bench/cells/time_estimate.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

// Seconds before the time limit that a task gets SIGTERM, to keep its checkpoint and stop; an
// --sbatch-arg=--signal may move it within [kLeastSignalSeconds, sbatch's 65535].
constexpr int kSignalSeconds = 120;
constexpr int kLeastSignalSeconds = 60;  // the training step in progress and the checkpoint's write

// The #SBATCH options the scripts set themselves, and why: an --sbatch-arg may not set them over
// (a second line would undo the requeue or the logs, or contradict --time, --mem or --partition).
// --signal is apart: it may move the SIGTERM, never replace it (sbatch_signal).
struct OwnedSbatchOption {
  const char* name;
  const char* why;
};
constexpr OwnedSbatchOption kOwnedSbatchOptions[] = {
    {"array", "fscil-bench's to set from the command (the cells, with --max-parallel)"},
    {"cpus-per-task", "fscil-bench's to set from the command (the cells' threads, with --threads)"},
    {"output", "fscil-bench's to set (the logs under --out)"},
    {"error", "fscil-bench's to set (the logs under --out)"},
    {"open-mode", "fscil-bench's to set (the logs under --out)"},
    {"requeue", "fscil-bench's to set (a preempted task is requeued and resumes)"},
    {"no-requeue", "fscil-bench's to set (a preempted task is requeued and resumes)"},
    {"time", "fscil-bench's to set (give fscil-bench slurm --time)"},
    {"mem", "fscil-bench's to set (give fscil-bench slurm --mem)"},
    {"partition", "fscil-bench's to set (give fscil-bench slurm --partition)"},
};

// Every value that reaches an #SBATCH line, checked as what it is, so neither sbatch nor bash can
// read it as something else (a newline would be a command, a space splits sbatch's value).
void check_slurm_values(const SlurmOptions& slurm, const fs::path& logs) {
  const auto refuse_unless = [](const std::string& value, const char* pattern, const char* option, const char* expected) {
    if (!value.empty() && !std::regex_match(value, std::regex(pattern))) {
      throw CliError(fmt::format("{} '{}': expected {}", option, shown_text(value), expected));
    }
  };
  refuse_unless(slurm.partition, R"([A-Za-z0-9_.-]+(,[A-Za-z0-9_.-]+)*)", "--partition",
                "a Slurm partition name (letters, digits, '_', '-', '.'; several comma-separated)");
  refuse_unless(slurm.time, R"((\d+-)?\d+(:\d+){0,2}|UNLIMITED|unlimited|INFINITE|infinite)", "--time",
                "a Slurm time limit: MINUTES, [DAYS-]HOURS:MINUTES:SECONDS, DAYS-HOURS or UNLIMITED");
  refuse_unless(slurm.mem, R"(\d+[KMGTkmgt]?)", "--mem", "a Slurm memory size: a whole number with K, M, G or T, e.g. 8G");
  for (const auto& argument : slurm.sbatch_arguments) {
    if (argument.rfind("--", 0) != 0 || argument.find_first_of(" \t\n\r\v\f") != std::string::npos) {
      throw CliError(fmt::format("--sbatch-arg '{}': expected one sbatch option on one line, without blanks, e.g. "
                                 "--sbatch-arg=--account=abc", shown_text(argument)));
    }
    // sbatch takes any unambiguous prefix of a long option (--arr for --array), so a prefix is refused too.
    const std::string name = argument.substr(2, argument.find('=') - 2);
    if (!name.empty() && std::string("signal").rfind(name, 0) == 0) {
      std::smatch seconds;
      const bool moved = std::regex_match(argument, seconds, std::regex(R"(--signal=B:TERM@(\d{1,5}))")) &&
                         std::stoi(seconds[1]) >= kLeastSignalSeconds && std::stoi(seconds[1]) <= 65535;
      if (!moved) {
        throw CliError(fmt::format("--sbatch-arg {}: the array's tasks stop on SIGTERM to their script, which keeps "
                                   "the run's checkpoint; expected --signal=B:TERM@SECONDS, {} to 65535, to move it "
                                   "(fscil-bench's is B:TERM@{})", shell_command({argument}), kLeastSignalSeconds,
                                   kSignalSeconds));
      }
    }
    for (const auto& owned : kOwnedSbatchOptions) {
      if (!name.empty() && std::string(owned.name).rfind(name, 0) == 0) {
        throw CliError(fmt::format("--sbatch-arg {}: --{} is {}; expected another sbatch option",
                                   shell_command({argument}), owned.name, owned.why));
      }
    }
  }
  // sbatch splits an #SBATCH value at blanks and expands % in --output; a shell quote cannot help there.
  if (logs.string().find_first_of(" \t\n\r\v\f%\"'\\") != std::string::npos) {
    throw CliError(fmt::format("--out '{}': an #SBATCH --output line cannot hold this path (blanks, quotes, '%' or "
                               "backslashes); choose a folder without them", shown_text(logs.parent_path().string(), 1000)));
  }
}

bool is_signal_argument(const std::string& argument) { return argument.rfind("--signal=", 0) == 0; }

// The array's --signal line: SIGTERM to the script kSignalSeconds before the limit, or as long
// before it as an --sbatch-arg=--signal=B:TERM@SECONDS says (check_slurm_values allows no other).
std::string sbatch_signal(const SlurmOptions& slurm) {
  std::string signal = fmt::format("--signal=B:TERM@{}", kSignalSeconds);
  for (const auto& argument : slurm.sbatch_arguments) {
    if (is_signal_argument(argument)) signal = argument;
  }
  return signal;
}

// The #SBATCH lines both scripts share.
std::string common_lines(const SlurmOptions& slurm) {
  std::string lines;
  if (!slurm.partition.empty()) lines += fmt::format("#SBATCH --partition={}\n", slurm.partition);
  if (!slurm.time.empty()) lines += fmt::format("#SBATCH --time={}\n", slurm.time);
  if (!slurm.mem.empty()) lines += fmt::format("#SBATCH --mem={}\n", slurm.mem);
  for (const auto& argument : slurm.sbatch_arguments) {
    if (!is_signal_argument(argument)) lines += fmt::format("#SBATCH {}\n", argument);
  }
  return lines;
}

std::string array_script(const std::string& command, const std::string& range, int cpus, const fs::path& logs,
                         const fs::path& workdir, const SlurmOptions& slurm, const std::string& time_note) {
  return fmt::format(
      "#!/bin/bash\n"
      "# One task per cell of the command (fscil-bench plan lists them). Written by fscil-bench slurm.\n"
      "#SBATCH --job-name=fscil-bench\n"
      "#SBATCH --array={range}\n"
      "#SBATCH --cpus-per-task={cpus}\n"
      "#SBATCH --output={logs}/cell-%a.log\n"
      "#SBATCH --open-mode=append\n"
      "#SBATCH {signal}\n"
      "#SBATCH --requeue\n"
      "{time_note}"
      "{common}"
      "cd {workdir} || exit 1\n"
      "# SIGTERM (a time limit near, or a preemption) goes to fscil-bench, which keeps the checkpoint of\n"
      "# its last finished session; a requeued task, or fscil-bench slurm --missing-only, continues it.\n"
      "trap 'stop=1; [ -n \"${{child:-}}\" ] && kill -TERM \"$child\" 2>/dev/null' TERM\n"
      "{command} --cell \"$SLURM_ARRAY_TASK_ID\" --threads \"${{SLURM_CPUS_PER_TASK:-{cpus}}}\" &\n"
      "child=$!\n"
      "[ -n \"${{stop:-}}\" ] && kill -TERM \"$child\" 2>/dev/null\n"
      "while kill -0 \"$child\" 2>/dev/null; do wait \"$child\"; done  # a trap ends a wait early\n"
      "wait \"$child\"  # its exit status, which bash keeps\n",
      fmt::arg("range", range), fmt::arg("cpus", cpus), fmt::arg("logs", logs.string()),
      fmt::arg("time_note", time_note), fmt::arg("signal", sbatch_signal(slurm)), fmt::arg("common", common_lines(slurm)),
      fmt::arg("workdir", shell_command({workdir.string()})), fmt::arg("command", command));
}

// Without --time: 1.5 times the longest chosen cell's estimate on this machine (each task training
// its own shared stages), at least 10 minutes, rounded up to whole minutes.
std::string suggested_time(const RunOptions& options, const std::vector<std::string>& grid, std::vector<BenchCell> cells,
                           const std::vector<int>& chosen, int cpus) {
  RunOptions on_a_task = options;
  on_a_task.threads = cpus;
  for (const Calibration& calibration : estimate_cells(on_a_task, grid, cells, /*one_after_another=*/false)) {
    if (!calibration.idle) fmt::print(stderr, "fscil-bench slurm: time limit from {}\n", calibration.basis);
  }
  double longest = 0;
  for (int index : chosen) longest = std::max(longest, cells[static_cast<std::size_t>(index)].estimated_seconds);
  return clock_time(std::max(600.0, std::ceil(1.5 * longest / 60) * 60));
}

std::string merge_script(const std::string& command, const std::string& check, const fs::path& logs,
                         const fs::path& workdir, const SlurmOptions& slurm) {
  return fmt::format(
      "#!/bin/bash\n"
      "# The tables over every cell's result files, after the array: submitted with\n"
      "# sbatch --dependency=afterany:ARRAY_JOB_ID (fscil-bench slurm --submit does it).\n"
      "#SBATCH --job-name=fscil-bench-merge\n"
      "#SBATCH --cpus-per-task=1\n"
      "#SBATCH --output={logs}/merge.log\n"
      "{common}"
      "cd {workdir} || exit 1\n"
      "{command}\n"
      "# Fails, listing them, while any cell has no result file yet.\n"
      "{check}\n",
      fmt::arg("logs", logs.string()), fmt::arg("common", common_lines(slurm)),
      fmt::arg("workdir", shell_command({workdir.string()})), fmt::arg("command", command), fmt::arg("check", check));
}

// Runs `sbatch --parsable ...` and returns the job id it prints (its warnings go to stderr).
std::string submit(const std::vector<std::string>& words) {
  const std::string command = shell_command(words);
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) throw Error(fmt::format("{}: cannot run", command));
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = ::pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  const std::string last_line = output.substr(output.rfind('\n') == std::string::npos ? 0 : output.rfind('\n') + 1);
  const std::string id = last_line.substr(0, last_line.find(';'));  // "id;cluster" on a federation
  if (status != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw Error(fmt::format("{} failed ({}){}", command,
                            WIFEXITED(status) ? fmt::format("exit {}", WEXITSTATUS(status)) : "no exit status",
                            last_line.empty() ? "" : ": " + last_line));
  }
  return id;
}

}  // namespace

std::string array_range(const std::vector<int>& cells, int max_parallel) {
  std::string range;
  for (std::size_t i = 0; i < cells.size();) {
    std::size_t j = i;
    while (j + 1 < cells.size() && cells[j + 1] == cells[j] + 1) ++j;
    if (!range.empty()) range += ',';
    range += j == i ? std::to_string(cells[i]) : fmt::format("{}-{}", cells[i], cells[j]);
    i = j + 1;
  }
  return max_parallel > 0 ? fmt::format("{}%{}", range, max_parallel) : range;
}

std::string run_slurm(const RunOptions& options, const std::vector<std::string>& grid, const SlurmOptions& slurm,
                      const std::string& executable) {
  if (slurm.max_parallel < 0) throw CliError(fmt::format("--max-parallel {}: expected 0 (no limit) or more", slurm.max_parallel));
  const fs::path logs = fs::absolute(options.out) / "cell-logs";
  check_slurm_values(slurm, logs);
  const auto cells = plan_cells(options, grid);
  check_every_cell(options, grid);  // a script whose every task fails on a bad value is no script
  std::vector<int> chosen;
  for (const auto& cell : cells) {
    if (!slurm.missing_only || !cell_has_results(options, cell)) chosen.push_back(cell.index);
  }
  const int cpus = slurm.cpus_per_task > 0 ? slurm.cpus_per_task : options.threads > 0 ? options.threads : 1;
  SlurmOptions limits = slurm;
  std::string time_note;
  if (limits.time.empty() && !chosen.empty()) {
    limits.time = suggested_time(options, grid, cells, chosen, cpus);
    time_note = "# --time was not given: the limit below is fscil-bench's suggestion, 1.5 x the longest cell's\n"
                "# estimate on the machine that wrote this script (fscil-bench plan), at least 10 minutes. Give\n"
                "# --time when the nodes are slower, or when it passes the partition's MaxTime.\n";
  }
  const fs::path workdir = fs::current_path();
  const fs::path folder = fs::absolute(options.out) / "slurm";
  fs::create_directories(folder);
  fs::create_directories(logs);

  std::vector<std::string> task = {executable};
  for (const auto& word : command_arguments(options, grid)) task.push_back(word);
  std::vector<std::string> merge = {executable, "report", "--results", options.out, "--methods", options.methods};
  for (const auto& axis : grid) merge.insert(merge.end(), {"--grid", axis});
  const fs::path array_file = folder / "array.sbatch";
  const fs::path merge_file = folder / "merge.sbatch";
  if (chosen.empty()) {
    return fmt::format("All {} cells have their result files: nothing to submit. Tables: {}\n", cells.size(),
                       shell_command(merge));
  }
  write_file_atomically(array_file, array_script(shell_command(task), array_range(chosen, slurm.max_parallel), cpus,
                                                 logs, workdir, limits, time_note));
  std::vector<std::string> check = {executable, "plan"};
  for (const auto& word : command_arguments(options, grid)) check.push_back(word);
  if (!grid.empty()) check.erase(check.begin() + 2);  // "plan sweep --grid ...": plan takes --grid itself
  check.emplace_back("--missing-only");
  write_file_atomically(merge_file, merge_script(shell_command(merge), shell_command(check), logs, workdir, slurm));
  std::string text = fmt::format("{} of {} cells in {} ({} cpus per task{}); tables after them: {}\n", chosen.size(),
                                 cells.size(), array_file.string(), cpus,
                                 time_note.empty() ? "" : fmt::format(", --time {} suggested from the plan", limits.time),
                                 merge_file.string());
  if (!slurm.submit) {
    return text + fmt::format("Submit with: jid=$(sbatch --parsable {}) && sbatch --dependency=afterany:$jid {}\n",
                              shell_command({array_file.string()}), shell_command({merge_file.string()}));
  }
  const std::string array_job = submit({"sbatch", "--parsable", array_file.string()});
  std::string merge_job;
  try {
    merge_job = submit({"sbatch", "--parsable", "--dependency=afterany:" + array_job, merge_file.string()});
  } catch (const Error& error) {
    throw Error(fmt::format("array job {} submitted, its merge job not: {}", array_job, error.what()));
  }
  return text + fmt::format("Submitted array job {} and merge job {}\n", array_job, merge_job);
}

}  // namespace fscil
