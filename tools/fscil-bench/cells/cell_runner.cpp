#include "tools/fscil-bench/cells/cell_runner.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

#include "metrics/resource_usage.h"
#include "core/stop_request.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "core/error.h"
#include "tools/fscil-bench/cells/command_arguments.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/cells/time_estimate.h"
#include "core/parallel_for.h"

extern char** environ;

namespace fscil {

namespace fs = std::filesystem;

namespace {

pid_t spawn_cell(const std::string& executable, const std::vector<std::string>& arguments, const fs::path& log) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(executable.c_str()));
  for (const auto& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw Error(fmt::format("{}: cannot start a cell ({})", executable, std::strerror(error)));
  return pid;
}

// The last line a cell wrote: its error line when it failed.
std::string last_line_of(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

std::string exit_text(int status) {
  if (WIFEXITED(status)) return fmt::format("exit {}", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return fmt::format("killed by signal {}", WTERMSIG(status));
  return "ended";
}

// Longest first (LPT): with J cells at a time, the last cells to start are the short ones, so the
// lanes end together. Which cell is long is this machine's estimate (cells/time_estimate.h) of each
// cell alone at the cell's thread count; where there is none (a real dataset not on this machine,
// a calibration that failed) the plan's order stays, as the order is an economy.
std::string order_longest_first(RunOptions options, const std::vector<std::string>& grid, int threads,
                                std::vector<BenchCell>& cells) {
  options.threads = threads;
  try {
    estimate_cells(options, grid, cells, /*one_after_another=*/false);
  } catch (const Error& error) {
    return fmt::format("in the plan's order (no time estimate: {})", error.what());
  }
  std::stable_sort(cells.begin(), cells.end(), [](const BenchCell& a, const BenchCell& b) {
    return a.estimated_seconds > b.estimated_seconds;
  });
  return "longest first by this machine's estimate";
}

}  // namespace

int threads_per_cell(int threads, int jobs) {
  return std::max(1, thread_count(threads) / std::max(1, jobs));
}

std::string run_cells(const RunOptions& options, const std::vector<std::string>& grid, int jobs,
                      const std::string& executable) {
  if (jobs < 1) throw CliError(fmt::format("--jobs {}: expected at least 1", jobs));
  auto cells = plan_cells(options, grid);
  check_every_cell(options, grid);  // once, before any cell starts, not once per cell spawned
  jobs = std::min<int>(jobs, static_cast<int>(cells.size()));  // the threads go to cells that run
  const int threads = threads_per_cell(options.threads, jobs);
  const OutFolderLock folder = OutFolderLock::shared(options.out);  // no whole command on it meanwhile
  const std::string order = jobs > 1 ? order_longest_first(options, grid, threads, cells) : "in the plan's order";
  const fs::path logs = fs::path(options.out) / "cell-logs";
  fs::create_directories(logs);
  const auto say = [&](const std::string& line) {
    if (!options.quiet) std::cerr << line << '\n';
  };
  say(fmt::format("{} cells, {} at a time, {} thread(s) each, {}; logs in {}", cells.size(), jobs, threads, order,
                  logs.string()));

  struct Running {
    int cell;
    Stopwatch clock;
  };
  std::map<pid_t, Running> running;
  std::vector<std::string> failed;
  std::size_t next = 0;
  bool stop_forwarded = false;
  while (next < cells.size() || !running.empty()) {
    while (stop_signal() == 0 && next < cells.size() && static_cast<int>(running.size()) < jobs) {
      const BenchCell& cell = cells[next++];
      auto arguments = command_arguments(options, grid);
      arguments.insert(arguments.end(), {"--cell", std::to_string(cell.index), "--threads", std::to_string(threads)});
      const fs::path log = logs / fmt::format("cell-{}.log", cell.index);
      running[spawn_cell(executable, arguments, log)] = {cell.index, Stopwatch()};
      say(fmt::format("cell {} of {} started: {} seed {} (log {})", cell.index, cells.size(),
                      fmt::join(cell.methods, ","), cell.seed, log.string()));
    }
    if (running.empty()) break;
    if (stop_signal() != 0 && !stop_forwarded) {
      for (const auto& [pid, cell] : running) ::kill(pid, SIGTERM);
      stop_forwarded = true;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid == 0 || (pid < 0 && errno == EINTR)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    if (pid < 0) throw Error(fmt::format("run-cells: waiting for the cells failed ({})", std::strerror(errno)));
    const auto found = running.find(pid);
    if (found == running.end()) continue;
    const int cell = found->second.cell;
    const fs::path log = logs / fmt::format("cell-{}.log", cell);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      say(fmt::format("cell {} done in {:.1f} s", cell, found->second.clock.seconds()));
    } else if (stop_signal() == 0) {
      failed.push_back(fmt::format("cell {} ({}: {}, see {})", cell, exit_text(status), last_line_of(log), log.string()));
      say(fmt::format("cell {} failed: {}", cell, failed.back()));
    }
    running.erase(found);
  }
  stop_if_requested();
  if (!failed.empty()) {
    throw Error(fmt::format("run-cells: {} of {} cells failed: {}", failed.size(), cells.size(),
                               fmt::join(failed, "; ")));
  }
  return write_command_tables(options, grid) +
         fmt::format("{} cells run {} at a time; tables over all of them in {}/\n", cells.size(), jobs, options.out);
}

}  // namespace fscil
