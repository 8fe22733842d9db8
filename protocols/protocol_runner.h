#pragma once
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "datasets/prepared_dataset.h"
#include "methods/method.h"
#include "metrics/session_outcome.h"
#include "protocols/profiles.h"
#include "protocols/scored_embeddings.h"
#include "protocols/session_schedule.h"

namespace fscil {

// One schedule entry as a method sees it: features and raw signals of `indices` (gathered per
// request, features computed then when the dataset keeps none), and their protocol labels.
SessionData gather_session(const PreparedDataset& dataset, const SessionSchedule& schedule,
                           const std::vector<std::int64_t>& indices, int session);

InputShape input_shape_of(const PreparedDataset& dataset);

// Fills what a method learns about the protocol from its context: classes, input shape and the
// tensor front end. run_sessions does it; a method restored from a checkpoint needs it first.
void describe_protocol(RunContext& context, const PreparedDataset& dataset, const SessionSchedule& schedule);

// Continuing from and writing checkpoints; run_sessions knows no files.
struct SessionCheckpoints {
  // Sessions a checkpoint already holds; the method and the random state stand after the last.
  std::vector<SessionOutcome> finished;
  // Called after every session with the outcomes so far (the run's state is then consistent).
  std::function<void(const std::vector<SessionOutcome>&)> after_session;
};

// A base session trained by another method of the same command (Method::continue_from_base):
// its training time and what it reported while training.
struct InheritedBase {
  double seconds = 0;
  std::map<std::string, double> diagnostics;
  std::vector<EpochLog> training_log;
};

// Receives the embeddings (N x D, embed() of the scored samples of every seen class) and labels
// each session was scored on (--save-embeddings); a run that continues from finished sessions (a
// checkpoint, a shared or cached base) hands the last of them over too, from the state it left.
using ScoredEmbeddingSink =
    std::function<void(int session, const torch::Tensor& embeddings, const std::vector<std::int64_t>& labels)>;

// Drives any method through every session of the schedule and scores it after each on the
// joint `scored` split (test, or validation) of all classes seen so far. The runner never knows
// which method it drives. With `inherited_base` the method already holds a base trained
// elsewhere: session 0 is only scored, and reports that base's training time and diagnostics.
// `reuse`: once_per_run for a method whose entry declares sessions_keep_embedding.
std::vector<SessionOutcome> run_sessions(Method& method, const PreparedDataset& dataset,
                                         const SessionSchedule& schedule, RunContext& context,
                                         EvaluationSplit scored = EvaluationSplit::test,
                                         const std::optional<InheritedBase>& inherited_base = std::nullopt,
                                         const SessionCheckpoints& checkpoints = {},
                                         const ScoredEmbeddingSink& keep_embeddings = {},
                                         EmbeddingReuse reuse = EmbeddingReuse::every_session);

struct InferenceTiming {
  double seconds_per_sample = 0;
  std::int64_t batch = 0;
};
// Inference time per sample (IT) of the method as it stands: the median of `repeats` timed passes
// of one batch of up to `batch` test samples through embed() and classify(), after one untimed
// warm-up pass.
constexpr std::int64_t kTimedInferenceBatch = 128;
InferenceTiming time_inference(Method& method, const PreparedDataset& dataset, const SessionSchedule& schedule,
                               std::int64_t batch = kTimedInferenceBatch, int repeats = kTimedInferenceRepeats);

}  // namespace fscil
