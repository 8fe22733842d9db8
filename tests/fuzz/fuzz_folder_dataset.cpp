// The folder format (dataset.json + manifest.csv + recordings), scanned as a lab's own dataset and
// as HapTex, then every recording read. The input is split at NUL bytes into dataset.json,
// manifest.csv, a CSV recording (written as rec.csv and rec2.csv) and a single-column recording
// (a.txt, b.txt, c.txt, so that a manifest can name one per channel).
#include <array>

#include "core/error.h"
#include "datasets/readers/folder_adapter.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

// A manifest naming an absolute path or climbing out of the tree would send the reader through
// the machine's own files: not the reader's behaviour we are after, and unbounded in size.
bool stays_in_tree(std::string_view manifest) {
  if (manifest.find("..") != std::string_view::npos) return false;
  bool at_name_start = true;
  for (const char c : manifest) {
    if (c == '/' && at_name_start) return false;
    if (c == ',' || c == ';' || c == '\n') {
      at_name_start = true;
    } else if (c != ' ' && c != '\t' && c != '\r' && c != '"') {
      at_name_start = false;
    }
  }
  return true;
}

void scan_and_read(fscil::DatasetScan (*scan_of)(const std::filesystem::path&)) {
  const fscil::DatasetScan scan = scan_of(fscil::fuzz::scratch_folder());
  for (const auto& recording : scan.recordings) scan.read(recording);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  std::array<std::string_view, 4> parts;
  std::string_view rest = fuzz::text_of(data, size);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const auto end = p + 1 < parts.size() ? rest.find('\0') : std::string_view::npos;
    parts[p] = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
  }
  if (!stays_in_tree(parts[1])) return -1;
  fuzz::scratch_file("dataset.json", parts[0]);
  fuzz::scratch_file("manifest.csv", parts[1]);
  for (const char* name : {"rec.csv", "rec2.csv"}) fuzz::scratch_file(name, parts[2]);
  for (const char* name : {"a.txt", "b.txt", "c.txt"}) fuzz::scratch_file(name, parts[3]);
  fuzz::expect_only<DatasetError>([] { scan_and_read(scan_tactile_folder); });
  fuzz::expect_only<DatasetError>([] { scan_and_read(scan_haptex); });
  return 0;
}
