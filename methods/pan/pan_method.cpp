#include "methods/pan/pan_method.h"

#include <fmt/format.h>

#include "core/stop_request.h"
#include "methods/common/base_validation.h"
#include "methods/common/class_members.h"
#include "methods/common/best_epoch.h"
#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/session_order.h"
#include "methods/common/shared_stage.h"
#include "methods/common/supervised_training.h"
#include "methods/pan/attention_prototypes.h"
#include "methods/pan/new_row_finetune.h"
#include "methods/pan/pan_episode.h"
#include "methods/pan/prototype_query_attention.h"

namespace fscil {

namespace F = torch::nn::functional;

namespace {

// The samples of classes [0, classes) of `data`, labels unchanged.
SessionData first_classes(const SessionData& data, std::int64_t classes) {
  const torch::Tensor index = torch::nonzero(data.labels < classes).view(-1);
  SessionData subset;
  subset.session = data.session;
  const SampleRows& rows = data.features;
  subset.features = SampleRows(index.size(0), [rows, index](const torch::Tensor& local) {
    return rows.gather(index.index_select(0, local));
  });
  subset.labels = data.labels.index_select(0, index);
  for (std::int64_t c = 0; c < classes; ++c) subset.new_classes.push_back(c);
  return subset;
}

}  // namespace

PanMethod::PanMethod(const ParameterSet& params) : settings_(PanSettings::from(params)) {}

NamedModules PanMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  const std::int64_t dim = encoder_->embedding_size();
  classifier_ = CosineClassifier(context.total_classes, dim, settings_.temperature);
  attention_ = PanAttention(dim);
  prototype_attention_ = PanAttention(dim);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"classifier", classifier_.ptr()},
          {"attention", attention_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

torch::optim::OptimizerParamGroup PanMethod::episode_group(std::vector<torch::Tensor> parameters,
                                                          double learning_rate) const {
  return torch::optim::OptimizerParamGroup(
      std::move(parameters), std::make_unique<torch::optim::SGDOptions>(torch::optim::SGDOptions(learning_rate)
                                                                            .momentum(settings_.standard.momentum)
                                                                            .nesterov(true)
                                                                            .weight_decay(settings_.standard.weight_decay)));
}

// The release's optimisers take encoder.parameters(), and its bn0 belongs to the model around the
// encoder (Network.py L151, L209): bn0's scale and shift are never trained. Ours is inside.
std::vector<torch::Tensor> PanMethod::encoder_parameters() const {
  std::vector<torch::Tensor> parameters;
  for (const auto& item : encoder_->named_parameters()) {
    if (item.key().rfind("bn0.", 0) != 0) parameters.push_back(item.value());
  }
  return parameters;
}

void PanMethod::train_base(const SessionData& base, RunContext& context) {
  train_pan_stages(base, context);
  record_base_validation(*this, context);
}

void PanMethod::train_pan_stages(const SessionData& base, RunContext& context) {
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  if (classes > encoder_->embedding_size()) {
    throw MethodError(fmt::format("pan scores its standard training on the first {} embedding channels, and the "
                                  "embedding has {}",
                                  classes, encoder_->embedding_size()));
  }
  train_or_take_stage(kBaseStages, shared_modules(), context, [&] {
    const std::int64_t temporary_base = temporary_base_classes(classes, settings_.temporary_base);
    context.diagnostics["temporary_base_classes"] = static_cast<double>(temporary_base);
    train_standard(first_classes(base, temporary_base), temporary_base, "temporary_standard", context);
    train_pseudo_incremental(base, temporary_base, context);
    train_standard(base, classes, "standard", context);
    // Plain means of the unnormalised embeddings (data_init, models/stdu/base.py L111-L151).
    classifier_->set_rows(0, class_means(embed_rows(base.features), base.labels, class_range(0, classes)));
    seen_classes_->add(classes);
  });
}

StageModules PanMethod::shared_modules() {
  return {{"encoder.", encoder_.get()},
          {"classifier.", classifier_.get()},
          {"attention.", attention_.get()},
          {"seen_classes.", seen_classes_.get()}};
}

// Stages (a) and (c) (standard_train_helper.py L10-L56 at 9f784713): the encoder alone, in train
// mode, on CE over the first `classes` channels of its embedding; under a selection, each stage
// keeps its best epoch scored the same way (fscil_trainer.py L152-L158: on test, in the release).
void PanMethod::train_standard(const SessionData& data, std::int64_t classes, const std::string& stage,
                               RunContext& context) {
  encoder_->train();
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    return F::cross_entropy(encoder_->forward(features).slice(1, 0, classes), labels);
  };
  BestEpoch best({encoder_.get()});
  train_epochs(encoder_parameters(), loss, data, settings_.standard, context, stage, [&](int epoch) {
    score_base_epoch(
        best, stage, epoch, context,
        [&](const SessionData& scored) { return embed_rows(scored.features).slice(1, 0, classes); },
        [&](const SessionData& split) { return first_classes(split, classes); });
  });
  best.restore(context, stage);
}

// Stage (b) (incremental_train_helper.py L10-L89, fscil_trainer.py L191-L229 at 3ddc7af7): in eval
// mode, as the release runs it (L206), so BatchNorm keeps its statistics.
void PanMethod::train_pseudo_incremental(const SessionData& base, std::int64_t temporary_base, RunContext& context) {
  if (settings_.pit_epochs == 0) return;
  const PanEpisodeSampler sampler(base, temporary_base, context.base_classes, settings_.way, settings_.shot,
                                  settings_.query);
  std::vector<torch::optim::OptimizerParamGroup> groups;
  groups.push_back(episode_group(encoder_parameters(), settings_.encoder_lr));
  groups.push_back(episode_group(attention_->parameters(), settings_.attention_lr));
  torch::optim::SGD optimizer(std::move(groups), torch::optim::SGDOptions(settings_.encoder_lr));
  encoder_->eval();  // the attentions have no dropout (the release runs them in eval mode only)
  for (int epoch = 0; epoch < settings_.pit_epochs; ++epoch) {
    double loss_sum = 0;
    for (int e = 0; e < settings_.pit_episodes; ++e) {
      const PanEpisode episode = sampler.draw(context.generator);
      const std::int64_t way = episode.way, shot = episode.shot, query = episode.query;
      const torch::Tensor base_embedding = encoder_->forward(episode.base_features);
      const torch::Tensor novel_embedding = encoder_->forward(episode.novel_features);
      const std::int64_t dim = base_embedding.size(1), supports = shot * way;
      const auto part_means = [&](const torch::Tensor& part) {
        return part.slice(0, 0, supports).view({shot, way, dim}).mean(0);
      };
      const torch::Tensor means = torch::cat({part_means(base_embedding), part_means(novel_embedding)});
      // Query q of slot c of either part: row q x 2 way + c, labels the slots (incremental_train_helper.py L32, L73-L81).
      const torch::Tensor queries = torch::cat({base_embedding.slice(0, supports).view({query, way, dim}),
                                                novel_embedding.slice(0, supports).view({query, way, dim})},
                                               1)
                                        .reshape({query * 2 * way, dim});
      const torch::Tensor labels = torch::arange(2 * way).repeat({query});
      torch::Tensor replaced;
      {
        torch::NoGradGuard no_grad;  // its output reaches the loss through .data only (Network.py L64-L69)
        const torch::Tensor support_rows =
            torch::cat({base_embedding.slice(0, 0, supports), novel_embedding.slice(0, 0, supports)});
        replaced = attention_prototypes(prototype_attention_, support_rows, queries, shot);
      }
      const torch::Tensor prototypes =
          straight_through(means.unsqueeze(0).expand({queries.size(0), 2 * way, dim}), replaced);
      const torch::Tensor loss =
          F::cross_entropy(pqa_logits(attention_, prototypes, queries, settings_.temperature), labels);
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      stop_if_requested();
      loss_sum += loss.item<double>();
    }
    context.log_epoch("pseudo-incremental", epoch + 1, settings_.pit_epochs,
                      {{"loss", loss_sum / settings_.pit_episodes}, {"lr", settings_.encoder_lr}});
  }
}

void PanMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const torch::Tensor embeddings = embed_in_batches(encoder_, support.features);
  const torch::Tensor means = class_means(embeddings, support.labels, support.new_classes);
  const torch::Tensor old_rows = classifier_->weight().slice(0, 0, seen).detach();
  const torch::Tensor rows =
      finetune_new_rows(embeddings, support.labels, old_rows, means, settings_.temperature, settings_.session_steps,
                        settings_.session_lr, [&](int step, double loss) {
                          context.log_epoch("session", step, settings_.session_steps, {{"loss", loss}});
                        });
  classifier_->set_rows(seen, rows);
  seen_classes_->add(static_cast<std::int64_t>(support.new_classes.size()));
}

torch::Tensor PanMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

// Every sample attends with all seen rows (fscil_trainer.py L256-L275); no attention prototypes at
// test (the config's ap_on_test is never read).
torch::Tensor PanMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const std::int64_t seen = seen_classes_->value();
  return pqa_logits(attention_, classifier_->weight().slice(0, 0, seen), embeddings, settings_.temperature);
}

void count_pqa_cost(ModelCost& cost, const std::string& name, const PanAttention& attention, std::int64_t tokens) {
  const std::int64_t dim = attention->dim();
  // Four D x D projections of every token, the scores and their weighted sum, a LayerNorm of every token.
  for (const auto& [part, linear] : {std::pair{"query", attention->query}, {"key", attention->key},
                                     {"value", attention->value}, {"out", attention->out}}) {
    LayerCost layer = layer_with_parameters(name + "." + part, "linear", linear->parameters());
    layer.macs = tokens * linear_macs(dim, dim);
    cost.add(std::move(layer));
  }
  LayerCost scores{name + ".scores", "attention"};
  scores.macs = 2 * tokens * tokens * dim;
  cost.add(std::move(scores));
  LayerCost norm = layer_with_parameters(name + ".norm", "layer_norm", attention->norm->parameters());
  norm.macs = tokens * dim;
  cost.add(std::move(norm));
}

void PanMethod::count_rows_cost(ModelCost& cost) const {
  const std::int64_t seen = seen_classes_->value(), dim = encoder_->embedding_size();
  count_cosine_classifier(cost, "classifier", dim, seen, classifier_->parameters());
  LayerCost row_norms{"classifier.row_norms", "cosine"};  // the rows leave PQA changed by each sample
  row_norms.macs = seen * dim;
  cost.add(std::move(row_norms));
}

ModelCost PanMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  // PQA on the seen rows and the sample, then the cosine logits.
  count_pqa_cost(cost, "attention", attention_, seen_classes_->value() + 1);
  count_rows_cost(cost);
  cost.freeze("encoder");
  cost.freeze("attention");  // sessions fine-tune the new rows only
  return cost;
}

MethodEntry pan_entry() {
  MethodEntry entry{"pan",
                    "PAN: encoder trained on its own first channels, pseudo-incremental episodes whose prototypes "
                    "attend with each query (PQA), class-mean rows fine-tuned per session, PQA at test",
                    [](const ParameterSet& params) { return std::make_unique<PanMethod>(params); }};
  // Stages (a) and (c) both run the shared pretraining schedule, (b) its own epochs.
  entry.base_epoch_keys = {"pretrain_epochs", "pretrain_epochs", "pan_pit_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const PanSettings pan = PanSettings::from(read);
    // (a) trains on the temporary base classes' share of the samples, (c) on all of them.
    const double temporary = static_cast<double>(temporary_base_classes(sizes.base_classes, pan.temporary_base));
    // The three stages and the rows after them are one shared stage (kBaseStages): plan counts them
    // once for pan and pa-pct.
    StageWork stages = pretraining_work(read, sizes);
    stages.stage = PanMethod::kBaseStages;
    stages.trained *= 1 + temporary / sizes.base_classes;
    stages.trained += pan.pit_epochs * pan.pit_episodes * 2.0 * pan.way * (pan.shot + pan.query);
    const StageWork rows = base_embedding_work(sizes);
    stages.inferred += rows.inferred;
    stages.head_steps += rows.head_steps;
    return std::vector<StageWork>{stages, session_work(sizes, pan.session_steps)};
  };
  entry.profile_defaults = pretraining_profiles({{"smoke", {{"pan_pit_episodes", "4"}}}});
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.session_only_parameters = {"pan_session_steps", "pan_session_lr"};
  entry.shared_stages[PanMethod::kBaseStages] = {};  // pa-pct trains them alike
  return entry;
}

}  // namespace fscil
