#include "tools/fscil-bench/options/seed_list.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <sstream>

#include "core/shown_text.h"
#include "core/error.h"
#include "core/number_text.h"

namespace fscil {

namespace {

std::uint64_t parse_seed(const std::string& text, const std::string& whole) {
  if (text.empty() || text.size() > 18 ||
      !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); })) {
    throw CliError(fmt::format("--seeds '{}': expected comma-separated non-negative integers or ranges like 1-5",
                               whole));
  }
  return *parse_number<std::uint64_t>(text);  // at most 18 digits: always a 64-bit number
}

}  // namespace

std::vector<std::uint64_t> parse_seed_list(const std::string& text) {
  std::vector<std::uint64_t> seeds;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const auto dash = item.find('-');
    if (dash == std::string::npos) {
      seeds.push_back(parse_seed(item, text));
      continue;
    }
    const std::uint64_t first = parse_seed(item.substr(0, dash), text);
    const std::uint64_t last = parse_seed(item.substr(dash + 1), text);
    if (last < first || last - first > 1000) {
      throw CliError(fmt::format("--seeds '{}': range {} must run upwards over at most 1000 seeds", text, item));
    }
    for (std::uint64_t seed = first; seed <= last; ++seed) seeds.push_back(seed);
  }
  if (seeds.empty() || text.back() == ',') {
    throw CliError(fmt::format("--seeds '{}': expected comma-separated non-negative integers or ranges like 1-5", shown_text(text)));
  }
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    if (std::count(seeds.begin(), seeds.end(), seeds[i]) > 1) {
      throw CliError(fmt::format("--seeds '{}': seed {} is listed twice", text, seeds[i]));
    }
  }
  return seeds;
}

}  // namespace fscil
