#include "tools/fscil-bench/command_line.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <regex>
#include <string_view>
#include <system_error>
#include <utility>

#include "core/error.h"
#include "core/shown_text.h"
#include "core/stop_request.h"
#include "core/text_file.h"
#include "datasets/hdf5_file.h"
#include "methods/method_registry.h"
#include "metrics/resource_usage.h"
#include "protocols/profiles.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/commands/command_table.h"
#include "tools/fscil-bench/options/help_text.h"
#include "tools/fscil-bench/options/config_file.h"
#include "tools/fscil-bench/options/machine_info.h"
#include "tools/fscil-bench/options/run_option_table.h"

namespace fscil {

namespace {

// One line naming what was wrong; earlier result files stay as they were written. Whatever a
// library or a path put in the message, no raw byte reaches the terminal (a line break is spelled
// \n, never cut at: the reason follows the path), and past 2000 characters the middle goes, not
// the end, where the reason is.
void print_error(const std::string& message, const char* hint = "") {
  std::string shown = shown_text(message, 6 * message.size() + 1);  // whole: an escape takes up to 6 characters
  constexpr std::size_t kHead = 1200, kTail = 800;
  if (shown.size() > kHead + kTail) {
    const auto on_a_character = [&](std::size_t at) {  // not inside a UTF-8 sequence
      while (at < shown.size() && (static_cast<unsigned char>(shown[at]) & 0xC0) == 0x80) ++at;
      return at;
    };
    const std::size_t head = on_a_character(kHead), tail = on_a_character(shown.size() - kTail);
    shown = fmt::format("{} ... ({} characters in all) ... {}", shown.substr(0, head), shown.size(), shown.substr(tail));
  }
  fmt::print(stderr, "fscil-bench: error: {}{}\n", shown, hint);
}

const CLI::Option* option_named(const CLI::App& app, const std::string& name) {
  if (const CLI::Option* option = app.get_option_no_throw(name)) return option;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (const CLI::Option* option = command->get_option_no_throw(name)) return option;
  }
  return nullptr;
}

// CLI11's message in the shape of ours ("--threads '1.5': expected a whole number"): its own words
// ("Could not convert", "At Most 1 required but received 2") never reach a user.
std::string cli_message(const CLI::App& app, const CLI::ParseError& error) {
  const std::string text = error.what();
  static const std::regex convert(R"(^Could not convert: (\S+) = (.*)$)");
  static const std::regex unexpected(R"(^The following arguments? (?:was|were) not expected: (.*)$)");
  static const std::regex missing(R"(^(\S+): \d+ required \S+ missing$)");
  static const std::regex repeated(R"(^(\S+): At Most 1 required but received (\d+)$)");
  // cli_range.h's read_by: "--x: 'v': expected ..." and "--x: --x v: ..." in the shape of ours.
  static const std::regex refused_value(R"(^(--\S+): ('.*': expected .*)$)");
  static const std::regex named_twice(R"(^(--\S+): (--\S+ .*)$)");
  std::smatch match;
  if (std::regex_match(text, match, convert)) {
    const CLI::Option* option = option_named(app, match[1]);
    const std::string type = option != nullptr ? option->get_type_name() : "";
    const bool whole = type.rfind("INT", 0) == 0;
    static const std::regex digits(R"(^[+-]?[0-9]+$)");
    if (whole && std::regex_match(match[2].str(), digits)) {  // a whole number, only past what the option holds
      const bool negative = match[2].str().front() == '-';
      return fmt::format("{} '{}': a whole number too {} for this option", match[1].str(), match[2].str(),
                         negative ? "small" : "large");
    }
    const char* expected = whole ? "a whole number" : type.rfind("FLOAT", 0) == 0 ? "a number" : "a value";
    return fmt::format("{} '{}': expected {}", match[1].str(), match[2].str(), expected);
  }
  if (std::regex_match(text, match, unexpected)) {
    // CLI11's message lists the words last first ("'x --mem=8G'" for "--mem=8G x"); what is left
    // unparsed is in the order typed.
    const std::vector<std::string> left = app.remaining(true);
    const std::string words = left.empty() ? match[1].str() : fmt::format("{}", fmt::join(left, " "));
    return fmt::format("'{}': not an option, value or subcommand this command takes", words);
  }
  if (std::regex_match(text, match, refused_value)) return fmt::format("{} {}", match[1].str(), match[2].str());
  if (std::regex_match(text, match, named_twice) && match[2].str().rfind(match[1].str() + " ", 0) == 0) {
    return match[2].str();
  }
  if (std::regex_match(text, match, missing)) return fmt::format("{}: expected a value after it", match[1].str());
  if (std::regex_match(text, match, repeated)) {
    return fmt::format("{}: given {} times; give it once", match[1].str(), match[2].str());
  }
  return text;
}

// Where to read what was mistyped: the help of the subcommand given, or the program's.
std::string help_hint(const CLI::App& app) {
  const auto given = app.get_subcommands();
  return fmt::format(" (try: fscil-bench{} --help)", given.empty() ? "" : " " + given.front()->get_name());
}

// Parses `words`, where `typed` is what the user typed of them: an error in a value the --config
// file gave is the file's to name, not a flag the user never typed.
void parse_words(CLI::App& app, std::vector<std::string> words, const ConfigFile* config,
                 const std::vector<std::string>& typed) {
  std::vector<char*> pointers;
  for (auto& word : words) pointers.push_back(word.data());
  try {
    app.parse(static_cast<int>(pointers.size()), pointers.data());
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) throw;  // --help, --help-all
    const std::string message = cli_message(app, error);
    for (const auto& key : config == nullptr ? std::vector<std::string>{} : config->keys()) {
      const std::string option = "--" + key;
      if (!command_line_gives(typed, option) && message.rfind(option, 0) == 0 &&
          (message[option.size()] == ':' || message[option.size()] == ' ')) {
        throw CliError(fmt::format("--config {}: \"{}\"{}", config->file().string(), shown_text(key),
                                   message.substr(option.size())));
      }
    }
    throw CliError(message + help_hint(app));
  }
}

// argv with a --config file's options merged in (config_file.h), then parsed. The file's values
// that the command line overrides are parsed first, in their place, so that they are checked too;
// its "set" and "grid" values are named by the file in `run`, and the "set" values the command line
// replaced are kept there to be checked when read.
void parse(CLI::App& app, int argc, char** argv, RunOptions& run) {
  const std::vector<std::string> typed(argv, argv + argc);
  const std::string config_path = config_file_of(typed);
  if (config_path.empty()) return parse_words(app, typed, nullptr, typed);
  const ConfigFile config(config_path);
  const auto option_kind = [&](const std::string& name) {
    const CLI::Option* option = app.get_option_no_throw(name);
    if (option == nullptr) return OptionKind::unknown;
    return option->get_expected_min() == 0 ? OptionKind::flag : OptionKind::takes_value;
  };
  if (const auto unoverridden = config.without_its_options(typed, option_kind); unoverridden != typed) {
    parse_words(app, config.merged_into(unoverridden, option_kind), &config, unoverridden);
  }
  parse_words(app, config.merged_into(typed, option_kind), &config, typed);
  for (const auto& [key, value] : config.settings()) {
    if (ConfigFile::replaced_on_command_line(typed, key)) {
      run.replaced_assignments.push_back({key, value, config.settings_origin()});
    } else {
      run.assignment_origins[key] = config.settings_origin();
    }
  }
  for (const auto& [key, origin] : config.grid_origins(typed)) run.assignment_origins[key] = origin;
}

// Options that a run would otherwise ignore without a word.
void refuse_ignored_options(const Invocation& invocation) {
  if (invocation.given("--cache-dir") && invocation.run.no_cache) {
    throw CliError("--cache-dir and --no-cache: --no-cache reads and writes no cache; give one of them");
  }
  // These two options set a protocol parameter that --set and --grid can give as well: the --set
  // value won over the option without a word, and a sweep dropped the option.
  const std::pair<const char*, const char*> parameter_options[] = {{"--class-order", "class_order"},
                                                                   {"--split-mode", "split_mode"}};
  const auto names = [](const std::string& assignment, const char* key) {
    return assignment.substr(0, assignment.find('=')) == key;
  };
  for (const auto& [option, key] : parameter_options) {
    if (!invocation.given(option)) continue;
    const std::string fixed = fmt::format("{} {}", option, shown_text(invocation.app[option]->as<std::string>()));
    for (const auto& assignment : invocation.run.assignments) {
      if (!names(assignment, key)) continue;
      const auto origin = invocation.run.assignment_origins.find(key);
      throw CliError(fmt::format("{} and {}{}='{}': both set {}; give it once", fixed,
                                 origin == invocation.run.assignment_origins.end() ? "--set " : origin->second + ".",
                                 key, shown_text(assignment.substr(assignment.find('=') + 1)), key));
    }
    for (const CLI::App* command : invocation.app.get_subcommands()) {
      const CLI::Option* grid = command->get_option_no_throw("--grid");
      if (grid == nullptr) continue;
      for (const auto& axis : grid->results()) {
        if (names(axis, key)) {
          throw CliError(fmt::format("{} and --grid {}: a parameter is either fixed or swept", fixed, shown_text(axis)));
        }
      }
    }
  }
}

// --resume DIR continues the command whose --out it was: the one check of DIR for every command
// (cells and sweeps set RunOptions::resume themselves only on a folder they find).
void apply_resume(const Invocation& invocation) {
  if (invocation.given("--resume") && invocation.resume_dir.empty()) {
    throw CliError("--resume: expected the folder of the interrupted command (its --out)");
  }
  if (invocation.resume_dir.empty()) return;
  if (const std::string why = why_not_a_folder(invocation.resume_dir); !why.empty()) {
    throw CliError(fmt::format("--resume {}: {}, nothing to resume (give the --out of the interrupted command)",
                               invocation.resume_dir, why));
  }
  // An interrupted command leaves its .lock behind: a folder without one was never an --out.
  if (!written_by_fscil_bench(invocation.resume_dir)) {
    throw CliError(fmt::format("--resume {}: no fscil-bench command wrote there (no .lock, no result files), nothing "
                               "to resume; without --resume a run starts there", invocation.resume_dir));
  }
  RunOptions& run = invocation.run;
  if (invocation.given("--out") && run.out != invocation.resume_dir) {
    throw CliError(fmt::format("--resume {} and --out {}: a resumed run writes where it started", invocation.resume_dir,
                               run.out));
  }
  run.out = invocation.resume_dir;
  run.resume = true;
}

// The main job: every method x seed, or one cell of it.
int run_main_job(const Invocation& invocation) {
  invocation.require_methods_and_dataset();
  const RunOptions& run = invocation.run;
  fmt::print("{}", run.cell >= 0 ? run_cell(run, {}, run.cell) : run_benchmark(run));
  return exit_status::success;
}

// Tables printed to a full disk or a closed pipe are a failure, not a success.
void require_output_written() {
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    throw Error(fmt::format("standard output: cannot write ({})", errno != 0 ? std::strerror(errno) : "write error"));
  }
}

int run_subcommand(int argc, char** argv) {
  close_method_registry();
  keep_freed_memory_for_reuse();
  CLI::App app{"fscil-bench: few-shot class-incremental learning benchmarks on tactile and audio signals"};
  app.formatter(wrapping_help_formatter());  // before the subcommands, which take it over
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  app.set_version_flag("--version", version_text, "Release, commit and library versions, then exit");
  app.require_subcommand(0, 1);

  RunOptions run;
  // The readers of --methods and --profile need the method registry, which the option table's unit
  // tests do not link.
  declare_run_options(app, run,
                      {{"--methods", [](const std::string& text) { resolve_method_names(text); }},
                       {"--profile", [](const std::string& text) { require_profile(text); }}});
  Invocation invocation{run, app, {}};
  app.add_option("--resume", invocation.resume_dir,
                 "continue the interrupted command whose --out was DIR (give the same options): finished runs are "
                 "kept, a run stopped mid-way continues from its last session checkpoint");
  std::string config_file;  // read by parse() before CLI11 sees the words; declared for --help
  app.add_option("--config", config_file,
                 "JSON file of run options: {\"methods\": \"all\", \"seeds\": \"1-5\", \"set\": {\"shot\": 5}, \"grid\": "
                 "{\"pspc_probes\": [5, 50]}}; options given on the command line override it");
  std::vector<std::pair<CLI::App*, std::unique_ptr<Subcommand>>> subcommands;
  for (const auto& entry : subcommand_table()) {
    CLI::App* command = app.add_subcommand(entry.name, entry.summary);
    subcommands.emplace_back(command, entry.create());
    subcommands.back().second->declare(*command);
    if (command->get_fallthrough()) command->footer(run_options_footer(app));
  }

  try {
    parse(app, argc, argv, run);
    refuse_ignored_options(invocation);
    apply_resume(invocation);
    Subcommand* chosen = nullptr;
    for (auto& [command, subcommand] : subcommands) {
      if (command->parsed()) chosen = subcommand.get();
    }
    if (run.cell >= 0 && chosen != nullptr && !chosen->takes_cell()) {
      throw CliError("--cell: expected a run or sweep command (see: fscil-bench plan)");
    }
    if (chosen == nullptr || chosen->trains()) install_stop_handlers();
    const int status = chosen != nullptr ? chosen->run(invocation) : run_main_job(invocation);
    require_output_written();
    return status;
  } catch (const StopRequested& stop) {
    // Finished runs keep their result files, the run in progress its last session's checkpoint.
    fmt::print(stderr, "fscil-bench: {}: finished sessions are kept; continue with the same command and --resume "
                       "(a --cell continues by itself)\n", stop.what());
    return stop.status();
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --help-all
    print_error(error.what(), help_hint(app).c_str());
    return exit_status::usage;
  } catch (const Error& error) {
    print_error(error.what());
    return error.status();
  } catch (const std::filesystem::filesystem_error& error) {  // the path and the system's reason, not the library's text
    print_error(fmt::format("{}: {}", error.path1().empty() ? std::string("a path") : error.path1().string(),
                            error.code().message()));
    return exit_status::bad_input;
  } catch (const std::system_error& error) {
    // fmt::print's own failure to write stdout (a full disk, a closed pipe), as require_output_written() says it.
    const bool stdout_failed = std::string_view(error.what()).rfind("cannot write to file", 0) == 0;
    print_error(stdout_failed ? fmt::format("standard output: cannot write ({})", error.code().message()) : error.what());
    return exit_status::bad_input;
  } catch (const std::exception& error) {  // a library's own error
    print_error(error.what());
    return exit_status::bad_input;
  }
}

}  // namespace

int run_command_line(int argc, char** argv) {
  std::signal(SIGXFSZ, SIG_IGN);  // a file-size limit fails the write (EFBIG), which is reported, instead of killing
  const int status = run_subcommand(argc, argv);
  if (hdf5_cannot_shut_down()) {  // its error is printed; HDF5's exit handler would crash
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    std::_Exit(status);
  }
  return status;
}

}  // namespace fscil
