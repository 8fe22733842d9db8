// fscil-bench: run FSCIL methods on tactile and audio datasets and tabulate the results.
#include "tools/fscil-bench/command_line.h"

int main(int argc, char** argv) { return fscil::fscil_bench_main(argc, argv); }
