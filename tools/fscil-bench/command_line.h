#pragma once
#include "tools/fscil-bench/options/data_folder.h"

namespace fscil {

// The whole fscil-bench command line: parses argv, runs the subcommand, returns the exit status.
int run_command_line(int argc, char** argv);

// main() of fscil-bench, and of a program built against the installed package that adds methods
// with register_method() first (README "Adding a method"): such a program reads the paper's tables
// and the released configs from that package (its config sets FSCIL_BENCH_PACKAGE_DATA).
inline int fscil_bench_main(int argc, char** argv) {
#ifdef FSCIL_BENCH_PACKAGE_DATA
  use_package_data_folder(FSCIL_BENCH_PACKAGE_DATA);
#endif
  return run_command_line(argc, argv);
}

}  // namespace fscil
