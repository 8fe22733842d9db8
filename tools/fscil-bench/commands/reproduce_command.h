#pragma once
#include <string>
#include <utility>
#include <vector>

#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// fscil-bench reproduce --list: every named reproduction, with the paper's caption and what runs.
std::string list_reproductions();
// Every reproduction's name and the paper's caption, in the catalogue's order (for `list`).
std::vector<std::pair<std::string, std::string>> reproduction_captions();

// fscil-bench reproduce NAME: the runs (or sweep) behind one of the paper's tables or figures with
// `options` (dataset, profile, seeds, threads, out, resume), then that table in the paper's layout
// as OUT/NAME.tex, NAME.md and NAME.csv (the paper's numbers beside ours where it has them), its
// figures under OUT/figures/, and OUT/index.html. Returns the Markdown. Throws CliError for an
// unknown name or for --methods (a reproduction runs its own).
std::string run_reproduction(const std::string& name, RunOptions options);

}  // namespace fscil
