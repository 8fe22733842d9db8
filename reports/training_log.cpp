#include "reports/training_log.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace fscil {

std::string render_training_log_csv(const RunRecord& record) {
  std::set<std::string> names;
  for (const auto& session : record.sessions) {
    for (const auto& epoch : session.training_log) {
      for (const auto& [name, value] : epoch.values) names.insert(name);
    }
  }
  std::string out = "session,stage,epoch";
  for (const auto& name : names) out += "," + name;
  out += "\n";
  for (const auto& session : record.sessions) {
    for (const auto& epoch : session.training_log) {
      out += fmt::format("{},{},{}", session.session, epoch.stage, epoch.epoch);
      for (const auto& name : names) {
        const auto found = epoch.values.find(name);
        out += found == epoch.values.end() || std::isnan(found->second) ? std::string(",")
                                                                        : fmt::format(",{:.6g}", found->second);
      }
      out += "\n";
    }
  }
  return out;
}

std::filesystem::path training_log_path(const RunRecord& record, bool several_cells) {
  std::filesystem::path path = "logs";
  if (several_cells) path /= grid_cell_name(record.grid);
  return path / std::filesystem::path(run_record_file_name(record)).replace_extension(".csv");
}

}  // namespace fscil
