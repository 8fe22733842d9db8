#include "metrics/session_json.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/shown_text.h"
#include "metrics/json_numbers.h"
#include "metrics/session_accuracy.h"
#include "metrics/session_fields.h"

namespace fscil {

namespace {

using nlohmann::json;
using Kind = SessionField::Kind;

json number_json(double value, NonFinite non_finite) {
  if (std::isfinite(value)) return value;
  if (non_finite == NonFinite::null) return nullptr;
  return std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
}

// A number, or what number_json wrote for a value that is not finite.
double number_of(const json& value, const std::string& field, const std::string& origin) {
  if (value.is_number()) return value.get<double>();
  if (value.is_null() || value == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (value == "inf") return std::numeric_limits<double>::infinity();
  if (value == "-inf") return -std::numeric_limits<double>::infinity();
  throw Error(fmt::format("{}: {} {}, expected a number, null, \"nan\", \"inf\" or \"-inf\"", origin, field,
                          shown_text(value.dump())));
}

// Stages and value names become CSV fields of the training log as they are.
void require_csv_text(const std::string& text, const std::string& what, const std::string& expected,
                      const std::string& origin) {
  const bool control = std::any_of(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
  });
  if (text.empty() || control || text.find_first_of(",\"") != std::string::npos) {
    throw Error(fmt::format("{}: training log {} '{}', expected {} without commas, quotes or control characters",
                            origin, what, shown_text(text), expected));
  }
}

json field_json(const SessionField& field, const SessionOutcome& session, NonFinite non_finite) {
  const double value = field.value(session);
  if (field.kind == Kind::count || field.kind == Kind::samples) return static_cast<std::int64_t>(value);
  return number_json(value, non_finite);
}

double field_of(const SessionField& field, const json& value, const std::string& origin) {
  switch (field.kind) {
    case Kind::count: return whole_number<int>(value, field.key, origin, 0);
    case Kind::samples: {
      // Held as a double with the accuracies: past 2^53 it would come back as another number.
      constexpr std::int64_t kMostExact = std::int64_t{1} << 53;
      const std::int64_t samples = whole_number<std::int64_t>(value, field.key, origin, 0);
      if (samples > kMostExact) {
        throw Error(fmt::format("{}: {} {}, expected a whole number from 0 to {}", origin, field.key, samples, kMostExact));
      }
      return static_cast<double>(samples);
    }
    case Kind::percent:
    case Kind::novel_percent:
      if (!value.is_number()) {
        throw Error(fmt::format("{}: {} {}, expected a number", origin, field.key, shown_text(value.dump())));
      }
      return value.get<double>();
    case Kind::seconds:
      if (!value.is_number() || !(value.get<double>() >= 0 && value.get<double>() <= kMostSeconds)) {
        throw Error(fmt::format("{}: {} {}, expected a number of seconds in [0, {:g}]", origin, field.key,
                                shown_text(value.dump()), kMostSeconds));
      }
      return value.get<double>();
    case Kind::ratio: {
      // A dispersion ratio: unknown (NaN), or a ratio of two spreads, never below 0.
      const double ratio = number_of(value, field.key, origin);
      if (ratio < 0) throw Error(fmt::format("{}: {} {}, expected a ratio >= 0 or null", origin, field.key, ratio));
      return ratio;
    }
  }
  return 0;
}

void require_consistent_accuracies(const SessionOutcome& session, const std::string& origin) {
  for (const auto& field : session_fields()) {
    if (field.kind != Kind::percent && field.kind != Kind::novel_percent) continue;
    const double percent = field.value(session);
    if (!(percent >= 0 && percent <= 100)) {
      throw Error(fmt::format("{}: session {} has an accuracy of {}, expected percentages in [0, 100]", origin,
                              session.session, percent));
    }
  }
  // The joint accuracy weighs the base and the novel classes' samples: it lies between theirs.
  const SessionAccuracy& scored = session.accuracy;
  const double low = std::min(scored.base, scored.novel), high = std::max(scored.base, scored.novel);
  if (session.session > 0 && (scored.all < low - 1e-6 || scored.all > high + 1e-6)) {
    throw Error(fmt::format("{}: session {} has an accuracy of {} with base {} and novel {}, expected one between them",
                            origin, session.session, scored.all, scored.base, scored.novel));
  }
  // Session 0 scores the base classes alone: they are its current classes, and no class is novel.
  if (session.session == 0 && (std::abs(scored.base - scored.all) > 1e-6 || std::abs(scored.current - scored.all) > 1e-6 ||
                               scored.novel != 0 || scored.harmonic != 0)) {
    throw Error(fmt::format("{}: session 0 has accuracy {}, base {}, current {}, novel {} and harmonic mean {}, expected "
                            "base and current equal to the accuracy and no novel classes (0)", origin, scored.all,
                            scored.base, scored.current, scored.novel, scored.harmonic));
  }
  // The harmonic mean is of the base and the novel accuracy, as score_session computes it.
  if (const double harmonic = harmonic_mean(scored.base, scored.novel); std::abs(harmonic - scored.harmonic) > 1e-6) {
    throw Error(fmt::format("{}: session {} has a harmonic mean of {} with base {} and novel {}, expected {}", origin,
                            session.session, scored.harmonic, scored.base, scored.novel, harmonic));
  }
}

json training_log_json(const std::vector<EpochLog>& log, NonFinite non_finite) {
  json rows = json::array();
  for (const auto& row : log) {
    json values = json::object();
    for (const auto& [name, value] : row.values) values[name] = number_json(value, non_finite);
    rows.push_back({{"stage", row.stage}, {"epoch", row.epoch}, {"values", values}});
  }
  return rows;
}

std::vector<EpochLog> training_log_of(const json& rows, const std::string& origin, const std::string& path) {
  if (!rows.is_array()) throw Error(fmt::format("{}: field '{}': expected a list", origin, path));
  std::vector<EpochLog> log;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const JsonFields<Error> row(rows[i], origin, fmt::format("{}[{}]", path, i));
    row.require_known_keys({"stage", "epoch", "values"});
    EpochLog epoch{row.text("stage"), row.whole<int>("epoch", 1), {}};
    require_csv_text(epoch.stage, "stage", "text", origin);
    for (const auto& [name, value] : row.object("values").json().items()) {
      require_csv_text(name, "value", "a name", origin);
      epoch.values[name] = number_of(value, "training log " + name, origin);
    }
    // A stage counts its epochs up from 1, each once in a session.
    if (std::any_of(log.begin(), log.end(), [&](const EpochLog& earlier) {
          return earlier.stage == epoch.stage && earlier.epoch == epoch.epoch;
        })) {
      row.fail("epoch", fmt::format("each epoch of stage '{}' once, found epoch {} again", shown_text(epoch.stage),
                                    epoch.epoch));
    }
    log.push_back(std::move(epoch));
  }
  return log;
}

}  // namespace

json sessions_json(const std::vector<SessionOutcome>& sessions, NonFinite non_finite) {
  json rows = json::array();
  for (const auto& session : sessions) {
    json row = json::object();
    for (const auto& field : session_fields()) row[field.key] = field_json(field, session, non_finite);
    json diagnostics = json::object();
    for (const auto& [name, value] : session.diagnostics) diagnostics[name] = number_json(value, non_finite);
    row["diagnostics"] = diagnostics;
    row["training_log"] = training_log_json(session.training_log, non_finite);
    rows.push_back(row);
  }
  return rows;
}

std::vector<SessionOutcome> sessions_from_json(const json& rows, const std::string& origin) {
  if (!rows.is_array()) throw Error(fmt::format("{}: sessions {}, expected a list", origin, shown_text(rows.dump())));
  std::vector<std::string> known = {"diagnostics", "training_log"};
  for (const auto& field : session_fields()) known.push_back(field.key);
  std::vector<SessionOutcome> sessions;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const JsonFields<Error> row(rows[i], origin, fmt::format("sessions[{}]", i));
    row.require_known_keys(known);
    SessionOutcome session;
    for (const auto& field : session_fields()) {
      field.set(session, field_of(field, row.at(field.key, "a number"), origin));
    }
    require_consistent_accuracies(session, origin);
    if (row.has("diagnostics")) {
      for (const auto& [name, value] : row.object("diagnostics").json().items()) {
        session.diagnostics[name] = number_of(value, "diagnostic " + name, origin);
      }
    }
    // Files written before the log was kept have none.
    if (row.has("training_log")) {
      session.training_log =
          training_log_of(row.json().at("training_log"), origin, fmt::format("sessions[{}].training_log", i));
    }
    sessions.push_back(std::move(session));
  }
  return sessions;
}

}  // namespace fscil
