#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fscil {

// --config FILE: a JSON object whose keys name run options without their dashes
// ("methods": "all", "seeds": "1-5", "threads": 2, "save-model": true), plus "set" (an object of
// --set keys and values) and "grid" (an object of sweep keys and value lists). Returns the
// command line with the file's options inserted: run options after the program name, --grid after
// the subcommand that takes it. An option the command line gives itself is left out (the flag
// overrides the file); the file's --set assignments come first, so the command line's assignment
// of the same key replaces the file's, and a key the command line sweeps with --grid is taken from there alone.
// `option_kind` says what "--name" is. CliError naming the file on anything else: unreadable JSON,
// an unknown key, a value of the wrong type (a flag takes true or false, an option with a value
// not), a grid without a sweep, plan, run-cells or slurm subcommand.
enum class OptionKind { unknown, flag, takes_value };
std::vector<std::string> with_config_file(const std::vector<std::string>& command_line,
                                          const std::filesystem::path& file,
                                          const std::function<OptionKind(const std::string&)>& option_kind);

// The command line without the words of the run options the file also gives (`--threads 2`,
// `--threads=2`, a flag): merged with the file by with_config_file and parsed, it checks the
// file's values that the command line overrides. A run never reads them, but nonsense in a file
// is the file's error whichever value wins.
std::vector<std::string> without_options_of_file(const std::vector<std::string>& command_line,
                                                 const std::filesystem::path& file,
                                                 const std::function<OptionKind(const std::string&)>& option_kind);

// The "set" block of a config file as key -> value text (numbers as written, booleans as
// true/false): what the released dataset configs give as their datasets' defaults.
std::vector<std::pair<std::string, std::string>> config_settings(const std::filesystem::path& file);

// Whether the command line gives `option` itself (`--threads 2` or `--threads=2`): its value
// wins over the file's.
bool command_line_gives(const std::vector<std::string>& command_line, const std::string& option);

// The top-level keys of a config file, in its order.
std::vector<std::string> config_keys(const std::filesystem::path& file);

// The FILE of `--config FILE` or `--config=FILE` in the command line, or "".
std::string config_file_of(const std::vector<std::string>& command_line);

}  // namespace fscil
