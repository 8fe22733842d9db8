#include "methods/arp/arp_method.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "methods/arp/arp_episode.h"
#include "methods/arp/repeated_batch_statistics.h"
#include "methods/common/best_epoch.h"
#include "methods/common/embedding.h"
#include "methods/common/epoch_validation.h"
#include "methods/common/session_order.h"
#include "methods/common/supervised_training.h"

namespace fscil {

namespace F = torch::nn::functional;

ArpMethod::ArpMethod(const ParameterSet& params) : settings_(ArpSettings::from(params)) {}

NamedModules ArpMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  const std::int64_t dim = encoder_->embedding_size();
  rows_ = ArpRows(context.total_classes, dim);
  relation_ = RelationHead(dim, settings_.relation_width);
  attention_ = RefinementAttention(dim);
  seen_classes_ = ClassCount();
  base_classes_ = ClassCount();
  NamedModules modules{{"encoder", encoder_.ptr()},
                       {"rows", rows_.ptr()},
                       {"relation", relation_.ptr()},
                       {"seen_classes", seen_classes_.ptr()},
                       {"base_classes", base_classes_.ptr()}};
  // Part of the model only where the test uses it; otherwise base training's alone.
  if (settings_.refined_test_rows) modules.push_back({"attention", attention_.ptr()});
  return modules;
}

// main_SPPR_Nsynth.py meta_train (L116-L193) and FSCIL_model_define_V1.py forward (L126-L160).
void ArpMethod::train_base(const SessionData& base, RunContext& context) {
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  const ArpEpisodeSampler sampler(base, classes, settings_.way, settings_.shot, settings_.tasks);
  // One optimiser over every parameter (L58; Utils.py L67-L69), the learned rows included.
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& part : {rows_->parameters(), relation_->parameters(), attention_->parameters()}) {
    parameters.insert(parameters.end(), part.begin(), part.end());
  }
  encoder_->train();
  relation_->train();
  attention_->train();
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    const ArpEpisode episode = sampler.draw(context.generator);
    // The supports' means keep their gradient (L127-L133).
    const torch::Tensor means = support_means(encoder_->forward(episode.features), settings_.shot);
    // The release embeds the batch once per task (L150): the same features and gradients as one
    // pass, but `tasks` running-statistics updates, which this one pass makes at once.
    torch::Tensor queries;
    {
      const RepeatedBatchStatistics repeated(*encoder_, settings_.tasks);
      queries = encoder_->forward(features);
    }
    const torch::Tensor rows = rows_->rows.slice(0, 0, classes);
    // CE over every task's logits with the labels repeated per task (main L157-L160): the mean of
    // the tasks' means, as every task scores the same batch.
    torch::Tensor total = torch::zeros({});
    for (const torch::Tensor& slots : episode.task_slots) {
      const torch::Tensor refined =
          refine_task_rows(attention_, rows, episode.classes.index_select(0, slots), means.index_select(0, slots));
      total = total + F::cross_entropy(relation_->forward(queries, refined), labels);
    }
    return total / settings_.tasks;
  };
  // The release stops once the base-validation loss (plain rows, no refinement) has not fallen for
  // more than early_stop_tol epochs (main L166, L179, L219-L230), and keeps the weights it stopped
  // with: its "best" state_dict() shares storage with the live weights. Under --selection
  // validation the epoch of the lowest loss is kept instead, which is what that code meant to do.
  const SessionData* validation = context.validation;
  const bool may_stop = validation != nullptr && settings_.base.epochs > settings_.early_stop_tol + 1;
  const bool select = validation != nullptr && context.selection == EpochSelection::validation;
  BestEpoch best({encoder_.get(), rows_.get(), relation_.get(), attention_.get()});
  double lowest = std::numeric_limits<double>::infinity();
  int epochs_without_lower = 0;
  train_epochs_while(parameters, loss, base, settings_.base, context, "base", [&](int epoch) {
    if (validation == nullptr || validation->labels.size(0) == 0) return true;
    const auto [validation_ce, accuracy] = validation_scores(*validation, classes);
    auto& values = context.training_log.back().values;
    values[kBaseValidationKey] = accuracy;
    if (!may_stop && !select) return true;
    values["validation_ce"] = validation_ce;
    if (select) {
      values["selection_score"] = -validation_ce;
      best.consider("base", epoch, -validation_ce);
    }
    epochs_without_lower = validation_ce < lowest ? 0 : epochs_without_lower + 1;
    lowest = std::min(lowest, validation_ce);
    if (may_stop && epochs_without_lower > settings_.early_stop_tol) {
      context.diagnostics["base_stopped_epoch"] = epoch;
      return false;
    }
    return true;
  });
  best.restore(context, "base");
  seen_classes_->add(classes);
  base_classes_->add(classes);
  record_base_scores(context);
}

// The base's scores on base validation with the plain rows (`base_validation`) and with the
// refined rows (`base_validation_refined_rows`), whichever arp_test_rows the test reads, from one
// pass of the encoder. Beside them the learned rows' norm and how far the attention moves them
// (eval mode; in session 0 every row is a query and a key).
void ArpMethod::record_base_scores(RunContext& context) {
  torch::NoGradGuard no_grad;
  const torch::Tensor rows = rows_->rows.slice(0, 0, seen_classes_->value());
  const torch::Tensor refined = refine_seen_rows(attention_, rows, base_classes_->value());
  context.diagnostics["base_row_norm"] = rows.norm(2, 1).mean().item<double>();
  context.diagnostics["refinement_norm"] = (refined - rows).norm(2, 1).mean().item<double>();
  if (context.validation == nullptr) return;
  const torch::Tensor embeddings = embed_in_batches(encoder_, context.validation->features);
  const auto accuracy = [&](const torch::Tensor& scored_rows) {
    const torch::Tensor predicted = relation_logits(embeddings, scored_rows).argmax(1);
    return 100.0 * (predicted == context.validation->labels).to(torch::kDouble).mean().item<double>();
  };
  const double plain = accuracy(rows);
  const double with_refined = accuracy(refined);
  context.diagnostics["base_validation"] = plain;
  context.diagnostics["base_validation_refined_rows"] = with_refined;
  if (context.progress != nullptr) {
    context.progress->note(fmt::format("base validation accuracy {:.2f}% (refined rows {:.2f}%)", plain, with_refined));
  }
}

// calculate_means (FSCIL_model_define_V1.py L188-L198): the shots' mean raw embeddings, nothing
// trained. The release's first session embeds them with BatchNorm still in training mode (a fresh
// model, main L98); here the encoder is frozen and embeds in eval mode, as every later session.
void ArpMethod::learn_session(const SessionData& support, RunContext& /*context*/) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const auto added = static_cast<std::int64_t>(support.new_classes.size());
  const torch::Tensor means = class_means(embed_in_batches(encoder_, support.features), support.labels, support.new_classes);
  {
    torch::NoGradGuard no_grad;
    rows_->rows.slice(0, seen, seen + added).copy_(means);
  }
  seen_classes_->add(added);
}

torch::Tensor ArpMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

// forward_test (FSCIL_model_define_V1.py L162-L165): the relation head on every seen row, plain as
// released, or refined under arp_test_rows=refined.
torch::Tensor ArpMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const torch::Tensor rows = rows_->rows.slice(0, 0, seen_classes_->value());
  return relation_logits(embeddings, settings_.refined_test_rows ? refine_seen_rows(attention_, rows, base_classes_->value()) : rows);
}

// In eval mode and in chunks of samples: every pair is a row of the head's hidden layers.
torch::Tensor ArpMethod::relation_logits(const torch::Tensor& embeddings, const torch::Tensor& rows) {
  const bool was_training = relation_->is_training();
  relation_->eval();
  std::vector<torch::Tensor> chunks;
  for (const torch::Tensor& chunk : embeddings.split(1024)) chunks.push_back(relation_->forward(chunk, rows));
  relation_->train(was_training);
  return torch::cat(chunks);
}

std::pair<double, double> ArpMethod::validation_scores(const SessionData& validation, std::int64_t classes) {
  torch::NoGradGuard no_grad;
  const torch::Tensor logits =
      relation_logits(embed_in_batches(encoder_, validation.features), rows_->rows.slice(0, 0, classes));
  const double accuracy = 100.0 * (logits.argmax(1) == validation.labels).to(torch::kDouble).mean().item<double>();
  return {F::cross_entropy(logits, validation.labels).item<double>(), accuracy};
}

MethodEntry arp_entry() {
  MethodEntry entry{"arp",
                    "ARP: learned base rows refined by attention in base-training episodes, a relation head scoring "
                    "samples against rows; sessions add the shots' means, nothing trained",
                    [](const ParameterSet& params) { return std::make_unique<ArpMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const ArpSettings arp = ArpSettings::from(read);
    // Every batch carries an episode's supports besides its queries; ARP's own early stop can only
    // shorten the epochs.
    StageWork base = pretraining_work(read, sizes);
    const double batches = std::ceil(static_cast<double>(sizes.base_train) / arp.base.batch_size);
    const double supports = std::min<double>(arp.way + arp.tasks, sizes.base_classes) * arp.shot;
    // The supports pass alone, a small batch: 3.8 times a sample's share of a full batch, fitted on
    // simtex, fast, seed 1 (docs/profiling.md).
    base.trained += 3.8 * arp.base.expected_epochs() * batches * supports;
    return std::vector<StageWork>{base, base_embedding_work(sizes, 0), session_work(sizes, 0)};
  };
  entry.profile_defaults = pretraining_profiles();
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  return entry;
}

}  // namespace fscil
