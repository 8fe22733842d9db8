#include "tools/fscil-bench/options/config_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "tests/temporary_directory.h"
#include "core/error.h"

namespace fscil {
namespace {

using Words = std::vector<std::string>;

OptionKind run_option(const std::string& name) {
  static const std::set<std::string> flags = {"--save-model", "--quiet"};
  static const std::set<std::string> options = {"--methods", "--dataset", "--seeds", "--threads",
                                                "--set",     "--profile", "--config"};
  return flags.count(name) > 0 ? OptionKind::flag : options.count(name) > 0 ? OptionKind::takes_value : OptionKind::unknown;
}

std::filesystem::path write(const TemporaryDirectory& directory, const std::string& text) {
  const auto path = directory.path() / "run.json";
  std::ofstream(path) << text;
  return path;
}

TEST(ConfigFile, OptionsGoFirstTheGridAfterItsSubcommandAndTheCommandLineWins) {
  TemporaryDirectory directory;
  const auto file = write(directory, R"({"methods": "prototype", "seeds": "1-2", "threads": 2, "save-model": true,
    "quiet": false, "set": {"shot": 3, "pic_weight": 0.1}, "grid": {"pspc_probes": [5, 50], "shot": [1]}})");
  const Words command_line = {"fscil-bench", "sweep", "--seeds", "3", "--set", "shot=5", "--config", file.string()};
  // The command line's --set shot=5 replaces the file's shot (a key is given once).
  const Words expected = {"fscil-bench", "--methods", "prototype", "--threads", "2", "--save-model",
                          "--set", "pic_weight=0.1", "sweep", "--grid", "pspc_probes=5,50", "--grid", "shot=1",
                          "--seeds", "3", "--set", "shot=5", "--config", file.string()};
  EXPECT_EQ(ConfigFile(file).merged_into(command_line, run_option), expected);
  EXPECT_EQ(config_file_of(command_line), file.string());
  // An axis the command line sweeps replaces the file's axis and its fixed value.
  const Words sweeps_shot = {"fscil-bench", "sweep", "--grid", "shot=2,4"};
  const Words without_shot = {"fscil-bench", "--methods", "prototype", "--seeds", "1-2", "--threads", "2", "--save-model",
                              "--set", "pic_weight=0.1", "sweep", "--grid", "pspc_probes=5,50", "--grid", "shot=2,4"};
  EXPECT_EQ(ConfigFile(file).merged_into(sweeps_shot, run_option), without_shot);
  // CLI11 reads `--set a=1 shot=5` as one --set of two values: shot is the command line's there too.
  const Words two_values = {"fscil-bench", "--set", "pic_weight=0.2", "shot=5"};
  const Words only_the_command_lines = {"fscil-bench", "--methods", "prototype", "--seeds", "1-2", "--threads", "2",
                                        "--save-model", "--set", "pic_weight=0.2", "shot=5"};
  const auto set_only = write(directory, R"({"methods": "prototype", "seeds": "1-2", "threads": 2, "save-model": true,
    "set": {"shot": 3, "pic_weight": 0.1}})");
  EXPECT_EQ(ConfigFile(set_only).merged_into(two_values, run_option), only_the_command_lines);
  const auto flags = write(directory, R"({"set": {"use_cutmix": true, "temperature": 16}})");
  EXPECT_EQ(ConfigFile(flags).settings(), (std::vector<std::pair<std::string, std::string>>{{"use_cutmix", "true"},
                                                                                      {"temperature", "16"}}));
  EXPECT_EQ(config_file_of({"fscil-bench", "--config=a.json"}), "a.json");
  EXPECT_EQ(config_file_of({"fscil-bench", "list"}), "");
}

TEST(ConfigFile, WithoutTheOptionsOfTheFileLeavesTheFilesValuesToBeChecked) {
  TemporaryDirectory directory;
  const auto file = write(directory, R"({"threads": "many", "quiet": true, "set": {"shot": 3}})");
  const Words command_line = {"fscil-bench", "plan", "--threads", "2", "--quiet", "--threads=3", "--seeds", "1",
                              "--set", "shot=5", "--config", file.string()};
  const Words unoverridden = {"fscil-bench", "plan", "--seeds", "1", "--set", "shot=5", "--config", file.string()};
  const ConfigFile config(file);
  std::filesystem::remove(file);  // read once, when constructed: the parse is not repeated per use
  EXPECT_EQ(config.without_its_options(command_line, run_option), unoverridden);
  const Words file_values = {"fscil-bench", "--threads", "many", "--quiet", "plan", "--seeds", "1", "--set", "shot=5",
                             "--config", file.string()};
  EXPECT_EQ(config.merged_into(unoverridden, run_option), file_values);
  EXPECT_EQ(config.without_its_options({"fscil-bench", "--threads"}, run_option), Words{"fscil-bench"});  // a value cut off
  // A value the command line overrides is read by the file's rules all the same.
  const auto flag_with_value = write(directory, R"({"quiet": "yes"})");
  const ConfigFile quiet_yes(flag_with_value);
  EXPECT_THROW(quiet_yes.merged_into(quiet_yes.without_its_options({"fscil-bench", "--quiet"}, run_option), run_option),
               CliError);
}

TEST(ConfigFile, BadFilesAreOneErrorNamingTheFileAndTheKey) {
  TemporaryDirectory directory;
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"{\"methods\": ", "not JSON"},
      {"[1, 2]", "expected a JSON object of run options"},
      {"{\"method\": \"prototype\"}", "\"method\": not a run option"},
      {"{\"config\": \"other.json\"}", "\"config\": not a run option"},
      {"{\"methods\": [\"prototype\"]}", "\"methods\": expected a string, a number or true/false"},
      {"{\"set\": [\"shot=3\"]}", "\"set\": expected an object of keys and values"},
      {"{\"grid\": {\"shot\": 3}}", "\"grid\".shot: expected a list of values"},
      {"{\"grid\": {\"shot\": [1, 5]}}", "\"grid\" needs the sweep, plan, run-cells or slurm subcommand"},
      // A flag's "yes" was once read as a stray word of the command line, a value option's true as a flag.
      {"{\"save-model\": \"yes\"}", "\"save-model\": expected true or false, found \"yes\""},
      {"{\"threads\": true}", "\"threads\": expected a value, found true"},
      {"{\"methods\": \"a\", \"methods\": \"b\"}", "key 'methods' given twice"},
      // A NUL in a key is spelled out: it once cut the error line where it stood.
      {"{\"me\\u0000thods\": 1}", "\"me\\x00thods\": not a run option"},
  };
  for (const auto& [text, message] : bad) {
    const auto file = write(directory, text);
    try {
      ConfigFile(file).merged_into({"fscil-bench"}, run_option);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const CliError& error) {
      EXPECT_NE(std::string(error.what()).find("--config " + file.string() + ": "), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
    }
  }
  // Read by the one file reader: a bad input naming the file (exit 1), not a malformed option.
  EXPECT_THROW(ConfigFile(directory.path() / "missing.json"), FileError);
}

}  // namespace
}  // namespace fscil
