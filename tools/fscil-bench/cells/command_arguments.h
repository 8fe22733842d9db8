#pragma once
#include <string>
#include <vector>

#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// The arguments that repeat the command `options` and `grid` describe (a sweep when `grid` is
// not empty), without --threads, --resume and --cell, which the caller adds per cell. Every
// option is written out, defaults included, so a script states exactly what it runs.
std::vector<std::string> command_arguments(const RunOptions& options, const std::vector<std::string>& grid);

// `words` as one line a POSIX shell reads back word for word (single quotes where needed).
std::string shell_command(const std::vector<std::string>& words);

}  // namespace fscil
