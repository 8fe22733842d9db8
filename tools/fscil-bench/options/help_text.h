#pragma once
#include <CLI/CLI.hpp>

#include <cstddef>
#include <memory>
#include <string>

namespace fscil {

// Help and listings fit a terminal this wide, whatever COLUMNS says.
inline constexpr std::size_t kHelpColumns = 100;

// `text` broken between words into lines of at most `width` characters (a word longer than that
// stands on a line of its own), joined by '\n'; each line after the first starts with `indent`
// spaces, which count toward `width`.
std::string wrap_words(const std::string& text, std::size_t width, std::size_t indent = 0);

// `label` padded to `column` characters (or followed by one space where it is longer), then `text`
// wrapped to end by kHelpColumns, its lines after the first indented to `column`: a listing's row.
std::string labelled_lines(const std::string& label, const std::string& text, std::size_t column);

// CLI11's help with every description wrapped to kHelpColumns beside its option column.
std::shared_ptr<CLI::Formatter> wrapping_help_formatter();

// The footer of a subcommand that takes the run options through (CLI11's fallthrough): their
// names, wrapped, so its --help says what it takes rather than "every run option".
std::string run_options_footer(const CLI::App& main_command);

}  // namespace fscil
