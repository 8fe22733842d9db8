// The text-table readers (CSV with a header, one number per line, signal CSV) on one file:
// accepted tables are rectangular and accepted signals finite, everything else is a DatasetError.
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "datasets/readers/text_table.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

bool finite_and_shaped(const fscil::SignalData& signal) {
  return signal.channels >= 1 && signal.length >= 1 &&
         signal.values.size() == static_cast<std::size_t>(signal.channels * signal.length) &&
         std::all_of(signal.values.begin(), signal.values.end(), [](float v) { return std::isfinite(v); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  const auto path = fuzz::scratch_file("table.csv", fuzz::text_of(data, size));
  fuzz::expect_only<DatasetError>([&] {
    const TextTable table = read_text_table(path);
    fuzz::require(table.rows.size() == table.line_of_row.size());
    for (const auto& row : table.rows) fuzz::require(row.size() == table.header.size());
    // Every column of the header as a channel, then one the header lacks.
    fuzz::require(finite_and_shaped(read_signal_csv(path, table.header)));
    read_signal_csv(path, {"absent channel"});
  });
  fuzz::expect_only<DatasetError>([&] { fuzz::require(finite_and_shaped(read_single_column(path))); });
  return 0;
}
