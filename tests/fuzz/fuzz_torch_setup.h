#pragma once
#include <torch/torch.h>

#include <string>

namespace fscil::fuzz {

// For LLVMFuzzerInitialize of the torch targets: one thread, and no C++ backtrace in LibTorch's
// error messages. Every LibTorch error symbolizes one, some 100 ms under ASan: the messages lose
// it, the fuzzer gains tenfold speed.
inline void set_up_torch() {
  torch::set_num_threads(1);
  c10::SetStackTraceFetcher([] { return std::string(); });
}

}  // namespace fscil::fuzz
