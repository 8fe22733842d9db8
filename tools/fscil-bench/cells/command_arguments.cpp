#include "tools/fscil-bench/cells/command_arguments.h"

#include "tools/fscil-bench/options/run_option_table.h"

namespace fscil {

std::vector<std::string> command_arguments(const RunOptions& options, const std::vector<std::string>& grid) {
  std::vector<std::string> words;
  if (!grid.empty()) {
    words.emplace_back("sweep");
    for (const auto& axis : grid) words.insert(words.end(), {"--grid", axis});
  }
  for (auto& word : run_option_words(options)) words.push_back(std::move(word));
  return words;
}

std::string shell_command(const std::vector<std::string>& words) {
  std::string line;
  for (const auto& word : words) {
    if (!line.empty()) line += ' ';
    const bool plain = !word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                                "0123456789_-.,/=+:@%") == std::string::npos;
    if (plain) {
      line += word;
      continue;
    }
    line += '\'';
    for (char c : word) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

}  // namespace fscil
