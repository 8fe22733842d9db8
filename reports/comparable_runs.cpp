#include "reports/comparable_runs.h"

#include <fmt/format.h>

#include <map>
#include <set>
#include <tuple>

#include "core/error.h"

namespace fscil {

namespace {

using Parameters = std::map<std::string, std::string>;

std::string first_difference(const Parameters& a, const Parameters& b) {
  std::set<std::string> keys;
  for (const auto& [key, value] : a) keys.insert(key);
  for (const auto& [key, value] : b) keys.insert(key);
  keys.erase("base_training");  // how a base was obtained (trained or shared), not what it is
  const auto value_of = [](const Parameters& parameters, const std::string& key) {
    const auto found = parameters.find(key);
    return found == parameters.end() ? std::string("(not read)") : found->second;
  };
  for (const auto& key : keys) {
    if (value_of(a, key) != value_of(b, key)) {
      return fmt::format("{}={} against {}={}", key, value_of(a, key), key, value_of(b, key));
    }
  }
  return "";
}

std::string name_of(const RunRecord& record) { return record.source.empty() ? "this run" : record.source; }

}  // namespace

std::string incomparability(const RunRecord& a, const RunRecord& b) {
  // Not even as rows of other datasets: a table's precision is one (summarize_runs).
  if (precision_of(a) != precision_of(b)) return fmt::format("made in {} against {}", precision_of(a), precision_of(b));
  if (a.dataset != b.dataset || !same_cell(a.grid, b.grid)) return "";
  if (a.dataset_key != b.dataset_key) return fmt::format("data {} against {}", a.dataset_key, b.dataset_key);
  if (a.profile != b.profile) return fmt::format("profile {} against {}", a.profile, b.profile);
  if (a.evaluated_on != b.evaluated_on) {
    return fmt::format("scored on {} against {}", a.evaluated_on, b.evaluated_on);
  }
  if (a.threads != b.threads) return fmt::format("threads {} against {}", a.threads, b.threads);
  // Files written before protocol parameters were recorded compare on the fields above only.
  if (!a.protocol_parameters.empty() && !b.protocol_parameters.empty()) {
    if (auto difference = first_difference(a.protocol_parameters, b.protocol_parameters); !difference.empty()) {
      return difference;
    }
  }
  if (a.method != b.method) return "";
  return first_difference(a.parameters, b.parameters);
}

void require_comparable_runs(const std::vector<RunRecord>& records) {
  // Comparability is equality of the fields above, so each run is checked against the first run
  // of its dataset and the first of its method there.
  std::map<std::pair<std::string, std::string>, const RunRecord*> first_of_dataset;  // per sweep cell
  std::map<std::tuple<std::string, std::string, std::string>, const RunRecord*> first_of_method;
  std::map<std::tuple<std::string, std::string, std::string, std::uint64_t>, const RunRecord*> run_of_seed;
  const auto refuse = [](const RunRecord& a, const RunRecord& b, const std::string& why) {
    throw ReportError(fmt::format("{} and {}: runs that cannot share a table ({}); keep them in separate folders",
                                  name_of(a), name_of(b), why));
  };
  for (const auto& record : records) {
    const std::string cell = grid_cell_name(record.grid);
    for (const RunRecord* first : {first_of_dataset.emplace(std::pair(record.dataset, cell), &record).first->second,
                                   first_of_method.emplace(std::tuple(record.method, record.dataset, cell), &record)
                                       .first->second}) {
      if (const std::string why = incomparability(*first, record); !why.empty()) refuse(*first, record, why);
    }
    const auto [same_seed, unique] =
        run_of_seed.emplace(std::tuple(record.method, record.dataset, cell, record.seed), &record);
    if (!unique) refuse(*same_seed->second, record, fmt::format("{} seed {} twice", record.method, record.seed));
  }
}

}  // namespace fscil
