// Reference-number files: what loads is written back and loads again to as many values, anything
// else is a ReportError naming file and line.
#include "reports/reference_numbers.h"
#include "core/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  const auto path = fuzz::scratch_file("reference.csv", fuzz::text_of(data, size));
  fuzz::expect_only<ReportError>([&] {
    const auto values = load_reference_csv(path);
    for (const auto& value : values) fuzz::require(value.tolerance >= 0);
    const auto again = fuzz::scratch_file("again.csv", render_reference_csv(values, "fuzz"));
    fuzz::require(load_reference_csv(again).size() == values.size());
  });
  return 0;
}
