#include "tools/fscil-bench/options/config_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/json_keys.h"
#include "core/shown_text.h"
#include "core/text_file.h"

namespace fscil {

namespace {

using json = nlohmann::ordered_json;  // the file's order: the first grid axis varies slowest

// A scalar of the file as the command line would write it.
std::string text_of(const json& value, const std::string& where) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  // Past 2^63 the reader keeps the number unsigned: read as signed it came back negative.
  if (value.is_number_unsigned()) return std::to_string(value.get<std::uint64_t>());
  if (value.is_number_integer()) return std::to_string(value.get<std::int64_t>());
  if (value.is_number()) return value.dump();
  throw CliError(fmt::format("{}: expected a string, a number or true/false", where));
}

// Whether the command line gives `key` a value with `option` (`--set KEY=...`, `--grid=KEY=...`,
// or a later word of `--set a=1 KEY=2`, which CLI11 reads as one --set): a --set value or a --grid
// axis of the command line replaces the file's.
bool keyed_on_command_line(const std::vector<std::string>& command_line, const std::string& option,
                           const std::string& key) {
  const auto names_key = [&](const std::string& value) { return value.substr(0, value.find('=')) == key; };
  for (std::size_t i = 1; i < command_line.size(); ++i) {
    const std::string& word = command_line[i];
    if (word.rfind(option + "=", 0) == 0 && names_key(word.substr(option.size() + 1))) return true;
    if (word != option) continue;
    for (std::size_t j = i + 1; j < command_line.size() && command_line[j].rfind('-', 0) != 0; ++j) {
      if (names_key(command_line[j])) return true;
    }
  }
  return false;
}

// Whether `word` of a command line gives `option`: `--threads` (its value the next word) or `--threads=2`.
bool gives_option(const std::string& word, const std::string& option) {
  return word == option || word.rfind(option + "=", 0) == 0;
}

bool swept_on_command_line(const std::vector<std::string>& command_line, const std::string& key) {
  return keyed_on_command_line(command_line, "--grid", key);
}

std::string set_block_of(const std::filesystem::path& file) { return fmt::format("--config {}: \"set\"", file.string()); }

// --help, --version and another --config are the program's flags, not options of a run: a file
// that gives them would print help and exit 0, and run nothing.
bool is_run_option_key(const std::string& key) {
  return key != "config" && key != "help" && key != "help-all" && key != "version";
}

json parse_config(const std::filesystem::path& file) {
  const std::string text = read_text_file(file);
  json config;
  refuse_deep_json<CliError>(text, "--config " + file.string(), "run options");
  try {
    config = json::parse(text);
  } catch (const json::exception& error) {
    throw CliError(fmt::format("--config {}: not JSON ({})", file.string(), json_error_text(error)));
  }
  if (!config.is_object()) throw CliError(fmt::format("--config {}: expected a JSON object of run options", file.string()));
  if (const auto key = duplicated_json_key(text)) {
    throw CliError(fmt::format("--config {}: key '{}' given twice in one object; give it once", file.string(),
                               shown_text(*key)));
  }
  refuse_number_read_as_zero<CliError>(text, "--config " + file.string());
  return config;
}

std::vector<std::pair<std::string, std::string>> settings_of(const json& value, const std::string& where) {
  if (!value.is_object()) throw CliError(where + ": expected an object of keys and values");
  std::vector<std::pair<std::string, std::string>> settings;
  for (const auto& [name, setting] : value.items()) {
    settings.emplace_back(name, text_of(setting, where + "." + shown_text(name)));
  }
  return settings;
}

}  // namespace

bool command_line_gives(const std::vector<std::string>& command_line, const std::string& option) {
  return std::any_of(command_line.begin(), command_line.end(),
                     [&](const std::string& word) { return gives_option(word, option); });
}

ConfigFile::ConfigFile(std::filesystem::path file)
    : file_(std::move(file)), json_(std::make_shared<const json>(parse_config(file_))) {}

std::vector<std::string> ConfigFile::keys() const {
  std::vector<std::string> keys;
  for (const auto& [key, value] : json_->items()) keys.push_back(key);
  return keys;
}

std::vector<std::string> ConfigFile::without_its_options(const std::vector<std::string>& command_line,
                                                         const OptionKindOf& option_kind) const {
  std::vector<std::string> kept = command_line;
  for (const auto& [key, value] : json_->items()) {
    if (key == "set" || key == "grid" || !is_run_option_key(key)) continue;
    const std::string option = "--" + key;
    const std::size_t words = option_kind(option) == OptionKind::takes_value ? 2 : 1;
    for (std::size_t i = 1; i < kept.size();) {
      if (!gives_option(kept[i], option)) {
        ++i;
        continue;
      }
      const std::size_t given = kept[i] == option ? words : 1;  // `--threads 2` or `--threads=2`
      kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(i),
                 kept.begin() + static_cast<std::ptrdiff_t>(std::min(i + given, kept.size())));
    }
  }
  return kept;
}

std::vector<std::pair<std::string, std::string>> ConfigFile::settings() const {
  if (!json_->contains("set")) return {};
  return settings_of(json_->at("set"), set_block_of(file_));
}

std::string ConfigFile::settings_origin() const { return set_block_of(file_); }

std::map<std::string, std::string> ConfigFile::grid_origins(const std::vector<std::string>& command_line) const {
  std::map<std::string, std::string> origins;
  if (!json_->contains("grid") || !json_->at("grid").is_object()) return origins;  // merged_into refuses it
  for (const auto& [name, values] : json_->at("grid").items()) {
    if (!swept_on_command_line(command_line, name)) {
      origins[name] = fmt::format("--config {}: \"grid\"", file_.string());
    }
  }
  return origins;
}

bool ConfigFile::replaced_on_command_line(const std::vector<std::string>& command_line, const std::string& key) {
  return swept_on_command_line(command_line, key) || keyed_on_command_line(command_line, "--set", key);
}

std::string config_file_of(const std::vector<std::string>& command_line) {
  for (std::size_t i = 1; i < command_line.size(); ++i) {
    if (command_line[i] == "--config" && i + 1 < command_line.size()) return command_line[i + 1];
    if (command_line[i].rfind("--config=", 0) == 0) return command_line[i].substr(9);
  }
  return {};
}

std::vector<std::string> ConfigFile::merged_into(const std::vector<std::string>& command_line,
                                                 const OptionKindOf& option_kind) const {
  std::vector<std::string> options;  // after the program name
  std::vector<std::string> grid;     // after the subcommand
  for (const auto& [key, value] : json_->items()) {
    const std::string where = fmt::format("--config {}: \"{}\"", file_.string(), shown_text(key));
    if (key == "set") {
      for (const auto& [name, setting] : settings_of(value, where)) {
        if (!replaced_on_command_line(command_line, name)) {
          options.insert(options.end(), {"--set", name + "=" + setting});
        }
      }
    } else if (key == "grid") {
      if (!value.is_object()) throw CliError(where + ": expected an object of keys and value lists");
      for (const auto& [name, values] : value.items()) {
        if (!values.is_array() || values.empty()) {
          throw CliError(fmt::format("{}.{}: expected a list of values", where, shown_text(name)));
        }
        if (swept_on_command_line(command_line, name)) continue;  // the command line's axis wins
        std::string axis = name + "=";
        for (std::size_t i = 0; i < values.size(); ++i) {
          axis += (i == 0 ? "" : ",") + text_of(values[i], where + "." + shown_text(name));
        }
        grid.insert(grid.end(), {"--grid", axis});
      }
    } else if (!is_run_option_key(key) || option_kind("--" + key) == OptionKind::unknown) {
      throw CliError(fmt::format("{}: not a run option (expected e.g. methods, dataset, seeds, set, grid)", where));
    } else if (command_line_gives(command_line, "--" + key)) {
      continue;  // the command line's own value wins
    } else if (option_kind("--" + key) == OptionKind::flag) {
      if (!value.is_boolean()) {
        throw CliError(fmt::format("{}: expected true or false, found {}", where, shown_text(value.dump())));
      }
      if (value.get<bool>()) options.push_back("--" + key);
    } else if (value.is_boolean()) {
      throw CliError(fmt::format("{}: expected a value, found {}", where, value.dump()));
    } else {
      options.insert(options.end(), {"--" + key, text_of(value, where)});
    }
  }

  std::vector<std::string> merged = {command_line.front()};
  merged.insert(merged.end(), options.begin(), options.end());
  bool grid_placed = grid.empty();
  for (std::size_t i = 1; i < command_line.size(); ++i) {
    merged.push_back(command_line[i]);
    const std::string& word = command_line[i];
    if (!grid_placed && (word == "sweep" || word == "plan" || word == "run-cells" || word == "slurm")) {
      merged.insert(merged.end(), grid.begin(), grid.end());
      grid_placed = true;
    }
  }
  if (!grid_placed) {
    throw CliError(fmt::format("--config {}: \"grid\" needs the sweep, plan, run-cells or slurm subcommand", file_.string()));
  }
  return merged;
}

}  // namespace fscil
