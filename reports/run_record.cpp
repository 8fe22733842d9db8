#include "reports/run_record.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/shown_text.h"
#include "core/atomic_file.h"
#include "reports/comparable_runs.h"
#include "core/text_file.h"
#include "core/error.h"

namespace fscil {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
constexpr int kSchemaVersion = 1;
constexpr const char* kGridCharacters = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-";

// JSON has no NaN: unknown values are null.
json number_or_null(double value) { return std::isnan(value) ? json(nullptr) : json(value); }
double number_from(const json& value) {
  return value.is_null() ? std::numeric_limits<double>::quiet_NaN() : value.get<double>();
}

// A whole number that fits T: get<T>() would convert 1e300 or -1.5 with undefined behaviour.
template <typename T>
T whole_number(const json& value, const std::string& field, const std::string& origin) {
  constexpr auto most = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
  bool fits = false;
  if (value.is_number_unsigned()) {
    fits = value.get<std::uint64_t>() <= most;
  } else if (value.is_number_integer()) {
    const auto number = value.get<std::int64_t>();
    fits = number < 0 ? number >= static_cast<std::int64_t>(std::numeric_limits<T>::min())
                      : static_cast<std::uint64_t>(number) <= most;
  }
  if (!fits) {
    throw ReportError(fmt::format("{}: {} {}, expected a whole number from {} to {}", origin, field,
                                  shown_text(value.dump()), std::numeric_limits<T>::min(), most));
  }
  return value.get<T>();
}

json training_log_json(const std::vector<EpochLog>& log) {
  json rows = json::array();
  for (const auto& row : log) {
    json values = json::object();
    for (const auto& [name, value] : row.values) values[name] = number_or_null(value);
    rows.push_back({{"stage", row.stage}, {"epoch", row.epoch}, {"values", values}});
  }
  return rows;
}

std::string safe_name(std::string text) {
  for (char& c : text) {
    if (c == '/' || c == ' ' || c == '+') c = '_';
  }
  return text;
}
}  // namespace

std::vector<double> RunRecord::session_accuracies() const {
  std::vector<double> accuracies;
  for (const auto& session : sessions) accuracies.push_back(session.accuracy.all);
  return accuracies;
}

std::string run_record_file_name(const RunRecord& record) {
  return fmt::format("{}__{}__seed{}.json", safe_name(record.method), safe_name(record.dataset), record.seed);
}

bool is_selection_name(const std::string& name) {
  return name == "last" || name == "validation" || name == "test-oracle";
}

bool selected_on_test(const RunRecord& record) { return record.selection == "test-oracle"; }

bool is_grid_text(const std::string& text) {
  return !text.empty() && text.find_first_not_of(kGridCharacters) == std::string::npos;
}

std::string grid_cell_name(const std::map<std::string, std::string>& grid) {
  std::string name;
  for (const auto& [key, value] : grid) name += (name.empty() ? "" : "+") + key + "=" + value;
  return name;
}

std::string to_json_text(const RunRecord& record) {
  json sessions = json::array();
  for (const auto& s : record.sessions) {
    sessions.push_back({{"session", s.session},
                        {"seen_classes", s.seen_classes},
                        {"accuracy", s.accuracy.all},
                        {"base_accuracy", s.accuracy.base},
                        {"novel_accuracy", s.accuracy.novel},
                        {"current_accuracy", s.accuracy.current},
                        {"harmonic_mean", s.accuracy.harmonic},
                        {"test_samples", s.accuracy.samples},
                        {"train_seconds", s.train_seconds},
                        {"test_seconds", s.test_seconds},
                        {"context_ratio_mean", number_or_null(s.context_ratio_mean)},
                        {"context_ratio_max", number_or_null(s.context_ratio_max)},
                        {"diagnostics", s.diagnostics},
                        {"training_log", training_log_json(s.training_log)}});
  }
  const json document = {{"schema", kSchemaVersion},
                         {"method", record.method},
                         {"dataset", record.dataset},
                         {"profile", record.profile},
                         {"seed", record.seed},
                         {"threads", record.threads},
                         {"evaluated_on", record.evaluated_on},
                         {"selection", record.selection},
                         {"grid", record.grid},
                         {"parameters", record.parameters},
                         {"protocol_parameters", record.protocol_parameters},
                         {"machine", record.machine},
                         {"version", record.version},
                         {"git_commit", record.git_commit},
                         {"dataset_key", record.dataset_key},
                         {"sessions", sessions},
                         {"total_seconds", record.total_seconds},
                         {"peak_resident_bytes", record.peak_resident_bytes},
                         {"replay", {{"samples", record.replay_samples}, {"bytes", record.replay_bytes}}},
                         {"inference",
                          {{"macs", record.inference.macs},
                           {"flops", 2 * record.inference.macs},
                           {"parameters", record.inference.parameters},
                           {"trainable_parameters", record.inference.trainable_parameters},
                           {"seconds_per_sample", record.inference.seconds_per_sample},
                           {"batch", record.inference.batch}}}};
  return document.dump(2) + "\n";
}

RunRecord run_record_from_json_text(const std::string& text, const std::string& origin) {
  try {
    const json document = json::parse(text);
    if (document.at("schema") != json(kSchemaVersion)) {
      throw ReportError(fmt::format("{}: result schema {}, expected {}", origin, document.at("schema").dump(),
                                    kSchemaVersion));
    }
    RunRecord record;
    record.method = document.at("method").get<std::string>();
    record.dataset = document.at("dataset").get<std::string>();
    // Names go into CSV, Markdown and LaTeX tables and into file names as they are.
    for (const auto& [field, name] : {std::pair("method", record.method), std::pair("dataset", record.dataset)}) {
      if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.+/-") !=
                              std::string::npos) {
        throw ReportError(fmt::format("{}: {} '{}', expected letters, digits, '_', '.', '+', '/' or '-'", origin, field,
                                      shown_text(name)));
      }
    }
    record.profile = document.at("profile").get<std::string>();
    record.seed = whole_number<std::uint64_t>(document.at("seed"), "seed", origin);
    record.threads = whole_number<int>(document.at("threads"), "threads", origin);
    record.evaluated_on = document.value("evaluated_on", std::string("test"));
    if (record.evaluated_on != "test" && record.evaluated_on != "validation") {
      throw ReportError(fmt::format("{}: evaluated_on '{}', expected test or validation", origin,
                                    shown_text(record.evaluated_on)));
    }
    record.selection = document.value("selection", std::string("last"));  // files from before the choice
    if (!is_selection_name(record.selection)) {
      throw ReportError(fmt::format("{}: selection '{}', expected last, validation or test-oracle", origin,
                                    shown_text(record.selection)));
    }
    if (document.contains("grid")) record.grid = document.at("grid").get<std::map<std::string, std::string>>();
    for (const auto& [key, value] : record.grid) {
      // Cell values become CSV fields and folder names as they are.
      for (const std::string& text : {key, value}) {
        if (!is_grid_text(text)) {
          throw ReportError(fmt::format("{}: grid {}={}, expected letters, digits, '_', '.' or '-'", origin,
                                        shown_text(key), shown_text(value)));
        }
      }
    }
    record.parameters = document.at("parameters").get<std::map<std::string, std::string>>();
    if (document.contains("protocol_parameters")) {
      record.protocol_parameters = document.at("protocol_parameters").get<std::map<std::string, std::string>>();
    }
    record.machine = document.at("machine").get<std::map<std::string, std::string>>();
    record.version = document.value("version", std::string());
    record.git_commit = document.at("git_commit").get<std::string>();
    record.dataset_key = document.at("dataset_key").get<std::string>();
    record.total_seconds = document.at("total_seconds").get<double>();
    record.peak_resident_bytes =
        whole_number<std::int64_t>(document.at("peak_resident_bytes"), "peak_resident_bytes", origin);
    // Files written before replay was recorded have none: their methods kept no samples.
    if (document.contains("replay")) {
      record.replay_samples = whole_number<std::int64_t>(document.at("replay").at("samples"), "replay samples", origin);
      record.replay_bytes = whole_number<std::int64_t>(document.at("replay").at("bytes"), "replay bytes", origin);
    }
    if (document.contains("inference")) {
      const json& inference = document.at("inference");
      record.inference.macs = whole_number<std::int64_t>(inference.at("macs"), "inference macs", origin);
      record.inference.parameters =
          whole_number<std::int64_t>(inference.at("parameters"), "inference parameters", origin);
      record.inference.trainable_parameters =
          whole_number<std::int64_t>(inference.at("trainable_parameters"), "inference trainable_parameters", origin);
      record.inference.seconds_per_sample = inference.at("seconds_per_sample").get<double>();
      record.inference.batch = whole_number<std::int64_t>(inference.at("batch"), "inference batch", origin);
    }
    for (const auto& s : document.at("sessions")) {
      SessionRecord session;
      session.session = whole_number<int>(s.at("session"), "session", origin);
      session.seen_classes = whole_number<int>(s.at("seen_classes"), "seen_classes", origin);
      session.accuracy.all = s.at("accuracy").get<double>();
      session.accuracy.base = s.at("base_accuracy").get<double>();
      session.accuracy.novel = s.at("novel_accuracy").get<double>();
      session.accuracy.current = s.at("current_accuracy").get<double>();
      session.accuracy.harmonic = s.at("harmonic_mean").get<double>();
      session.accuracy.samples = whole_number<std::int64_t>(s.at("test_samples"), "test_samples", origin);
      session.train_seconds = s.at("train_seconds").get<double>();
      session.test_seconds = s.at("test_seconds").get<double>();
      session.context_ratio_mean = number_from(s.at("context_ratio_mean"));
      session.context_ratio_max = number_from(s.at("context_ratio_max"));
      if (s.contains("diagnostics")) {
        // NaN (a diverged loss) and infinities were written as null.
        for (const auto& [name, value] : s.at("diagnostics").get<std::map<std::string, json>>()) {
          session.diagnostics[name] = number_from(value);
        }
      }
      if (s.contains("training_log")) {  // files written before the log was kept have none
        for (const auto& row : s.at("training_log")) {
          EpochLog epoch{row.at("stage").get<std::string>(), whole_number<int>(row.at("epoch"), "epoch", origin), {}};
          // Stages become CSV fields of the training log as they are.
          if (epoch.stage.empty() || epoch.stage.find_first_of(",\"\t\r\n") != std::string::npos) {
            throw ReportError(fmt::format("{}: training log stage '{}', expected text without commas, quotes or "
                                          "line breaks", origin, shown_text(epoch.stage)));
          }
          for (const auto& [name, value] : row.at("values").get<std::map<std::string, json>>()) {
            if (name.empty() || name.find_first_of(",\"\t\r\n") != std::string::npos) {
              throw ReportError(fmt::format("{}: training log value '{}', expected a name without commas, quotes or "
                                            "line breaks", origin, shown_text(name)));
            }
            epoch.values[name] = number_from(value);
          }
          session.training_log.push_back(std::move(epoch));
        }
      }
      for (const double accuracy : {session.accuracy.all, session.accuracy.base, session.accuracy.novel,
                                    session.accuracy.current, session.accuracy.harmonic}) {
        if (!(accuracy >= 0 && accuracy <= 100)) {
          throw ReportError(fmt::format("{}: session {} has an accuracy of {}, expected percentages in [0, 100]",
                                        origin, session.session, accuracy));
        }
      }
      record.sessions.push_back(session);
    }
    if (record.sessions.empty()) throw ReportError(fmt::format("{}: no sessions recorded", origin));
    return record;
  } catch (const json::exception& error) {
    throw ReportError(fmt::format("{}: not a valid result file ({})", origin, error.what()));
  }
}

void save_run_record(const fs::path& directory, const RunRecord& record) {
  write_file_atomically(directory / "results" / run_record_file_name(record), to_json_text(record));
}

std::vector<RunRecord> load_run_records(const fs::path& directory) {
  if (!fs::is_directory(directory)) throw ReportError(fmt::format("{}: no such results directory", directory.string()));
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(directory)) {
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<RunRecord> records;
  for (const auto& file : files) {
    records.push_back(run_record_from_json_text(read_text_file(file), file.string()));
    records.back().source = file.string();
  }
  if (records.empty()) throw ReportError(fmt::format("{}: holds no result files (*.json)", directory.string()));
  require_comparable_runs(records);
  return records;
}

}  // namespace fscil
