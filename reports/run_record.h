#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "metrics/session_accuracy.h"
#include "metrics/session_outcome.h"

namespace fscil {

// The trained model's inference cost per sample, after the last session (rules in
// metrics/model_cost.h) and its measured inference time (IT).
struct InferenceRecord {
  std::int64_t macs = 0;
  std::int64_t parameters = 0;
  std::int64_t trainable_parameters = 0;
  double seconds_per_sample = 0;  // median over repeated batches of `batch` test samples
  std::int64_t batch = 0;
};

// A sweep cell: key=value in the order the command's --grid gave its keys (the first varies
// slowest); tables, labels and cell folders follow that order.
using GridCell = std::vector<std::pair<std::string, std::string>>;
// The value `cell` gives `key`, or nullptr.
const std::string* grid_value(const GridCell& cell, const std::string& key);
// `cell` without `key`.
GridCell without_key(GridCell cell, const std::string& key);
// Whether two cells assign the same values, whatever the order of their keys.
bool same_cell(const GridCell& a, const GridCell& b);
// `cell` with its keys in the order of `keys` (keys it lacks skipped), any others after, as they were.
GridCell in_key_order(const GridCell& cell, const std::vector<std::string>& keys);
// Appends to `keys` those of `cell` it does not hold yet, in the cell's order: over a folder's
// cells, every key in order of first appearance (the one rule of a table's grid columns).
void add_new_keys(const GridCell& cell, std::vector<std::string>& keys);

// Everything one (method, dataset, seed) run produced: the schema of result files, from
// which every report can be rebuilt.
struct RunRecord {
  std::string method;
  std::string dataset;
  std::string profile;
  std::uint64_t seed = 0;
  int threads = 0;
  // The split every session was scored on: "test", or "validation" (the protocol defaults are
  // chosen on). Files written before the choice existed were scored on test.
  std::string evaluated_on = "test";
  // How training epochs were chosen where a reference code chooses them (RunOptions::selection):
  // "last", "validation", or "test-oracle" (by test score, the reference codes' habit: inflated).
  std::string selection = "last";
  // The sweep cell this run belongs to (fscil-bench sweep --grid key=values). Runs of different
  // cells are different rows of every table. Empty outside a sweep.
  GridCell grid;
  std::map<std::string, std::string> parameters;  // every hyper-parameter and knob used
  // The subset of `parameters` the dataset and the session protocol read (way, shot, context
  // strength, ...): runs of different methods compare only when these agree. Empty in files
  // written before it was recorded.
  std::map<std::string, std::string> protocol_parameters;
  std::map<std::string, std::string> machine;     // host, cores, CPU, compiler, library versions
  std::string version;     // the harness's release; empty in files written before it was recorded
  std::string git_commit;  // the commit the binary was built from
  std::string dataset_key;  // cache key: which exact data was used
  // What the runner measured (metrics/session_outcome.h), written by metrics/session_json.h.
  std::vector<SessionOutcome> sessions;
  double total_seconds = 0;
  // The process's peak resident memory during this run, and its resident memory when the run
  // began (0 in files written before it was recorded): the data and whatever the process loaded
  // before, which the run shares with every other run of the command.
  std::int64_t peak_resident_bytes = 0;
  std::int64_t resident_at_start_bytes = 0;
  InferenceRecord inference;  // all zero in files written before costs were counted
  // Real old samples the method stores after its last session (OrCo's trade-off); 0 for none.
  std::int64_t replay_samples = 0;
  std::int64_t replay_bytes = 0;
  // What every table says of the method's numbers (MethodEntry::table_note); empty for a method run
  // as its release runs it, and in files written before it was recorded.
  std::string method_note;

  // The file this record was read from (not written to it); empty for a run in progress.
  std::string source;

  std::vector<double> session_accuracies() const;
};

std::string run_record_file_name(const RunRecord& record);
// The memory the run itself added: its peak above the resident memory it began with (the whole
// process's peak for a file without the start).
std::int64_t run_peak_bytes(const RunRecord& record);
// What the run's encoder computed in (--precision): "bf16" where its protocol parameters say so,
// "fp32" otherwise (files written before the option existed are fp32).
std::string precision_of(const RunRecord& record);
// Its protocol_parameters' removal (session_plan.h): "none" for add-only runs and files from before it.
std::string removal_of(const RunRecord& record);
// The selections and precisions a result file may name (--selection, --precision); the require_
// forms throw ReportError "selection 'x': expected last, validation or test-oracle". And whether a
// run was selected on the test split.
bool is_selection_name(const std::string& name);
bool is_precision_name(const std::string& name);
void require_selection_name(const std::string& name);
void require_precision_name(const std::string& name);
bool selected_on_test(const RunRecord& record);
// A sweep key or value: letters, digits, '_', '.' and '-' only (it names folders and fills CSV fields).
bool is_grid_text(const std::string& text);
// "key=value+key=value" of a sweep cell in its key order (folder name of the cell; "" outside a sweep).
std::string grid_cell_name(const GridCell& grid);
// "label [key=value+...]" for a row or series of a sweep cell, `label` alone outside a sweep: how
// every table and figure names a method's row.
std::string label_with_cell(const std::string& label, const GridCell& grid);
std::string to_json_text(const RunRecord& record);
RunRecord run_record_from_json_text(const std::string& text, const std::string& origin);

// The largest result file read. The runner writes a few hundred KB at most (the fast profile's
// longest training log, AMFO's, about 520 KB); a larger file is refused before it is read.
constexpr std::uintmax_t kMaxResultFileBytes = 64u << 20;

// `file` read (at most kMaxResultFileBytes) and parsed; its `source` is `file`.
RunRecord read_run_record(const std::filesystem::path& file);

void save_run_record(const std::filesystem::path& directory, const RunRecord& record);
// Every *.json result file below `directory`, sorted by path, the keys of their sweep cells in one
// order (the first file's, then keys it lacks as they come). Throws ReportError on a bad file
// and on runs that cannot be compared (see require_comparable_runs).
std::vector<RunRecord> load_run_records(const std::filesystem::path& directory);

}  // namespace fscil
