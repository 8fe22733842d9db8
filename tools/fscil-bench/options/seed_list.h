#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace fscil {

// "1,2,3", "1-5" or "1,4-6" -> the seeds in order; throws CliError on anything else.
std::vector<std::uint64_t> parse_seed_list(const std::string& text);

}  // namespace fscil
