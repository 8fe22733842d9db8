#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

namespace fscil {

// --config FILE: a JSON object whose keys name run options without their dashes
// ("methods": "all", "seeds": "1-5", "threads": 2, "save-model": true), plus "set" (an object of
// --set keys and values) and "grid" (an object of sweep keys and value lists). The file is read
// and checked as JSON once, when constructed; CliError naming the file on unreadable JSON or a key
// given twice, FileError when it cannot be read.
enum class OptionKind { unknown, flag, takes_value };
using OptionKindOf = std::function<OptionKind(const std::string&)>;  // what "--name" is

class ConfigFile {
 public:
  explicit ConfigFile(std::filesystem::path file);

  const std::filesystem::path& file() const { return file_; }

  // The top-level keys, in the file's order.
  std::vector<std::string> keys() const;

  // The "set" block as key -> value text (numbers as written, booleans as true/false): what the
  // released dataset configs give as their datasets' defaults.
  std::vector<std::pair<std::string, std::string>> settings() const;
  // How an error line names the "set" block: `--config FILE: "set"`.
  std::string settings_origin() const;
  // Whether the command line gives the "set" key `key` itself (--set KEY=..., or sweeps it with
  // --grid): the file's value then reaches no run.
  static bool replaced_on_command_line(const std::vector<std::string>& command_line, const std::string& key);
  // The "grid" keys whose values reach the cells (those the command line does not sweep itself),
  // each with how an error line names it: `--config FILE: "grid"`.
  std::map<std::string, std::string> grid_origins(const std::vector<std::string>& command_line) const;

  // The command line with the file's options inserted: run options after the program name, --grid
  // after the subcommand that takes it. An option the command line gives itself is left out (the
  // flag overrides the file); the file's --set assignments come first, so the command line's
  // assignment of the same key replaces the file's, and a key the command line sweeps with --grid
  // is taken from there alone. CliError naming the file on anything else: an unknown key, a value
  // of the wrong type (a flag takes true or false, an option with a value not), a grid without a
  // sweep, plan, run-cells or slurm subcommand.
  std::vector<std::string> merged_into(const std::vector<std::string>& command_line,
                                       const OptionKindOf& option_kind) const;

  // The command line without the words of the run options the file also gives (`--threads 2`,
  // `--threads=2`, a flag): merged with the file and parsed, it checks the file's values that the
  // command line overrides. A run never reads them, but nonsense in a file is the file's error
  // whichever value wins.
  std::vector<std::string> without_its_options(const std::vector<std::string>& command_line,
                                               const OptionKindOf& option_kind) const;

 private:
  std::filesystem::path file_;
  std::shared_ptr<const nlohmann::ordered_json> json_;
};

// Whether the command line gives `option` itself (`--threads 2` or `--threads=2`): its value
// wins over the file's.
bool command_line_gives(const std::vector<std::string>& command_line, const std::string& option);

// The FILE of `--config FILE` or `--config=FILE` in the command line, or "".
std::string config_file_of(const std::vector<std::string>& command_line);

}  // namespace fscil
