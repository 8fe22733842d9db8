#pragma once
#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

#include "metrics/session_outcome.h"

namespace fscil {

// The one serialiser of session results, used by result files (reports/run_record.cpp) and
// checkpoints (protocols/run_checkpoint.cpp): a JSON array of sessions, a member per field of
// metrics/session_fields.h plus "diagnostics" and "training_log".
//
// JSON has no NaN or infinity. Result files write them as null, which readers such as pandas
// take as missing; checkpoints must give a run back to the bit, a diverged loss's -inf
// included, so they write them as the texts "nan", "inf" and "-inf". Finite values are written
// so that they read back exactly.
enum class NonFinite { null, text };

nlohmann::json sessions_json(const std::vector<SessionOutcome>& sessions, NonFinite non_finite);

// Reads what sessions_json wrote, in either form. A value of the wrong kind (a count that is no
// whole number in range, an accuracy outside [0, 100], a text where a number belongs, a training
// log name that a CSV field cannot hold) is an Error naming `origin` and the field.
std::vector<SessionOutcome> sessions_from_json(const nlohmann::json& sessions, const std::string& origin);

}  // namespace fscil
