#include "tools/fscil-bench/options/help_text.h"

#include <algorithm>
#include <sstream>
#include <vector>

namespace fscil {

namespace {

// Leaves room for CLI11's two-space indent before an option's name.
constexpr std::size_t kOptionColumn = 30;

class WrappingFormatter : public CLI::Formatter {
 public:
  explicit WrappingFormatter(std::size_t width = kHelpColumns) : width_(width) { column_width(kOptionColumn); }

  std::string make_option_desc(const CLI::Option* option) const override {
    return wrap_words(CLI::Formatter::make_option_desc(option), width_ - kOptionColumn);
  }

  std::string make_subcommand(const CLI::App* sub) const override {
    std::stringstream out;
    CLI::detail::format_help(out, sub->get_display_name(true),
                             wrap_words(sub->get_description(), width_ - kOptionColumn), kOptionColumn);
    return out.str();
  }

  std::string make_description(const CLI::App* app) const override {
    const std::string description = CLI::Formatter::make_description(app);
    return description.empty() ? description : wrap_words(description, width_) + "\n";
  }

  // --help-all indents each subcommand's help by two: it is laid out two narrower.
  std::string make_expanded(const CLI::App* sub) const override {
    return WrappingFormatter(width_ - 2).CLI::Formatter::make_expanded(sub);
  }

 private:
  std::size_t width_;
};

}  // namespace

std::string wrap_words(const std::string& text, std::size_t width, std::size_t indent) {
  std::vector<std::string> lines(1);
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    const std::size_t used = (lines.size() > 1 ? indent : 0) + lines.back().size();
    if (!lines.back().empty() && used + 1 + word.size() > width) {
      lines.push_back(word);
    } else {
      lines.back() += (lines.back().empty() ? "" : " ") + word;
    }
  }
  std::string wrapped = lines.front();
  for (std::size_t i = 1; i < lines.size(); ++i) wrapped += '\n' + std::string(indent, ' ') + lines[i];
  return wrapped;
}

std::string labelled_lines(const std::string& label, const std::string& text, std::size_t column) {
  std::string row = label;
  row.resize(std::max(column, label.size() + 1), ' ');
  const std::size_t indent = row.size();
  for (const char c : wrap_words(text, kHelpColumns - std::min(indent, kHelpColumns - 20))) {
    row += c;
    if (c == '\n') row.append(indent, ' ');
  }
  return row;
}

std::shared_ptr<CLI::Formatter> wrapping_help_formatter() { return std::make_shared<WrappingFormatter>(); }

std::string run_options_footer(const CLI::App& main_command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : main_command.get_options()) {
    const std::string name = option->get_name();
    if (name == "--help" || name == "--help-all" || name == "--version") continue;
    names.push_back(name);
  }
  std::string text = "Also takes the run options (fscil-bench --help says what each does):";
  for (const std::string& name : names) text += ' ' + name;
  return wrap_words(text, kHelpColumns, 2);
}

}  // namespace fscil
