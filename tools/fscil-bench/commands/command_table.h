#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tools/fscil-bench/commands/run_command.h"

namespace CLI {
class App;
}

namespace fscil {

// What a command is run with: the run options the command line gave (the main job's, which the
// subcommands that run methods take too), and the command line itself, to ask what it named.
struct Invocation {
  RunOptions& run;
  const CLI::App& app;
  std::string resume_dir;  // --resume DIR, "" without
  bool given(const char* option) const;
  // CliError unless --methods and --dataset were given (the commands that train named methods).
  void require_methods_and_dataset() const;
  // This binary, by the path the kernel knows it by: what cells and Slurm scripts run.
  std::string executable() const;
};

// One subcommand: its own options, bound to members as it declares them, and its run. The main job
// (no subcommand) is run_benchmark (run_command.h).
class Subcommand {
 public:
  virtual ~Subcommand() = default;
  // Declares its options on `command`, the CLI11 subcommand that carries its name and summary.
  virtual void declare(CLI::App& command) = 0;
  // Runs it; prints what it prints and returns the exit status.
  virtual int run(Invocation& invocation) = 0;
  // Whether it trains (and so stops at the next epoch on SIGTERM or SIGINT).
  virtual bool trains() const { return false; }
  // Whether --cell K may narrow it (a sweep does; the main job too).
  virtual bool takes_cell() const { return false; }
};

struct SubcommandEntry {
  const char* name;
  const char* summary;
  std::function<std::unique_ptr<Subcommand>()> create;
};

// Every subcommand, in --help order.
const std::vector<SubcommandEntry>& subcommand_table();

}  // namespace fscil
