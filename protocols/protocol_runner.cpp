#include "protocols/protocol_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "datasets/log_mel_extractor.h"
#include "metrics/context_dispersion.h"
#include "metrics/resource_usage.h"

namespace fscil {

namespace {

// Rows of a N x C x ... array; with channel_repeat > 1 (mono stored once) the channel axis is an
// expanded view, so the repeat costs no memory until a batch is gathered from it.
torch::Tensor rows_of(const FloatArray& array, const torch::Tensor& index, int channel_repeat) {
  // from_blob wraps the dataset's memory without copying; index_select makes the owned copy.
  const torch::Tensor all = torch::from_blob(const_cast<float*>(array.values.data()), array.shape, torch::kFloat);
  torch::Tensor rows = all.index_select(0, index);
  if (channel_repeat == 1) return rows;
  std::vector<std::int64_t> shape = rows.sizes().vec();
  shape[1] *= channel_repeat;
  return rows.expand(shape);
}

constexpr std::int64_t kTestBatch = 512;

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

// The dataset's front end on tensors, for methods that transform raw signals while training.
std::function<torch::Tensor(const torch::Tensor&)> tensor_front_end(const LogMelSettings& settings) {
  auto extractor = std::make_shared<const LogMelExtractor>(settings);
  return [extractor](const torch::Tensor& signals) {
    const torch::Tensor input = signals.to(torch::kFloat).contiguous();
    FloatArray array(input.sizes().vec());
    std::copy(input.data_ptr<float>(), input.data_ptr<float>() + input.numel(), array.values.begin());
    FloatArray features = extractor->extract(array, torch::get_num_threads());
    return torch::from_blob(features.values.data(), features.shape, torch::kFloat).clone();
  };
}

template <typename T>
std::vector<T> to_vector(const torch::Tensor& tensor) {
  const torch::Tensor contiguous = tensor.contiguous();
  return std::vector<T>(contiguous.data_ptr<T>(), contiguous.data_ptr<T>() + contiguous.numel());
}

}  // namespace

InputShape input_shape_of(const PreparedDataset& dataset) {
  const auto& features = dataset.features.shape;
  return {features[1] * dataset.description.channel_repeat, features[2], features[3],
          dataset.segments.signals.shape[2]};
}

SessionData gather_session(const PreparedDataset& dataset, const SessionSchedule& schedule,
                           const std::vector<std::int64_t>& indices, int session) {
  const torch::Tensor index = torch::tensor(indices, torch::kLong);
  SessionData data;
  data.session = session;
  const int repeat = dataset.description.channel_repeat;
  data.features = rows_of(dataset.features, index, repeat);
  data.signals = rows_of(dataset.segments.signals, index, repeat);
  data.labels = torch::tensor(schedule.labels_of(indices), torch::kLong);
  const SessionPlan& plan = schedule.plan;
  for (int c = plan.first_class_of(session); c < plan.seen_after(session); ++c) data.new_classes.push_back(c);
  return data;
}

std::vector<SessionOutcome> run_sessions(Method& method, const PreparedDataset& dataset,
                                         const SessionSchedule& schedule, RunContext& context,
                                         std::optional<double> inherited_base_seconds) {
  const SessionPlan& plan = schedule.plan;
  const SessionData validation = gather_session(dataset, schedule, schedule.validation, 0);
  const torch::Tensor test_index = torch::tensor(schedule.test, torch::kLong);
  const torch::Tensor test_features = rows_of(dataset.features, test_index, dataset.description.channel_repeat);
  const torch::Tensor test_labels = torch::tensor(schedule.labels_of(schedule.test), torch::kLong);
  context.validation = &validation;
  context.total_classes = plan.total_classes();
  context.base_classes = plan.base_classes;
  context.input = input_shape_of(dataset);
  context.front_end = tensor_front_end(dataset.description.front_end);

  const std::vector<int> segment_contexts = context_ids(dataset.segments);
  std::vector<SessionOutcome> outcomes;
  for (int session = 0; session < plan.sessions; ++session) {
    const SessionData data = gather_session(dataset, schedule, schedule.train[session], session);
    if (context.progress != nullptr) {
      context.progress->stage(fmt::format("session {}/{}: {} classes, {} training samples", session, plan.sessions - 1,
                                          data.new_classes.size(), data.labels.size(0)));
    }
    SessionOutcome outcome;
    outcome.session = session;
    outcome.seen_classes = plan.seen_after(session);
    Stopwatch train_clock;
    if (session > 0) {
      method.learn_session(data, context);
    } else if (!inherited_base_seconds) {
      method.train_base(data, context);
    }
    outcome.train_seconds = session == 0 && inherited_base_seconds ? *inherited_base_seconds : train_clock.seconds();

    Stopwatch test_clock;
    const torch::Tensor seen = (test_labels < outcome.seen_classes).nonzero().flatten();
    const torch::Tensor features = test_features.index_select(0, seen);
    std::vector<torch::Tensor> predictions, embeddings;
    for (std::int64_t first = 0; first < features.size(0); first += kTestBatch) {
      const torch::Tensor batch = features.narrow(0, first, std::min(kTestBatch, features.size(0) - first));
      const torch::Tensor embedding = method.embed(batch);
      predictions.push_back(method.classify(embedding).argmax(1));
      if (!segment_contexts.empty()) {
        embeddings.push_back(torch::nn::functional::normalize(embedding, torch::nn::functional::NormalizeFuncOptions().dim(1)));
      }
    }
    const auto labels = to_vector<std::int64_t>(test_labels.index_select(0, seen));
    outcome.accuracy = score_session(labels, to_vector<std::int64_t>(torch::cat(predictions)), plan.base_classes,
                                     plan.first_class_of(session), plan.seen_after(session));
    if (!segment_contexts.empty()) {
      // Measured on unit-length embeddings: the cosine classifier only sees directions.
      const torch::Tensor all = torch::cat(embeddings);
      std::vector<int> contexts;
      for (std::int64_t position : to_vector<std::int64_t>(seen)) contexts.push_back(segment_contexts[schedule.test[position]]);
      const ContextDispersion dispersion =
          measure_context_dispersion(to_vector<float>(all), all.size(1), labels, contexts);
      outcome.context_ratio_mean = dispersion.mean;
      outcome.context_ratio_max = dispersion.max;
    }
    outcome.test_seconds = test_clock.seconds();
    if (context.progress != nullptr) {
      std::string line = fmt::format("session {} accuracy {:.2f}% (base {:.2f}%, novel {:.2f}%) on {} test samples",
                                     session, outcome.accuracy.all, outcome.accuracy.base, outcome.accuracy.novel,
                                     outcome.accuracy.samples);
      if (!segment_contexts.empty()) {
        line += fmt::format(", context ratio R mean {:.3f} max {:.3f}", outcome.context_ratio_mean, outcome.context_ratio_max);
      }
      context.progress->note(line);
    }
    outcomes.push_back(outcome);
  }
  context.validation = nullptr;
  return outcomes;
}

InferenceTiming time_inference(Method& method, const PreparedDataset& dataset, const SessionSchedule& schedule,
                               std::int64_t batch, int repeats) {
  const std::vector<std::int64_t> first(schedule.test.begin(),
                                        schedule.test.begin() + std::min<std::int64_t>(batch, schedule.test.size()));
  const torch::Tensor features =
      rows_of(dataset.features, torch::tensor(first, torch::kLong), dataset.description.channel_repeat).contiguous();
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
