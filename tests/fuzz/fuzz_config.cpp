// Config files (--config): an accepted file becomes a command line that starts with the program and
// keeps the user's words; anything else is a CliError naming the file, never a library's error.
#include <algorithm>

#include "core/error.h"
#include "tests/fuzz/fuzz_support.h"
#include "tools/fscil-bench/options/config_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  const auto file = fuzz::scratch_file("run.json", fuzz::text_of(data, size));
  const auto kind = [](const std::string& name) {
    if (name == "--quiet" || name == "--save-model") return OptionKind::flag;
    if (name == "--methods" || name == "--seeds" || name == "--threads" || name == "--set") return OptionKind::takes_value;
    return OptionKind::unknown;
  };
  fuzz::expect_only<CliError>([&] {
    const std::vector<std::string> typed = {"fscil-bench", "sweep", "--threads", "2"};
    const auto words = ConfigFile(file).merged_into(typed, kind);
    fuzz::require(words.size() >= typed.size() && words.front() == "fscil-bench");
    fuzz::require(std::find(words.begin(), words.end(), "sweep") != words.end());
  });
  return 0;
}
