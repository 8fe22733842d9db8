#pragma once
#include <map>
#include <string>

namespace fscil {

// Host, cores, compiler and library versions for result files (Google Benchmark's Context).
std::map<std::string, std::string> describe_machine();
// The git commit this binary was built from (with "-dirty" when tracked files differed from it),
// or "unknown"; written at build time by tools/source_commit.cmake.
std::string source_commit();

}  // namespace fscil
