#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "metrics/session_accuracy.h"

namespace fscil {

struct SessionRecord {
  int session = 0;
  int seen_classes = 0;
  SessionAccuracy accuracy;
  double train_seconds = 0;
  double test_seconds = 0;
  // Context-to-class dispersion of the test embeddings; NaN (null in JSON) when unknown.
  double context_ratio_mean = std::numeric_limits<double>::quiet_NaN();
  double context_ratio_max = std::numeric_limits<double>::quiet_NaN();
  // What the method reported while it trained this session (base validation accuracy after each
  // stage, mean loss terms, PSPC's effective shots, ...).
  std::map<std::string, double> diagnostics;
};

// The trained model's inference cost per sample, after the last session (rules in
// metrics/model_cost.h) and its measured inference time (IT).
struct InferenceRecord {
  std::int64_t macs = 0;
  std::int64_t parameters = 0;
  std::int64_t trainable_parameters = 0;
  double seconds_per_sample = 0;  // median over repeated batches of `batch` test samples
  std::int64_t batch = 0;
};

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
  std::map<std::string, std::string> parameters;  // every hyper-parameter and knob used
  // The subset of `parameters` the dataset and the session protocol read (way, shot, context
  // strength, ...): runs of different methods compare only when these agree. Empty in files
  // written before it was recorded.
  std::map<std::string, std::string> protocol_parameters;
  std::map<std::string, std::string> machine;     // host, cores, CPU, compiler, library versions
  std::string version;     // the harness's release; empty in files written before it was recorded
  std::string git_commit;  // the commit the binary was built from
  std::string dataset_key;  // cache key: which exact data was used
  std::vector<SessionRecord> sessions;
  double total_seconds = 0;
  std::int64_t peak_resident_bytes = 0;  // this run's peak, dataset included
  InferenceRecord inference;  // all zero in files written before costs were counted
  // Real old samples the method stores after its last session (OrCo's trade-off); 0 for none.
  std::int64_t replay_samples = 0;
  std::int64_t replay_bytes = 0;

  // The file this record was read from (not written to it); empty for a run in progress.
  std::string source;

  std::vector<double> session_accuracies() const;
};

std::string run_record_file_name(const RunRecord& record);
std::string to_json_text(const RunRecord& record);
RunRecord run_record_from_json_text(const std::string& text, const std::string& origin);

void save_run_record(const std::filesystem::path& directory, const RunRecord& record);
// Every *.json result file below `directory`, sorted by path. Throws ReportError on a bad file
// and on runs that cannot be compared (see require_comparable_runs).
std::vector<RunRecord> load_run_records(const std::filesystem::path& directory);

}  // namespace fscil
