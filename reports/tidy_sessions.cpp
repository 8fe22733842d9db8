#include "reports/tidy_sessions.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fscil {

namespace {

std::string number_or_empty(double value) { return std::isnan(value) ? std::string() : fmt::format("{:.4f}", value); }

}  // namespace

std::string render_tidy_sessions_csv(const std::vector<RunRecord>& records) {
  std::vector<std::string> grid_keys;
  for (const auto& record : records) {
    for (const auto& [key, value] : record.grid) {
      if (key != "selection" && std::find(grid_keys.begin(), grid_keys.end(), key) == grid_keys.end()) {
        grid_keys.push_back(key);  // a sweep over selection has its own column
      }
    }
  }
  std::string out = "method,dataset";
  for (const auto& key : grid_keys) out += "," + key;
  out += ",split,selection,seed,session,seen_classes,accuracy,base,novel,current,harmonic_mean,train_seconds,"
         "test_seconds,R\n";
  for (const auto& record : records) {
    for (const auto& session : record.sessions) {
      out += fmt::format("{},{}", record.method, record.dataset);
      for (const auto& key : grid_keys) {
        const auto found = record.grid.find(key);
        out += "," + (found == record.grid.end() ? std::string() : found->second);
      }
      const bool incremental = session.session > 0;
      const auto& accuracy = session.accuracy;
      out += fmt::format(",{},{},{},{},{},{:.4f},{:.4f},{},{},{},{:.3f},{:.3f},{}\n", record.evaluated_on,
                         record.selection, record.seed, session.session, session.seen_classes, accuracy.all,
                         accuracy.base, incremental ? fmt::format("{:.4f}", accuracy.novel) : "",
                         incremental ? fmt::format("{:.4f}", accuracy.current) : "",
                         incremental ? fmt::format("{:.4f}", accuracy.harmonic) : "", session.train_seconds,
                         session.test_seconds, number_or_empty(session.context_ratio_mean));
    }
  }
  return out;
}

}  // namespace fscil
