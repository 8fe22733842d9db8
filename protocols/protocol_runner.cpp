#include "protocols/protocol_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "datasets/log_mel_extractor.h"
#include "metrics/context_dispersion.h"
#include "metrics/convergence.h"
#include "metrics/resource_usage.h"
#include "protocols/scored_embeddings.h"

namespace fscil {

namespace {

// Whether `label` is among `removed`, in increasing order as SessionPlan::removed_by gives them.
bool is_among(const std::vector<int>& removed, std::int64_t label) {
  return std::binary_search(removed.begin(), removed.end(), static_cast<int>(label));
}

// Whether the base training had finished (metrics/convergence.h): the largest rise of a judged
// stage as the `base_validation_rise` diagnostic, and the verdict as a progress note.
void note_training_verdict(SessionOutcome& outcome, ProgressReporter* progress) {
  const std::vector<StageConvergence> stages = judge_stages(outcome.training_log);
  if (stages.empty()) return;
  std::optional<double> rise;
  std::vector<std::string> described;
  for (const auto& stage : stages) {
    if (stage.verdict != TrainingVerdict::unjudged) rise = std::max(rise.value_or(stage.rise), stage.rise);
    described.push_back(describe_stage(stage));
  }
  if (rise) outcome.diagnostics["base_validation_rise"] = *rise;
  if (progress != nullptr) {
    progress->note(fmt::format("training {} ({})", verdict_name(run_verdict(stages)), fmt::join(described, "; ")));
  }
}

torch::Tensor tensor_of(const FloatArray& array) {
  // from_blob wraps the dataset's memory without copying; callers index_select an owned copy.
  return torch::from_blob(const_cast<float*>(array.values.data()), array.shape, torch::kFloat);
}

// With channel_repeat > 1 (mono stored once) the channel axis becomes an expanded view, so the
// repeat costs no memory until a method computes on it.
torch::Tensor repeat_channels(const torch::Tensor& rows, int channel_repeat) {
  if (channel_repeat == 1) return rows;
  std::vector<std::int64_t> shape = rows.sizes().vec();
  shape[1] *= channel_repeat;
  return rows.expand(shape);
}

using FrontEnd = std::function<torch::Tensor(const torch::Tensor&)>;

// The dataset's front end on tensors: ... x L raw signals -> ... x n_mels x frames.
FrontEnd tensor_front_end(const LogMelSettings& settings) {
  auto extractor = std::make_shared<const LogMelExtractor>(settings);
  return [extractor](const torch::Tensor& signals) {
    const torch::Tensor input = signals.to(torch::kFloat).contiguous();
    const std::int64_t length = input.size(-1);
    std::vector<std::int64_t> shape(input.sizes().begin(), input.sizes().end() - 1);
    shape.push_back(extractor->settings().n_mels);
    shape.push_back(extractor->frames(length));
    torch::Tensor features = torch::empty(shape, torch::kFloat);
    extractor->extract_rows(input.data_ptr<float>(), input.numel() / length, length, features.data_ptr<float>(),
                            torch::get_num_threads());
    return features;
  };
}

// Rows of a dataset array (signals, or features kept in memory) at `segments`.
SampleRows stored_rows(const FloatArray& array, const std::vector<std::int64_t>& segments, int channel_repeat) {
  const torch::Tensor positions = torch::tensor(segments, torch::kLong);
  const torch::Tensor all = tensor_of(array);
  return SampleRows(positions.size(0), [positions, all, channel_repeat](const torch::Tensor& index) {
    return repeat_channels(all.index_select(0, positions.index_select(0, index)), channel_repeat);
  });
}

SampleRows signal_rows(const PreparedDataset& dataset, const std::vector<std::int64_t>& segments) {
  return stored_rows(dataset.segments.signals, segments, dataset.description.channel_repeat);
}

// Features as kept in memory, or computed from the signals per request.
SampleRows feature_rows(const PreparedDataset& dataset, const std::vector<std::int64_t>& segments) {
  const int repeat = dataset.description.channel_repeat;
  if (!dataset.features_on_demand()) return stored_rows(dataset.features, segments, repeat);
  const torch::Tensor positions = torch::tensor(segments, torch::kLong);
  const torch::Tensor signals = tensor_of(dataset.segments.signals);
  const FrontEnd front_end = tensor_front_end(dataset.description.front_end);
  return SampleRows(positions.size(0), [positions, signals, repeat, front_end](const torch::Tensor& index) {
    return repeat_channels(front_end(signals.index_select(0, positions.index_select(0, index))), repeat);
  });
}

// One id per distinct acquisition context (the tuple of a recording's known context values,
// without the held-out marker), per segment; empty when the dataset knows no contexts.
std::vector<int> context_ids(const SegmentSet& segments) {
  const std::size_t columns = segments.context_names.size();
  std::vector<std::size_t> used;
  for (std::size_t k = 0; k < columns; ++k) {
    if (segments.context_names[k] != "held_out") used.push_back(k);
  }
  if (used.empty()) return {};
  std::map<std::vector<double>, int> ids;
  std::vector<int> per_recording;
  for (std::size_t r = 0; r < segments.recording_ids.size(); ++r) {
    std::vector<double> key;
    for (std::size_t k : used) key.push_back(segments.context_values[r * columns + k]);
    if (std::any_of(key.begin(), key.end(), [](double v) { return std::isnan(v); })) return {};
    per_recording.push_back(ids.emplace(key, static_cast<int>(ids.size())).first->second);
  }
  std::vector<int> per_segment;
  for (int recording : segments.recording_index) per_segment.push_back(per_recording[recording]);
  return per_segment;
}

template <typename T>
std::vector<T> to_vector(const torch::Tensor& tensor) {
  const torch::Tensor contiguous = tensor.contiguous();
  return std::vector<T>(contiguous.data_ptr<T>(), contiguous.data_ptr<T>() + contiguous.numel());
}

}  // namespace

InputShape input_shape_of(const PreparedDataset& dataset) {
  const auto& signals = dataset.segments.signals.shape;
  const LogMelSettings& front_end = dataset.description.front_end;
  return {signals[1] * dataset.description.channel_repeat, front_end.n_mels, front_end.frames(signals[2]), signals[2]};
}

SessionData gather_session(const PreparedDataset& dataset, const SessionSchedule& schedule,
                           const std::vector<std::int64_t>& indices, int session) {
  SessionData data;
  data.session = session;
  data.features = feature_rows(dataset, indices);
  data.signals = signal_rows(dataset, indices);
  data.labels = torch::tensor(schedule.labels_of(indices), torch::kLong);
  for (std::int64_t index : indices) data.recordings.push_back(dataset.segments.recording_index[index]);
  const SessionPlan& plan = schedule.plan;
  for (int c = plan.first_class_of(session); c < plan.seen_after(session); ++c) data.new_classes.push_back(c);
  for (int c : plan.removed_in(session)) data.removed_classes.push_back(c);
  return data;
}

void describe_protocol(RunContext& context, const PreparedDataset& dataset, const SessionSchedule& schedule) {
  context.total_classes = schedule.plan.total_classes();
  context.base_classes = schedule.plan.base_classes;
  context.input = input_shape_of(dataset);
  context.front_end = tensor_front_end(dataset.description.front_end);
}

std::vector<SessionOutcome> run_sessions(Method& method, const PreparedDataset& dataset,
                                         const SessionSchedule& schedule, RunContext& context, EvaluationSplit scored,
                                         const std::optional<InheritedBase>& inherited_base,
                                         const SessionCheckpoints& checkpoints,
                                         const ScoredEmbeddingSink& keep_embeddings, EmbeddingReuse reuse) {
  const SessionPlan& plan = schedule.plan;
  const SessionData validation = gather_session(dataset, schedule, schedule.validation, 0);
  const std::vector<std::int64_t>& scored_segments = schedule.scored_segments(scored);
  const std::vector<std::int64_t> scored_labels = schedule.labels_of(scored_segments);
  context.validation = &validation;
  describe_protocol(context, dataset, schedule);

  const std::vector<int> segment_contexts = context_ids(dataset.segments);
  std::vector<int> first_session;
  for (std::int64_t label : scored_labels) first_session.push_back(plan.session_of_class(label));
  ScoredEmbeddings scored_embeddings(feature_rows(dataset, scored_segments), std::move(first_session), reuse);
  // The scored samples of the classes present after `session` (a removed class's are not scored,
  // and its row takes part in no decision): their positions in `scored_segments`, their embeddings.
  const auto scored_after = [&](int session) {
    const std::vector<int> removed = plan.removed_by(session);  // in increasing order
    std::vector<std::int64_t> seen = scored_embeddings.positions_seen_by(session);
    torch::Tensor seen_embeddings = scored_embeddings.embeddings_after(method, session);
    if (!removed.empty()) {
      std::vector<std::int64_t> kept, kept_rows;
      for (std::size_t i = 0; i < seen.size(); ++i) {
        if (is_among(removed, scored_labels[seen[i]])) continue;
        kept.push_back(seen[i]);
        kept_rows.push_back(static_cast<std::int64_t>(i));
      }
      seen = std::move(kept);
      seen_embeddings = seen_embeddings.index_select(0, torch::tensor(kept_rows, torch::kLong));
    }
    return std::make_pair(std::move(seen), seen_embeddings);
  };
  const auto labels_at = [&](const std::vector<std::int64_t>& positions) {
    std::vector<std::int64_t> labels;
    for (std::int64_t position : positions) labels.push_back(scored_labels[static_cast<std::size_t>(position)]);
    return labels;
  };
  std::vector<SessionOutcome> outcomes = checkpoints.finished;
  if (!outcomes.empty()) {
    const int last_finished = static_cast<int>(outcomes.size()) - 1;
    scored_embeddings.keep_up_to(method, last_finished);
    // The method holds the state that session left (a checkpoint, a shared or cached base): its
    // embeddings are what scoring it gave, so they are kept as if it had run here.
    if (keep_embeddings) {
      const auto [seen, seen_embeddings] = scored_after(last_finished);
      keep_embeddings(last_finished, seen_embeddings, labels_at(seen));
    }
  }
  for (int session = static_cast<int>(outcomes.size()); session < plan.sessions; ++session) {
    const SessionData data = gather_session(dataset, schedule, schedule.train[session], session);
    const bool removing = session > 0 && !plan.adds_classes(session);
    const std::vector<int> removed = plan.removed_by(session);  // in increasing order
    if (context.progress != nullptr && removing) {
      context.progress->stage(fmt::format("session {}/{}: removes classes {}", session, plan.sessions - 1,
                                          fmt::join(data.removed_classes, ", ")));
    } else if (context.progress != nullptr) {
      context.progress->stage(fmt::format("session {}/{}: {} classes, {} training samples", session, plan.sessions - 1,
                                          data.new_classes.size(), data.labels.size(0)));
    }
    std::optional<SessionData> oracle_test;
    if (context.selection == EpochSelection::test_oracle) {
      std::vector<std::int64_t> seen_test;
      for (std::int64_t segment : schedule.scored_segments(EvaluationSplit::test)) {
        if (schedule.label[segment] < plan.seen_after(session) && !is_among(removed, schedule.label[segment])) {
          seen_test.push_back(segment);
        }
      }
      oracle_test = gather_session(dataset, schedule, seen_test, session);
    }
    context.oracle_test = oracle_test ? &*oracle_test : nullptr;
    SessionOutcome outcome;
    outcome.session = session;
    outcome.seen_classes = plan.present_after(session);  // the classes scored
    context.diagnostics.clear();
    context.training_log.clear();
    context.session_clock = Stopwatch();
    if (removing) {
      method.forget_classes(data.removed_classes, context);
    } else if (session > 0) {
      method.learn_session(data, context);
    } else if (!inherited_base) {
      method.train_base(data, context);
    }
    if (context.memory_budget) {
      context.diagnostics["max_memory_recomputed_passes"] = static_cast<double>(context.memory_budget->take_exceeding_passes());
    }
    context.oracle_test = nullptr;
    // The session clock: a stage the method took over from another run (RunContext::stages) counts.
    outcome.train_seconds = session == 0 && inherited_base ? inherited_base->seconds : context.session_clock.seconds();
    outcome.diagnostics = session == 0 && inherited_base ? inherited_base->diagnostics : context.diagnostics;
    outcome.training_log = session == 0 && inherited_base ? inherited_base->training_log : context.training_log;
    if (session == 0) note_training_verdict(outcome, context.progress);

    Stopwatch test_clock;
    auto [seen, seen_embeddings] = scored_after(session);
    const torch::Tensor removed_rows = torch::tensor(std::vector<std::int64_t>(removed.begin(), removed.end()), torch::kLong);
    std::vector<std::int64_t> seen_segments;
    for (std::int64_t position : seen) seen_segments.push_back(scored_segments[position]);
    std::vector<torch::Tensor> predictions, embeddings;
    for (std::int64_t first = 0; first < seen_embeddings.size(0); first += ScoredEmbeddings::kBatch) {
      const torch::Tensor embedding = seen_embeddings.narrow(0, first, std::min(ScoredEmbeddings::kBatch, seen_embeddings.size(0) - first));
      torch::Tensor logits = method.classify(embedding);
      if (!removed.empty()) logits = logits.index_fill(1, removed_rows, -std::numeric_limits<float>::infinity());
      predictions.push_back(logits.argmax(1));
      if (!segment_contexts.empty()) {
        embeddings.push_back(torch::nn::functional::normalize(embedding, torch::nn::functional::NormalizeFuncOptions().dim(1)));
      }
    }
    const std::vector<std::int64_t> labels = labels_at(seen);
    if (keep_embeddings) keep_embeddings(session, seen_embeddings, labels);
    const auto predicted = to_vector<std::int64_t>(torch::cat(predictions));
    outcome.accuracy = score_session(labels, predicted, plan.base_classes, plan.first_class_of(session), plan.seen_after(session));
    const CrossGroupErrors crossed = cross_group_errors(labels, predicted, plan.base_classes);
    outcome.diagnostics["scored_base_as_novel"] = crossed.base_as_novel;
    if (session > 0) outcome.diagnostics["scored_novel_as_base"] = crossed.novel_as_base;
    if (!segment_contexts.empty()) {
      // Measured on unit-length embeddings: the cosine classifier only sees directions.
      const torch::Tensor all = torch::cat(embeddings);
      std::vector<int> contexts;
      for (std::int64_t segment : seen_segments) contexts.push_back(segment_contexts[segment]);
      const ContextDispersion dispersion =
          measure_context_dispersion(to_vector<float>(all), all.size(1), labels, contexts);
      outcome.context_ratio_mean = dispersion.mean;
      outcome.context_ratio_max = dispersion.max;
    }
    outcome.test_seconds = test_clock.seconds();
    if (context.progress != nullptr) {
      // Session 0 has no novel classes: no novel accuracy to print.
      const std::string novel = session == 0 ? "" : fmt::format(", novel {:.2f}%", outcome.accuracy.novel);
      std::string line = fmt::format("session {} accuracy {:.2f}% (base {:.2f}%{}) on {} {} samples", session,
                                     outcome.accuracy.all, outcome.accuracy.base, novel, outcome.accuracy.samples,
                                     to_string(scored));
      if (!segment_contexts.empty()) {
        line += fmt::format(", context ratio R mean {:.3f} max {:.3f}", outcome.context_ratio_mean, outcome.context_ratio_max);
      }
      context.progress->note(line);
    }
    outcomes.push_back(outcome);
    if (checkpoints.after_session) checkpoints.after_session(outcomes);
    stop_if_requested();
  }
  context.validation = nullptr;
  return outcomes;
}

InferenceTiming time_inference(Method& method, const PreparedDataset& dataset, const SessionSchedule& schedule,
                               std::int64_t batch, int repeats) {
  const std::vector<std::int64_t> first(schedule.test.begin(),
                                        schedule.test.begin() + std::min<std::int64_t>(batch, schedule.test.size()));
  const torch::Tensor features = feature_rows(dataset, first).all().contiguous();
  method.logits(features);
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r) {
    Stopwatch clock;
    method.logits(features);
    seconds.push_back(clock.seconds());
  }
  std::nth_element(seconds.begin(), seconds.begin() + repeats / 2, seconds.end());
  return {seconds[repeats / 2] / static_cast<double>(first.size()), static_cast<std::int64_t>(first.size())};
}

}  // namespace fscil
