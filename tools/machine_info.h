#pragma once
#include <map>
#include <string>

namespace fscil {

// Host, cores, compiler and library versions for result files (Google Benchmark's Context).
std::map<std::string, std::string> describe_machine();
// The source tree's git commit (with "-dirty" when it has uncommitted changes), or "unknown".
std::string source_commit();

}  // namespace fscil
