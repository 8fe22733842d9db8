#pragma once
#include <map>
#include <string>

namespace fscil {

// Host, cores, compiler and library versions for result files (Google Benchmark's Context).
std::map<std::string, std::string> describe_machine();
// LibTorch, OpenBLAS, FFTW, HDF5 and libsndfile as this process runs them.
std::map<std::string, std::string> library_versions();
// The kernels ATen, OpenBLAS and oneDNN chose for this CPU, e.g. "aten=AVX2 openblas=Zen
// onednn=avx2" (no commas: it is a field of reference files). Runs agree to the bit only when
// these and the thread count agree.
std::string numeric_kernels();
// Whether oneDNN computes bfloat16 natively on this CPU (AVX512-BF16 or AMX); elsewhere it emulates it.
bool bf16_is_native();
// The harness's release (CMake's project version).
std::string harness_version();
// The git commit this binary was built from (with "-dirty" when tracked files differed from it),
// or "unknown"; written at build time by tools/fscil-bench/build_info.cmake.
std::string source_commit();
// A digest of this executable's bytes and of what it runs on (`machine`, describe_machine()'s
// result, but the host name: libraries, CPU, BLAS, kernels, hardware threads): the identity of the code
// that trains a cached base (protocols/stage_cache.h). Any rebuild that changes the code changes
// it. Empty when the executable cannot be read.
std::string code_digest(const std::map<std::string, std::string>& machine);
// What `fscil-bench --version` prints: release, commit, libraries, kernels, compiler and the data
// folder (tools/fscil-bench/options/data_folder.h), a line each.
std::string version_text();

}  // namespace fscil
