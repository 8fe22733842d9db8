#pragma once
#include <torch/torch.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "methods/diverged_training.h"
#include "methods/sample_rows.h"
#include "methods/common/precision.h"
#include "metrics/memory_budget.h"
#include "metrics/model_cost.h"
#include "core/parameter_set.h"
#include "core/progress_reporter.h"
#include "core/error.h"
#include "core/stop_request.h"
#include "metrics/session_outcome.h"

namespace fscil {

// One session's labelled data as a method sees it: no file names, no test labels.
struct SessionData {
  int session = 0;                  // 0 = base
  SampleRows features;              // N x C x n_mels x frames, log-Mel
  SampleRows signals;               // N x C x L, the raw segments (for methods that mix raw signals)
  torch::Tensor labels;             // N, int64 protocol class indices
  // N, the recording each sample was cut from (dataset recording indices); empty where unknown,
  // then every sample counts as its own recording.
  std::vector<std::int64_t> recordings;
  std::vector<std::int64_t> new_classes;      // classes this session introduces
  std::vector<std::int64_t> removed_classes;  // classes this session removes (removal=fciac); no samples then
};

struct InputShape {
  std::int64_t channels = 0, mel_bins = 0, frames = 0, signal_length = 0;
  // One sample's log-Mel map, as cost counting walks it.
  MapShape feature_map() const { return {channels, mel_bins, frames}; }
};

// What a method may use besides its data: seeded randomness, its parameters, the protocol's
// size, the base validation split (never the test split) and a progress reporter.
// Which epoch a method keeps at the points where the reference codes keep their best one
// (RunOptions::selection): the last; the best on base validation; or, as those codes do, the best
// on the test split (test_oracle: numbers inflated by looking at test, for measuring by how much).
enum class EpochSelection { last, validation, test_oracle };

// A method's trained state as named tensors (checkpoints at session boundaries).
using MethodState = std::map<std::string, torch::Tensor>;

// A stage of a base session as it ended (e.g. PITS-SC's pretraining): what a method whose same
// stage it is continues from, exactly as if it had trained the stage itself.
struct TrainedStage {
  MethodState state;                 // the modules and anything else the stage leaves
  std::mt19937_64 generator;         // RunContext::generator after it
  torch::Tensor torch_random_state;  // LibTorch's, after it
  std::vector<EpochLog> training_log;
  std::map<std::string, double> diagnostics;
  double seconds = 0;  // RunContext::session_clock at its end
};

// Where the runner keeps stages that several methods train alike (MethodEntry::shared_stages
// names them and the parameters read only after them): in a command, and in the stage cache.
// The runner names each stage's identity from the run's values, so a method asks by stage name.
class StageStore {
 public:
  virtual ~StageStore() = default;
  // A found stage is only read: a method copies it into its modules, never changes it in place.
  virtual std::optional<TrainedStage> find(const std::string& stage) = 0;
  // `trained` holds copies (put_module's): nothing the method trains afterwards aliases them.
  virtual void store(const std::string& stage, TrainedStage trained) = 0;
};

// Where a run keeps the progress of its base session's long stages, so that a run stopped within
// one (the end of a working session, a Slurm time limit) continues from the last epoch kept,
// exactly as if it had not stopped (methods/common/stage_progress.h says what a stage keeps;
// the runner keeps it beside the run's checkpoint and reads it back only under --resume).
class StageProgressStore {
 public:
  virtual ~StageProgressStore() = default;
  // The progress last kept of `stage` in this run, if any.
  virtual std::optional<TrainedStage> find(const std::string& stage) = 0;
  // Whether it is time to keep progress again: keeping writes the model, so it happens every few
  // minutes, not every epoch.
  virtual bool due() const = 0;
  virtual void store(const std::string& stage, const TrainedStage& progress) = 0;
  // Where the progress of `stage` is kept, for a message about it.
  virtual std::string origin(const std::string& stage) const = 0;
};

struct RunContext {
  std::uint64_t seed = 0;
  std::mt19937_64 generator;
  int total_classes = 0;  // classes of the whole protocol: classifier rows to allocate
  int base_classes = 0;
  InputShape input;
  // The dataset's log-Mel front end: N x C x L raw signals -> N x C x n_mels x frames, for
  // methods that transform raw signals during training (PITS-SC mixes them).
  std::function<torch::Tensor(const torch::Tensor&)> front_end;
  // Encoders recompute their stem's and each stage's activations in backward instead of keeping
  // them (`--set recompute=stages`): less memory, the same numbers.
  bool recompute_activations = false;
  // --max-memory: training passes that would pass it recompute as above (null: no limit).
  std::shared_ptr<MemoryBudget> memory_budget;
  // --precision: what the shared encoder computes in (methods/common/precision.h).
  Precision precision = Precision::fp32;
  const SessionData* validation = nullptr;
  EpochSelection selection = EpochSelection::last;
  // Under test_oracle only: the test samples of every class seen once the session being trained is
  // learned (the base classes in train_base), what the reference codes score their epochs on.
  const SessionData* oracle_test = nullptr;
  // What base-session epochs are scored on: base validation, the base classes' test samples
  // (test_oracle), or null when the last epoch is kept.
  const SessionData* base_selection_data() const {
    if (selection == EpochSelection::validation) return validation;
    if (selection == EpochSelection::test_oracle) return oracle_test;
    return nullptr;
  }
  ProgressReporter* progress = nullptr;
  // Named measurements of the session being trained (base validation accuracy after a stage,
  // loss terms, ...): the runner stores them with that session's results and clears them.
  std::map<std::string, double> diagnostics;
  // Every epoch of the session being trained, stored and cleared like `diagnostics`.
  std::vector<EpochLog> training_log;
  Stopwatch session_clock;  // restarted by the runner when a session begins; the session's train time
  // Stages shared between methods (null: none; a method then trains every stage itself).
  StageStore* stages = nullptr;
  // Where long base stages keep their progress (null: nowhere; a stage then starts from epoch 1).
  StageProgressStore* stage_progress = nullptr;

  // Logs a finished epoch (1-based, of `epochs`) with its mean "loss" and any other values, shows
  // it as progress, and throws StopRequested when a stop was asked (core/stop_request.h). A loss
  // that is not finite throws MethodError naming the stage, the epoch and its values: a diverged
  // training would otherwise score chance, exit 0 and hand its base to the stage cache.
  void log_epoch(const std::string& stage, int epoch, int epochs, std::map<std::string, double> values) {
    if (const auto loss = values.find("loss"); loss != values.end() && !std::isfinite(loss->second)) {
      throw MethodError(diverged_training(stage + " epoch " + std::to_string(epoch) + " of " + std::to_string(epochs),
                                          values));
    }
    values["seconds"] = session_clock.seconds();
    if (progress != nullptr) progress->epoch(stage, epoch, epochs, values["loss"]);
    training_log.push_back({stage, epoch, std::move(values)});
    stop_if_requested();  // SIGTERM: the last session's checkpoint is what a resumed run continues from
  }
};

// Real old samples a method stores for replay; zero for methods that keep none.
struct ReplayFootprint {
  std::int64_t samples = 0;
  std::int64_t bytes = 0;
};

// A FSCIL method. The runner calls train_base once, then learn_session per incremental
// session, and tests after each through embed() and classify(). A method reads every
// hyper-parameter from the ParameterSet in its constructor, so bad values fail before training.
class Method {
 public:
  virtual ~Method() = default;
  virtual void train_base(const SessionData& base, RunContext& context) = 0;
  virtual void learn_session(const SessionData& support, RunContext& context) = 0;
  // A removing session of the class-variable protocol (removal=fciac) instead of learn_session:
  // `classes` leave now and never return. Whatever a method does, the runner drops their rows
  // from every later decision; a method overrides this to forget them in its own state as its
  // paper does. By default its state stays as it is (its replay of them included).
  virtual void forget_classes(const std::vector<std::int64_t>& /*classes*/, RunContext& /*context*/) {}
  // features: N x C x n_mels x frames -> N x D, the embedding the classifier uses (eval mode).
  virtual torch::Tensor embed(const torch::Tensor& features) = 0;
  // N x D embeddings -> N x seen classes.
  virtual torch::Tensor classify(const torch::Tensor& embeddings) = 0;
  virtual ReplayFootprint replay_footprint() const { return {}; }
  // For methods whose registry entries share a base (MethodEntry::shared_base_key): takes over
  // `trained`'s modules as they stood right after its train_base(), and the run's random state as
  // it was then, so the sessions that follow are exactly those of a run that trained its own base. `trained` must not be used afterwards. False when it cannot.
  virtual bool continue_from_base(Method& /*trained*/, RunContext& /*context*/) { return false; }
  // Everything later sessions, tests and costs read, for a checkpoint after a session. On a
  // freshly made method (same parameters) restore_state() with the same context continues exactly
  // where save_state() stood. Throws MethodError when the state does not fit.
  virtual MethodState save_state() const = 0;
  virtual void restore_state(const MethodState& state, RunContext& context) = 0;
  // Inference cost of one sample through embed() and classify() as the model stands now,
  // counted by walking the method's modules (rules in metrics/model_cost.h; a ModuleMethod traces it).
  virtual ModelCost inference_cost(const InputShape& input) const = 0;

  torch::Tensor logits(const torch::Tensor& features) { return classify(embed(features)); }
  // embed() over rows of any number, a batch at a time.
  torch::Tensor embed_rows(const SampleRows& features, std::int64_t batch_size = 512) {
    return map_batches(features, batch_size, [this](const torch::Tensor& batch) { return embed(batch); });
  }
  // Top-1 accuracy in percent on labelled data (the base validation split, for progress notes).
  double accuracy_on(const SessionData& data) {
    return 100.0 * (classify(embed_rows(data.features)).argmax(1) == data.labels).to(torch::kDouble).mean().item<double>();
  }
};

}  // namespace fscil
