// Checkpoint files as they lie on disk (magic line, length and digest, torch archive): a file
// loads or is a ProtocolError. Mutations mostly stop at the length and digest check here;
// fuzz_checkpoint_body gets past it with archives LibTorch's own writer made.
//
// tools/fuzz.sh runs this target with -use_cmp=0. With comparison feedback libFuzzer learns the
// 16 digest digits and forges archives that no damage produces (a changed body keeps its FNV-1a
// digest with odds of 2^-64); a forged archive reaches LibTorch 1.13's unpickler, which allocates
// whatever size a record declares (31 GB in the first 10-minute run): upstream's code, not ours.
#include <torch/torch.h>

#include "core/error.h"
#include "protocols/run_checkpoint.h"
#include "tests/fuzz/fuzz_support.h"
#include "tests/fuzz/fuzz_torch_setup.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fscil::fuzz::set_up_torch();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  const auto path = fuzz::scratch_file("run.ckpt", fuzz::text_of(data, size));
  fuzz::expect_only<ProtocolError>([&] { load_checkpoint(path, "fuzz-run"); });
  return 0;
}
