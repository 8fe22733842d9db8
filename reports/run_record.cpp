#include "reports/run_record.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <nlohmann/json.hpp>

#include "core/shown_text.h"
#include "core/atomic_file.h"
#include "reports/comparable_runs.h"
#include "core/text_file.h"
#include "core/error.h"
#include "core/json_fields.h"
#include "core/valid_range.h"
#include "core/number_text.h"
#include "metrics/session_json.h"

namespace fscil {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
constexpr int kSchemaVersion = 1;
constexpr const char* kGridCharacters = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-";

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

std::string precision_of(const RunRecord& record) {
  const auto found = record.protocol_parameters.find("precision");
  return found == record.protocol_parameters.end() ? "fp32" : found->second;
}

std::string removal_of(const RunRecord& record) {
  const auto found = record.protocol_parameters.find("removal");
  return found == record.protocol_parameters.end() ? "none" : found->second;
}

std::string run_record_file_name(const RunRecord& record) {
  return fmt::format("{}__{}__seed{}.json", safe_name(record.method), safe_name(record.dataset), record.seed);
}

bool is_selection_name(const std::string& name) {
  return name == "last" || name == "validation" || name == "test-oracle";
}

bool is_precision_name(const std::string& name) { return name == "fp32" || name == "bf16"; }

void require_selection_name(const std::string& name) {
  if (!is_selection_name(name)) {
    throw ReportError(fmt::format("selection '{}': expected last, validation or test-oracle", shown_text(name)));
  }
}

void require_precision_name(const std::string& name) {
  if (!is_precision_name(name)) throw ReportError(fmt::format("precision '{}': expected fp32 or bf16", shown_text(name)));
}

bool selected_on_test(const RunRecord& record) { return record.selection == "test-oracle"; }

std::int64_t run_peak_bytes(const RunRecord& record) {
  return record.peak_resident_bytes - record.resident_at_start_bytes;
}

bool is_grid_text(const std::string& text) {
  return !text.empty() && text.find_first_not_of(kGridCharacters) == std::string::npos;
}

const std::string* grid_value(const GridCell& cell, const std::string& key) {
  for (const auto& [name, value] : cell) {
    if (name == key) return &value;
  }
  return nullptr;
}

GridCell without_key(GridCell cell, const std::string& key) {
  cell.erase(std::remove_if(cell.begin(), cell.end(), [&](const auto& entry) { return entry.first == key; }), cell.end());
  return cell;
}

bool same_cell(const GridCell& a, const GridCell& b) {
  return std::map<std::string, std::string>(a.begin(), a.end()) == std::map<std::string, std::string>(b.begin(), b.end());
}

GridCell in_key_order(const GridCell& cell, const std::vector<std::string>& keys) {
  GridCell ordered;
  for (const std::string& key : keys) {
    if (const std::string* value = grid_value(cell, key)) ordered.emplace_back(key, *value);
  }
  for (const auto& entry : cell) {
    if (std::find(keys.begin(), keys.end(), entry.first) == keys.end()) ordered.push_back(entry);
  }
  return ordered;
}

void add_new_keys(const GridCell& cell, std::vector<std::string>& keys) {
  for (const auto& entry : cell) {
    if (std::find(keys.begin(), keys.end(), entry.first) == keys.end()) keys.push_back(entry.first);
  }
}

std::string grid_cell_name(const GridCell& grid) {
  std::string name;
  for (const auto& [key, value] : grid) name += (name.empty() ? "" : "+") + key + "=" + value;
  return name;
}

std::string label_with_cell(const std::string& label, const GridCell& grid) {
  return grid.empty() ? label : fmt::format("{} [{}]", label, grid_cell_name(grid));
}

namespace {

// A JSON object keeps no order: the cell's key order goes beside it.
std::vector<std::string> grid_keys_of(const GridCell& cell) {
  std::vector<std::string> keys;
  for (const auto& entry : cell) keys.push_back(entry.first);
  return keys;
}

}  // namespace

std::string to_json_text(const RunRecord& record) {
  json document = {{"schema", kSchemaVersion},
                   {"method", record.method},
                   {"dataset", record.dataset},
                   {"profile", record.profile},
                   {"seed", record.seed},
                   {"threads", record.threads},
                   {"evaluated_on", record.evaluated_on},
                   {"selection", record.selection},
                   {"grid", std::map<std::string, std::string>(record.grid.begin(), record.grid.end())},
                   {"parameters", record.parameters},
                   {"protocol_parameters", record.protocol_parameters},
                   {"machine", record.machine},
                   {"version", record.version},
                   {"git_commit", record.git_commit},
                   {"dataset_key", record.dataset_key},
                   {"sessions", sessions_json(record.sessions, NonFinite::null)},
                   {"total_seconds", record.total_seconds},
                   {"peak_resident_bytes", record.peak_resident_bytes},
                   {"resident_at_start_bytes", record.resident_at_start_bytes},
                   {"replay", {{"samples", record.replay_samples}, {"bytes", record.replay_bytes}}},
                   {"inference",
                    {{"macs", record.inference.macs},
                     {"flops", 2 * record.inference.macs},
                     {"parameters", record.inference.parameters},
                     {"trainable_parameters", record.inference.trainable_parameters},
                     {"seconds_per_sample", record.inference.seconds_per_sample},
                     {"batch", record.inference.batch}}}};
  if (!record.grid.empty()) document["grid_keys"] = grid_keys_of(record.grid);
  if (!record.method_note.empty()) document["method_note"] = record.method_note;
  return document.dump(2) + "\n";
}

namespace {

// Fields that are each well formed can still contradict one another: the run the file claims
// to be must be one the program could have written.
void check_as_a_whole(const RunRecord& record, const std::string& origin) {
  // Not bounded above: --threads 0 records every hardware thread of the machine, however many.
  if (record.threads < 1) throw ReportError(fmt::format("{}: threads {}, expected 1 or more", origin, record.threads));
  const auto protocol_value = [&](const std::string& key) -> std::optional<std::int64_t> {
    for (const auto* values : {&record.protocol_parameters, &record.parameters}) {
      if (const auto found = values->find(key); found != values->end()) return parse_number<std::int64_t>(found->second);
    }
    return std::nullopt;
  };
  // The session plan's counts are whole numbers wherever they are recorded ("shot": "five" is no plan).
  for (const char* key : {"base_classes", "sessions", "shot", "way"}) {
    for (const auto* values : {&record.protocol_parameters, &record.parameters}) {
      const auto found = values->find(key);
      if (found == values->end()) continue;
      const auto count = parse_number<std::int64_t>(found->second);
      if (!count || *count < 1) {
        throw ReportError(fmt::format("{}: field '{}.{}': expected a whole number of at least 1, found '{}'", origin,
                                      values == &record.parameters ? "parameters" : "protocol_parameters", key,
                                      shown_text(found->second)));
      }
    }
  }
  // A value recorded in both maps is one value the run used.
  for (const auto& [key, value] : record.protocol_parameters) {
    if (const auto found = record.parameters.find(key); found != record.parameters.end() && found->second != value) {
      throw ReportError(fmt::format("{}: field 'parameters.{}' is '{}' but 'protocol_parameters.{}' is '{}', expected "
                                    "the one value the run used", origin, shown_text(key), shown_text(found->second),
                                    shown_text(key), shown_text(value)));
    }
  }
  // No run reads a number that is not finite (ParameterSet's numeric readers refuse one, and the few
  // values read as text are names: split_mode, a front-end preset).
  for (const auto* values : {&record.protocol_parameters, &record.parameters}) {
    for (const auto& [key, value] : *values) {
      const auto number = parse_number<double>(value);
      if (number && !std::isfinite(*number)) {
        throw ReportError(fmt::format("{}: field '{}.{}': '{}', expected a finite number", origin,
                                      values == &record.parameters ? "parameters" : "protocol_parameters",
                                      shown_text(key), shown_text(value)));
      }
    }
  }
  // What the runner writes (methods/common/precision.h, protocols/session_plan.cpp's removal).
  if (const std::string precision = precision_of(record); !is_precision_name(precision)) {
    throw ReportError(fmt::format("{}: field 'protocol_parameters.precision': '{}', expected fp32 or bf16", origin,
                                  shown_text(precision)));
  }
  if (const std::string removal = removal_of(record); removal != "none" && removal != "fciac") {
    throw ReportError(fmt::format("{}: field 'protocol_parameters.removal': '{}', expected none or fciac", origin,
                                  shown_text(removal)));
  }
  const auto sessions = protocol_value("sessions");
  // A result file is written once its run's last session has ended.
  if (sessions && static_cast<std::int64_t>(record.sessions.size()) != *sessions) {
    throw ReportError(fmt::format("{}: {} sessions recorded, expected the protocol's {}", origin,
                                  record.sessions.size(), *sessions));
  }
  const bool removes_classes = removal_of(record) != "none";
  const auto base_classes = protocol_value("base_classes"), way = protocol_value("way");
  for (std::size_t i = 0; i < record.sessions.size(); ++i) {
    const SessionOutcome& session = record.sessions[i];
    if (session.session != static_cast<int>(i)) {
      throw ReportError(fmt::format("{}: session {} recorded in place {}, expected sessions 0, 1, 2, ... in order",
                                    origin, session.session, i));
    }
    // Each session adds classes, unless the protocol also removes them (removal=fciac).
    const int earlier = i == 0 ? 0 : record.sessions[i - 1].seen_classes;
    if (session.seen_classes <= earlier && !(removes_classes && i > 0 && session.seen_classes > 0)) {
      throw ReportError(fmt::format("{}: session {} has {} seen classes, expected more than {}", origin, i,
                                    session.seen_classes, earlier));
    }
    // Sessions that only add classes: the base classes, then `way` more each.
    if (!removes_classes && base_classes && way && session.seen_classes != *base_classes + *way * static_cast<std::int64_t>(i)) {
      throw ReportError(fmt::format("{}: session {} has {} seen classes, expected the protocol's {} ({} base, {} way)",
                                    origin, i, session.seen_classes, *base_classes + *way * static_cast<std::int64_t>(i),
                                    *base_classes, *way));
    }
    if (session.accuracy.samples < 1) {
      throw ReportError(fmt::format("{}: session {} was tested on {} samples, expected at least 1", origin, i,
                                    session.accuracy.samples));
    }
  }
  // A sweep cell's value is the value its run used.
  for (const auto& [key, value] : record.grid) {
    const std::string used = key == "selection" ? record.selection
                             : record.parameters.count(key) > 0 ? record.parameters.at(key)
                             : record.protocol_parameters.count(key) > 0 ? record.protocol_parameters.at(key)
                                                                          : value;
    if (used != value) {
      throw ReportError(fmt::format("{}: grid cell {}={} but the run used {}={}", origin, key, value, key, used));
    }
  }
}

}  // namespace

RunRecord run_record_from_json_text(const std::string& text, const std::string& origin) {
  using Fields = JsonFields<ReportError>;
  const json document = parse_json_object<ReportError>(text, origin);
  const Fields top(document, origin);
  // Every field to_json_text writes; a file with more was not written by fscil-bench.
  top.require_known_keys({"schema", "method", "dataset", "profile", "seed", "threads", "evaluated_on", "selection",
                          "grid", "grid_keys", "parameters", "protocol_parameters", "machine", "version", "git_commit",
                          "dataset_key", "sessions", "total_seconds", "peak_resident_bytes", "resident_at_start_bytes", "replay",
                          "inference", "method_note"});
  if (top.whole<int>("schema") != kSchemaVersion) top.fail("schema", fmt::format("{}", kSchemaVersion));
  try {
    RunRecord record;
    record.method = top.text("method");
    record.dataset = top.text("dataset");
    // Names go into CSV, Markdown and LaTeX tables and into file names as they are.
    for (const auto& [field, name] : {std::pair("method", record.method), std::pair("dataset", record.dataset)}) {
      if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.+/-") !=
                              std::string::npos) {
        top.fail(field, fmt::format("letters, digits, '_', '.', '+', '/' or '-', found '{}'", shown_text(name)));
      }
    }
    record.profile = top.text("profile");
    record.seed = top.whole<std::uint64_t>("seed");
    record.threads = top.whole<int>("threads");
    record.evaluated_on = top.text("evaluated_on", "test");
    if (record.evaluated_on != "test" && record.evaluated_on != "validation") {
      top.fail("evaluated_on", fmt::format("test or validation, found '{}'", shown_text(record.evaluated_on)));
    }
    record.selection = top.text("selection", "last");  // files from before the choice
    if (!is_selection_name(record.selection)) {
      top.fail("selection", fmt::format("last, validation or test-oracle, found '{}'", shown_text(record.selection)));
    }
    if (top.has("grid")) {
      const std::map<std::string, std::string> assignments = top.texts("grid");
      record.grid.assign(assignments.begin(), assignments.end());
    }
    for (const auto& [key, value] : record.grid) {
      // Cell values become CSV fields and folder names as they are.
      for (const std::string& text : {key, value}) {
        if (!is_grid_text(text)) {
          top.fail("grid",
                   fmt::format("letters, digits, '_', '.' or '-', found {}={}", shown_text(key), shown_text(value)));
        }
      }
    }
    if (top.has("grid_keys")) {  // files written before it are in alphabetical order
      std::vector<std::string> keys = top.names("grid_keys");
      std::vector<std::string> sorted = keys;
      std::sort(sorted.begin(), sorted.end());
      if (sorted != grid_keys_of(record.grid)) {
        top.fail("grid_keys", fmt::format("the keys of grid ({}), found {}", fmt::join(grid_keys_of(record.grid), ", "),
                                          shown_text(fmt::format("{}", fmt::join(keys, ", ")))));
      }
      record.grid = in_key_order(record.grid, keys);
    }
    record.parameters = top.texts("parameters");
    if (top.has("protocol_parameters")) record.protocol_parameters = top.texts("protocol_parameters");
    record.machine = top.texts("machine");
    record.version = top.text("version", "");
    record.git_commit = top.text("git_commit");
    record.dataset_key = top.text("dataset_key");
    record.method_note = top.text("method_note", "");
    if (!is_one_line(record.method_note)) {
      top.fail("method_note", "one line of text without control characters, found " + shown_text(record.method_note));
    }
    record.total_seconds = top.number("total_seconds", ValidRange::between(0, kMostSeconds));
    record.peak_resident_bytes = top.whole<std::int64_t>("peak_resident_bytes", 0);
    if (top.has("resident_at_start_bytes")) {
      record.resident_at_start_bytes = top.whole<std::int64_t>("resident_at_start_bytes", 0);
      if (record.resident_at_start_bytes > record.peak_resident_bytes) {
        top.fail("resident_at_start_bytes",
                 fmt::format("at most peak_resident_bytes ({}), found {}", record.peak_resident_bytes,
                             record.resident_at_start_bytes));
      }
    }
    // Files written before replay was recorded have none: their methods kept no samples.
    if (top.has("replay")) {
      const Fields replay = top.object("replay");
      replay.require_known_keys({"samples", "bytes"});
      record.replay_samples = replay.whole<std::int64_t>("samples", 0);
      record.replay_bytes = replay.whole<std::int64_t>("bytes", 0);
    }
    if (top.has("inference")) {
      const Fields inference = top.object("inference");
      inference.require_known_keys(
          {"macs", "flops", "parameters", "trainable_parameters", "seconds_per_sample", "batch"});
      // Written again as flops = 2 x macs, which must fit the same 64 bits.
      record.inference.macs = inference.integer("macs", ValidRange::between(0, 4e18));
      record.inference.parameters = inference.whole<std::int64_t>("parameters", 0);
      record.inference.trainable_parameters = inference.whole<std::int64_t>("trainable_parameters", 0);
      record.inference.seconds_per_sample =
          inference.number("seconds_per_sample", ValidRange::between(0, kMostSeconds));
      record.inference.batch = inference.whole<std::int64_t>("batch", 0);
    }
    record.sessions = sessions_from_json(top.at("sessions", "a list of sessions"), origin);
    if (record.sessions.empty()) throw ReportError(fmt::format("{}: no sessions recorded", origin));
    check_as_a_whole(record, origin);
    return record;
  } catch (const json::exception& error) {  // the sessions' readers in metrics/
    throw ReportError(fmt::format("{}: not a valid result file ({})", origin, json_error_text(error)));
  } catch (const ReportError&) {
    throw;
  } catch (const Error& error) {  // from the readers in metrics/, which name the file and field
    throw ReportError(error.what());
  }
}

void save_run_record(const fs::path& directory, const RunRecord& record) {
  write_file_atomically(directory / "results" / run_record_file_name(record), to_json_text(record));
}

RunRecord read_run_record(const fs::path& file) {
  RunRecord record = run_record_from_json_text(read_text_file(file, kMaxResultFileBytes, "a result file"), file.string());
  record.source = file.string();
  return record;
}

std::vector<RunRecord> load_run_records(const fs::path& directory) {
  if (const std::string why = why_not_a_folder(directory); !why.empty()) {
    throw ReportError(fmt::format("{}: {} (expected the --out folder of a run)", directory.string(), why));
  }
  // An --out folder (one with results/ or cells/) keeps its result files in folders named results,
  // beside which a config file, a user's notes or an old copy may lie; any other folder is one of
  // result files, read whole.
  const bool out_folder = fs::is_directory(directory / "results") || fs::is_directory(directory / "cells");
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(directory)) {
    if (entry.path().extension() != ".json") continue;
    if (out_folder && entry.path().parent_path().filename() != "results") continue;
    // A folder or a FIFO named like a result is named as what it is, not passed over.
    if (const std::string why = why_not_a_regular_file(entry.path()); !why.empty()) {
      throw ReportError(fmt::format("{}: {}, expected a result file", entry.path().string(), why));
    }
    files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<RunRecord> records;
  for (const auto& file : files) {
    never_replace(file);
    records.push_back(read_run_record(file));
  }
  if (records.empty()) throw ReportError(fmt::format("{}: holds no result files (*.json)", directory.string()));
  // One key order for every cell, so that a cell is one row (files written before the order was
  // kept are alphabetical).
  std::vector<std::string> keys;
  for (const auto& record : records) add_new_keys(record.grid, keys);
  for (auto& record : records) record.grid = in_key_order(record.grid, keys);
  require_comparable_runs(records);
  return records;
}

}  // namespace fscil
