// fscil-bench's whole command line with one more method: `my-bench list` shows it, and
// --methods small-cnn-ncm,prototype runs it beside the built-in ones.
#include <methods/method_registry.h>
#include <tools/fscil-bench/command_line.h>

#include <utility>

#include "small_cnn_ncm_method.h"

int main(int argc, char** argv) {
  // Name, summary and factory; then what the tools need to know of it: the parameter that counts
  // its base epochs (the cost class `my-bench plan` shows), and that its sessions leave the encoder
  // as the base left it. No group; no profile shortens it: its 3 epochs are short already.
  fscil::MethodEntry entry{"small-cnn-ncm", "example out of tree: a small CNN trained on the base classes, "
                           "nearest class mean over its embeddings", &make_small_cnn_ncm_method};
  entry.base_epoch_keys = {"ncm_epochs"};
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base
  fscil::register_method(std::move(entry));
  return fscil::fscil_bench_main(argc, argv);
}
