#pragma once

namespace fscil {

// The number type the shared encoder computes in (--precision). Under bf16 its convolutions,
// matrix products and their gradients run in bfloat16 (LibTorch's CPU autocast, from the stem to
// the last stage's map); its input norm, its weights and their gradients, the batch norms'
// running statistics, the optimiser and everything after the embedding stay fp32. It pays only
// where the CPU computes bf16 natively (AVX512-BF16 or AMX): docs/profiling.md, "bfloat16".
enum class Precision { fp32, bf16 };

}  // namespace fscil
