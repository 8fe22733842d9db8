// Result files: an accepted record is written back and read again unchanged in its sessions,
// anything else is a ReportError naming the file.
#include "core/error.h"
#include "reports/run_record.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  fuzz::expect_only<ReportError>([&] {
    const RunRecord record = run_record_from_json_text(std::string(fuzz::text_of(data, size)), "fuzz.json");
    fuzz::require(!record.sessions.empty());
    const RunRecord again = run_record_from_json_text(to_json_text(record), "again.json");
    fuzz::require(again.sessions.size() == record.sessions.size() && again.seed == record.seed &&
                  again.threads == record.threads && again.parameters == record.parameters);
  });
  return 0;
}
