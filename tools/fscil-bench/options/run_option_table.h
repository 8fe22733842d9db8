#pragma once
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/parameter_set.h"
#include "core/valid_range.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace CLI {
class App;
}

namespace fscil {

// A run option, declared once: this row gives it to CLI11 (and so to --config files, whose keys
// are checked against CLI11), writes it back out for cells and Slurm tasks, and tells rerun
// whether a result file fixes it.
struct RunOption {
  using Member = std::variant<std::string RunOptions::*, int RunOptions::*, bool RunOptions::*,
                              std::vector<std::string> RunOptions::*>;
  const char* name;  // "--methods"
  const char* help;
  Member member;
  // How a cell's or Slurm task's command line carries it: always (even empty, so a cell refuses
  // what the command would), when given (a flag set, a text not empty, each list value), or never
  // (--threads, which a cell sets itself, and --cell).
  enum class Written { always, when_given, never };
  Written written = Written::when_given;
  // Part of what a result file records: rerun takes it from there and refuses it on its own
  // command line.
  bool from_result_file = false;
  std::optional<ValidRange> range = std::nullopt;  // a number's accepted values
  bool shows_default = false;       // --help shows the default
  const char* if_empty = nullptr;   // the refusal of an empty value, where one means nothing
  // The floor's own reader of a named choice (split mode, dataset, ...), run as the option is
  // parsed, so that its refusal names the option the user typed.
  void (*read_choice)(const std::string&) = nullptr;
};

// Every run option, in --help order (also the order a cell's command line is written in).
const std::vector<RunOption>& run_option_table();

// Declares every run option on `app`, bound to `options`; `more_readers` reads named choices whose
// readers the table cannot name (--methods and --profile need the method registry).
using ChoiceReader = void (*)(const std::string&);
void declare_run_options(CLI::App& app, RunOptions& options,
                         const std::map<std::string, ChoiceReader>& more_readers = {});

// `options` as the words of a command line (fscil-bench ...), every written option explicit.
std::vector<std::string> run_option_words(const RunOptions& options);

// Sets every --set key=value of `options` on `params`, each named by its origin, and the values
// they replaced to be checked too (RunOptions::assignment_origins, replaced_assignments); a key
// given twice is refused (the last would win silently).
void apply_assignments(const RunOptions& options, ParameterSet& params);

}  // namespace fscil
