#pragma once
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "methods/method.h"
#include "metrics/session_outcome.h"

namespace fscil {

// A run stopped at a session boundary: what it measured so far, the method's state and every
// random state, so that continuing gives exactly the results of a run that never stopped.
struct RunCheckpoint {
  std::string identity;  // which run this is; a checkpoint of another run is refused
  std::vector<SessionOutcome> outcomes;  // the finished sessions
  double elapsed_seconds = 0;
  MethodState method_state;
  std::mt19937_64 generator;
  torch::Tensor torch_random_state;
};

// A stage of a base session (a shared stage, or one in progress) as a checkpoint file holds it: its
// training log, diagnostics and clock as the one session's outcome, `elapsed_seconds` the run's.
RunCheckpoint checkpoint_of_stage(const TrainedStage& stage, std::string identity, double elapsed_seconds);
TrainedStage stage_of_checkpoint(RunCheckpoint checkpoint);

// Written to a temporary name and renamed; the file carries its length and a digest of its
// contents, so a truncated or altered file is recognised.
void save_checkpoint(const std::filesystem::path& path, const RunCheckpoint& checkpoint);
// Throws ProtocolError naming the file when it is corrupt or belongs to another run.
RunCheckpoint load_checkpoint(const std::filesystem::path& path, const std::string& expected_identity);

}  // namespace fscil
