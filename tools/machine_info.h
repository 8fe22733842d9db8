#pragma once
#include <map>
#include <string>

namespace fscil {

// Host, cores, compiler and library versions for result files (Google Benchmark's Context).
std::map<std::string, std::string> describe_machine();
// LibTorch, OpenBLAS, FFTW, HDF5 and libsndfile as this process runs them.
std::map<std::string, std::string> library_versions();
// The harness's release (CMake's project version).
std::string harness_version();
// The git commit this binary was built from (with "-dirty" when tracked files differed from it),
// or "unknown"; written at build time by tools/build_info.cmake.
std::string source_commit();
// What `fscil-bench --version` prints: release, commit, libraries and compiler, a line each.
std::string version_text();

}  // namespace fscil
