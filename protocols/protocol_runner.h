#pragma once
#include <vector>

#include "datasets/prepared_dataset.h"
#include "methods/method.h"
#include "protocols/session_outcome.h"
#include "protocols/session_schedule.h"

namespace fscil {

// The tensors of one schedule entry: features, raw signals and protocol labels of `indices`.
SessionData gather_session(const PreparedDataset& dataset, const SessionSchedule& schedule,
                           const std::vector<std::int64_t>& indices, int session);

InputShape input_shape_of(const PreparedDataset& dataset);

// Drives any method through every session of the schedule and scores it after each on the
// joint test set of all classes seen so far. The runner never knows which method it drives.
std::vector<SessionOutcome> run_sessions(Method& method, const PreparedDataset& dataset,
                                         const SessionSchedule& schedule, RunContext& context);

}  // namespace fscil
