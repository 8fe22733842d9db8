#include "protocols/protocol_runner.h"

#include <fmt/format.h>

#include "metrics/resource_usage.h"

namespace fscil {

namespace {

torch::Tensor rows_of(const FloatArray& array, const torch::Tensor& index) {
  // from_blob wraps the dataset's memory without copying; index_select makes the owned copy.
  const torch::Tensor all = torch::from_blob(const_cast<float*>(array.values.data()), array.shape, torch::kFloat);
  return all.index_select(0, index);
}

constexpr std::int64_t kTestBatch = 512;

}  // namespace

InputShape input_shape_of(const PreparedDataset& dataset) {
  const auto& features = dataset.features.shape;
  return {features[1], features[2], features[3], dataset.segments.signals.shape[2]};
}

SessionData gather_session(const PreparedDataset& dataset, const SessionSchedule& schedule,
                           const std::vector<std::int64_t>& indices, int session) {
  const torch::Tensor index = torch::tensor(indices, torch::kLong);
  SessionData data;
  data.session = session;
  data.features = rows_of(dataset.features, index);
  data.signals = rows_of(dataset.segments.signals, index);
  data.labels = torch::tensor(schedule.labels_of(indices), torch::kLong);
  const SessionPlan& plan = schedule.plan;
  for (int c = plan.first_class_of(session); c < plan.seen_after(session); ++c) data.new_classes.push_back(c);
  return data;
}

std::vector<SessionOutcome> run_sessions(Method& method, const PreparedDataset& dataset,
                                         const SessionSchedule& schedule, RunContext& context) {
  const SessionPlan& plan = schedule.plan;
  const SessionData validation = gather_session(dataset, schedule, schedule.validation, 0);
  const torch::Tensor test_index = torch::tensor(schedule.test, torch::kLong);
  const torch::Tensor test_features = rows_of(dataset.features, test_index);
  const torch::Tensor test_labels = torch::tensor(schedule.labels_of(schedule.test), torch::kLong);
  context.validation = &validation;
  context.total_classes = plan.total_classes();
  context.base_classes = plan.base_classes;
  context.input = input_shape_of(dataset);

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
    if (session == 0) {
      method.train_base(data, context);
    } else {
      method.learn_session(data, context);
    }
    outcome.train_seconds = train_clock.seconds();

    Stopwatch test_clock;
    const torch::Tensor seen = (test_labels < outcome.seen_classes).nonzero().flatten();
    const torch::Tensor features = test_features.index_select(0, seen);
    std::vector<torch::Tensor> predictions;
    for (std::int64_t first = 0; first < features.size(0); first += kTestBatch) {
      const torch::Tensor batch = features.narrow(0, first, std::min(kTestBatch, features.size(0) - first));
      predictions.push_back(method.logits(batch).argmax(1));
    }
    const torch::Tensor predicted = torch::cat(predictions).contiguous();
    const torch::Tensor labels = test_labels.index_select(0, seen).contiguous();
    outcome.accuracy = score_session(
        std::vector<std::int64_t>(labels.data_ptr<std::int64_t>(), labels.data_ptr<std::int64_t>() + labels.numel()),
        std::vector<std::int64_t>(predicted.data_ptr<std::int64_t>(),
                                  predicted.data_ptr<std::int64_t>() + predicted.numel()),
        plan.base_classes, plan.first_class_of(session), plan.seen_after(session));
    outcome.test_seconds = test_clock.seconds();
    if (context.progress != nullptr) {
      context.progress->note(fmt::format("session {} accuracy {:.2f}% (base {:.2f}%, novel {:.2f}%) on {} test samples",
                                         session, outcome.accuracy.all, outcome.accuracy.base, outcome.accuracy.novel,
                                         outcome.accuracy.samples));
    }
    outcomes.push_back(outcome);
  }
  context.validation = nullptr;
  return outcomes;
}

}  // namespace fscil
