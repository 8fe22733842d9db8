#include "tools/fscil-bench/cells/command_arguments.h"

namespace fscil {

std::vector<std::string> command_arguments(const RunOptions& options, const std::vector<std::string>& grid) {
  std::vector<std::string> words;
  if (!grid.empty()) {
    words.emplace_back("sweep");
    for (const auto& axis : grid) words.insert(words.end(), {"--grid", axis});
  }
  words.insert(words.end(), {"--methods", options.methods, "--dataset", options.dataset, "--profile", options.profile,
                             "--seeds", options.seeds, "--out", options.out, "--features", options.features,
                             "--split-mode", options.split_mode, "--class-order", options.class_order,
                             "--evaluate-on", options.evaluate_on, "--selection", options.selection});
  if (!options.data_root.empty()) words.insert(words.end(), {"--data-root", options.data_root});
  if (!options.cache_dir.empty()) words.insert(words.end(), {"--cache-dir", options.cache_dir});
  if (options.no_cache) words.emplace_back("--no-cache");
  if (options.no_stage_cache) words.emplace_back("--no-stage-cache");
  if (!options.save_embeddings.empty()) words.insert(words.end(), {"--save-embeddings", options.save_embeddings});
  if (options.save_model) words.emplace_back("--save-model");
  if (!options.max_memory.empty()) words.insert(words.end(), {"--max-memory", options.max_memory});
  for (const auto& assignment : options.assignments) words.insert(words.end(), {"--set", assignment});
  if (options.quiet) words.emplace_back("--quiet");
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
