#include "reports/tidy_sessions.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "metrics/session_fields.h"

namespace fscil {

namespace {

using Kind = SessionField::Kind;

std::string cell(const SessionField& field, const SessionOutcome& session) {
  const double value = field.value(session);
  switch (field.kind) {
    case Kind::count:
    case Kind::samples: return fmt::format("{}", static_cast<std::int64_t>(value));
    case Kind::percent: return fmt::format("{:.4f}", value);
    case Kind::novel_percent: return session.session > 0 ? fmt::format("{:.4f}", value) : "";
    case Kind::seconds: return fmt::format("{:.3f}", value);
    case Kind::ratio: return std::isnan(value) ? "" : fmt::format("{:.4f}", value);
  }
  return "";
}

}  // namespace

std::string render_tidy_sessions_csv(const std::vector<RunRecord>& records) {
  std::vector<std::string> grid_keys;
  for (const auto& record : records) add_new_keys(without_key(record.grid, "selection"), grid_keys);  // its own column
  std::string out = "method,dataset";
  for (const auto& key : grid_keys) out += "," + key;
  out += ",split,selection,precision,seed";
  for (const auto& field : session_fields()) {
    if (field.column) out += fmt::format(",{}", field.column);
  }
  out += "\n";
  for (const auto& record : records) {
    for (const auto& session : record.sessions) {
      out += fmt::format("{},{}", record.method, record.dataset);
      for (const auto& key : grid_keys) {
        const std::string* value = grid_value(record.grid, key);
        out += "," + (value == nullptr ? std::string() : *value);
      }
      out += fmt::format(",{},{},{},{}", record.evaluated_on, record.selection, precision_of(record), record.seed);
      for (const auto& field : session_fields()) {
        if (field.column) out += "," + cell(field, session);
      }
      out += "\n";
    }
  }
  return out;
}

}  // namespace fscil
