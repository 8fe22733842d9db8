// fscil-bench's whole command line with one more method: `my-bench list` shows it, and
// --methods small-cnn-ncm,prototype runs it beside the built-in ones.
#include <methods/method_registry.h>
#include <tools/fscil-bench/command_line.h>

#include "small_cnn_ncm_method.h"

int main(int argc, char** argv) {
  // Name, summary and factory; then what the tools need to know of it: no group, and the parameter
  // that counts its base epochs (the cost class `my-bench plan` shows). No profile shortens it: its
  // 3 epochs are short already.
  fscil::register_method({"small-cnn-ncm", "example out of tree: a small CNN trained on the base classes, "
                          "nearest class mean over its embeddings", &make_small_cnn_ncm_method, {}, {"ncm_epochs"}});
  return fscil::fscil_bench_main(argc, argv);
}
