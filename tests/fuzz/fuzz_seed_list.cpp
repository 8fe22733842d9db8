// --seeds values: a list is accepted with distinct seeds, or refused with CliError.
#include <algorithm>
#include <set>

#include "tests/fuzz/fuzz_support.h"
#include "core/error.h"
#include "tools/fscil-bench/options/seed_list.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  fuzz::expect_only<CliError>([&] {
    const auto seeds = parse_seed_list(std::string(fuzz::text_of(data, size)));
    fuzz::require(!seeds.empty() && std::set(seeds.begin(), seeds.end()).size() == seeds.size());
  });
  return 0;
}
