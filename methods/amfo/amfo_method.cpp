#include "methods/amfo/amfo_method.h"

#include <fmt/format.h>

#include "methods/common/base_validation.h"
#include "methods/common/best_epoch.h"
#include "methods/common/class_members.h"
#include "methods/common/class_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/session_order.h"
#include "methods/common/shuffled_batches.h"
#include "methods/dsn/dsn_head.h"
#include "methods/dsn/gaussian_replay.h"
#include "methods/dsn/shot_confusion.h"

namespace fscil {

AmfoMethod::AmfoMethod(const ParameterSet& params) : settings_(AmfoSettings::from(params)) {}

NamedModules AmfoMethod::build(const RunContext& context) {
  const ResNet18Options options = encoder_options(context);
  encoder_ = ResNet18Encoder(options);
  // The release's nodes are its embedding's width (node = 512, AMFO.py L18): here D.
  const std::int64_t dim = encoder_->embedding_size();
  head_ = AmfoHead(dim, options.widths[0], dim, context.base_classes);
  supports_ = SessionSupports();
  negative_heads_ = NegativeHeads();
  for (std::int64_t classes : sessions_to_build_) {
    supports_->add_session(torch::zeros({dim, dim}), torch::zeros({classes, dim}));
    negative_heads_->add_session(torch::zeros({classes, dim}));
  }
  fusion_ = FusionSlot(fusion_classes_to_build_ > 0 ? fusion_classes_to_build_ : context.base_classes,
                       settings_.fusion_hidden);
  gaussians_ = ClassGaussians(context.total_classes, dim);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"head", head_.ptr()},
          {"supports", supports_.ptr(), true},
          {"negative_heads", negative_heads_.ptr(), true},
          {"fusion", fusion_.ptr(), true},
          {"gaussians", gaussians_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

// A checkpoint after session s holds s support branches and heads and a fusion net over its seen
// classes: they are built at those sizes before the state is read.
void AmfoMethod::restore_state(const MethodState& state, RunContext& context) {
  sessions_to_build_.clear();
  for (int s = 1; state.count(fmt::format("supports.head{}", s)) > 0; ++s) {
    sessions_to_build_.push_back(state.at(fmt::format("supports.head{}", s)).size(0));
  }
  const auto fusion = state.find("fusion.net.hidden.weight");
  fusion_classes_to_build_ = fusion == state.end() ? 0 : fusion->second.size(1) / 2;
  ModuleMethod::restore_state(state, context);
  sessions_to_build_.clear();
  fusion_classes_to_build_ = 0;
}

AmfoLossSettings AmfoMethod::loss_settings(double fusion, double margin, double binary) const {
  AmfoLossSettings weights;
  weights.fusion = fusion;
  weights.margin = margin;
  weights.binary = binary;
  weights.temperature = settings_.temperature;
  weights.cosface_scale = settings_.cosface_scale;
  weights.positive_margin = settings_.positive_margin;
  weights.negative_margin = settings_.negative_margin;
  return weights;
}

// train.py L98-L153: one SGD over the encoder, both heads, the first-stage projection and the
// fusion net, on the shared schedule. The first stage's feature is detached before `shallow`
// (Resnet.py L241): the negative head's loss trains shallow, fc1 and fc2_n, not the encoder.
void AmfoMethod::train_base(const SessionData& base, RunContext& context) {
  sessions_to_build_.clear();
  fusion_classes_to_build_ = 0;
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& part : {head_->parameters(), fusion_->parameters()}) {
    parameters.insert(parameters.end(), part.begin(), part.end());
  }
  encoder_->train();
  const AmfoLossSettings weights =
      loss_settings(settings_.base_fusion_weight, settings_.base_margin_weight, settings_.base_binary_weight);
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    const auto [embeddings, first_stage] = encoder_->forward_with_first_stage(features);
    const HeadCosines heads = cosines(embeddings, first_stage.detach());
    const Fusion fusion = fuse(fusion_->net(), heads.positive, heads.negative);
    // Every label is a base class: the binary target is "base" throughout (AMFO.py L137).
    return amfo_loss(heads.positive, heads.negative, fusion, labels, classes, weights).total();
  };
  // The release keeps the base epoch with the best fused accuracy on the test split (train.py
  // L103, L147-L153): --selection.
  BestEpoch best({encoder_.get(), head_.get(), fusion_.get()});
  train_epochs(parameters, loss, base, settings_.base, context, "base", [&](int epoch) {
    score_base_epoch(best, "base", epoch, context,
                     [&](const SessionData& data) { return fused_cosines(embed_rows(data.features)); });
  });
  best.restore(context, "base");
  // Every base class's Gaussian of the deep embedding (Inc_train.py L225-L248), as DSN's.
  const torch::Tensor embeddings = embed_in_batches(encoder_, base.features);
  const auto [means, covariances] = class_statistics(embeddings, base.labels, class_range(0, classes));
  gaussians_->insert(0, means, covariances);
  seen_classes_->add(classes);
  record_base_validation(*this, context);
}

void AmfoMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const auto added = static_cast<std::int64_t>(support.new_classes.size());
  const torch::Tensor shots = embed_in_batches(encoder_, support.features);
  const auto [means, covariances] = class_statistics(shots, support.labels, support.new_classes);
  // The session's support branch starts as fc1, both its heads' rows as l2n(fc1 mean)
  // (Inc_train.py L278-L288); its gate at zero; a fresh fusion net over every seen class (L343-L345).
  {
    torch::NoGradGuard no_grad;
    const torch::Tensor rows = dsn_l2_norm(head_->fc1->forward(means));
    supports_->add_session(head_->fc1->weight, rows);
    negative_heads_->add_session(rows);
  }
  fusion_->replace(seen + added);
  gaussians_->insert(seen, means, covariances);
  train_session(shots, support.labels, seen, means, covariances, context);
  seen_classes_->add(added);
}

// The session's epochs (Inc_train.py L337-L510), DSN's loop with AMFO's model and loss. Everything
// but the newest branch, its two heads and the fusion net is frozen (the "part" optimiser,
// L346-L352), so the network before the session, the distillation teacher (L437-L438), scores the
// old classes as this one does: its cosines are this network's old columns, detached.
void AmfoMethod::train_session(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t first,
                               const torch::Tensor& shot_means, const torch::Tensor& shot_covariances,
                               RunContext& context) {
  const int session = supports_->sessions();
  const std::int64_t classes = supports_->classes_of(session), base = context.base_classes;
  for (auto* module : {static_cast<torch::nn::Module*>(head_.get()), static_cast<torch::nn::Module*>(supports_.get()),
                       static_cast<torch::nn::Module*>(negative_heads_.get())}) {
    for (auto& parameter : module->parameters()) parameter.set_requires_grad(false);
  }
  std::vector<torch::Tensor> trained{supports_->head(session), supports_->branch(session), negative_heads_->head(session)};
  for (const auto& parameter : fusion_->parameters()) trained.push_back(parameter);
  for (auto tensor : trained) tensor.set_requires_grad(true);
  torch::optim::SGD optimizer(trained, torch::optim::SGDOptions(settings_.session_lr).momentum(0.9).dampening(0.5));
  // The session's classes get new_samples draws, every older class old_samples: the release's
  // max(min, sample_k) with nothing raising sample_k (exemplar.py L59-L73; Inc_train.py L467).
  DrawCounts counts;
  counts.current = settings_.new_samples;
  counts.base_cap = counts.old_cap = counts.regular = settings_.old_samples;
  const AmfoLossSettings weights =
      loss_settings(settings_.session_fusion_weight, settings_.session_margin_weight, settings_.session_binary_weight);
  // Under test-oracle, the epoch with the best fused accuracy on every seen class's test samples
  // (Inc_train.py L489-L510; ties to the later epoch); otherwise the last epoch (ours).
  torch::Tensor oracle, oracle_labels;
  if (context.selection == EpochSelection::test_oracle) {
    oracle = embed_rows(context.oracle_test->features);
    oracle_labels = context.oracle_test->labels;
  }
  BestEpoch best({supports_.get(), negative_heads_.get(), fusion_.get()});
  GaussianReplay replay(*gaussians_, shots, shot_labels, first, base, shot_means, shot_covariances, counts,
                        settings_.refresh_every);
  for (int epoch = 0; epoch < settings_.session_epochs; ++epoch) {
    replay.start_epoch(epoch);
    const torch::Tensor &features = replay.features(), &labels = replay.labels();
    const std::vector<torch::Tensor> batches =
        shuffled_batches(features.size(0), settings_.session_batch, context.generator);
    ShotConfusion confusion(base, first, classes);
    double margin = 0, fusion_part = 0, binary = 0, distillation = 0, sparsity = 0;
    int steps = 0;
    for (const torch::Tensor& rows : batches) {
      const torch::Tensor batch_labels = labels.index_select(0, rows), is_new = batch_labels >= first;
      const torch::Tensor old_rows = rows.index({~is_new}), new_rows = rows.index({is_new});
      // Old classes' rows (drawn) pass with the stored gate, the previous step's (L423); the
      // session's rows set the training gate from their batch mean (L416).
      HeadCosines heads = cosines(features.index_select(0, old_rows));
      torch::Tensor gate, new_positive;
      if (new_rows.size(0) > 0) {
        const torch::Tensor new_features = features.index_select(0, new_rows);
        gate = training_gate(supports_->branch_cosines(session, new_features), epoch);
        const HeadCosines new_heads = cosines(new_features, {}, gate);
        new_positive = new_heads.positive;
        heads = {torch::cat({heads.positive, new_heads.positive}), torch::cat({heads.negative, new_heads.negative})};
      }
      const torch::Tensor output_labels = torch::cat({labels.index_select(0, old_rows), labels.index_select(0, new_rows)});
      const Fusion fusion = fuse(fusion_->net(), heads.positive, heads.negative);
      AmfoLoss loss = amfo_loss(heads.positive, heads.negative, fusion, output_labels, base, weights);
      add_session_terms(loss, heads.positive, heads.positive.slice(1, 0, first).detach(), settings_.temperature, gate,
                        settings_.sparsity_floor);
      optimizer.zero_grad();
      loss.total().backward();
      optimizer.step();
      if (gate.defined()) {
        torch::NoGradGuard no_grad;
        supports_->gate(session).copy_(gate.detach());  // finish_train (L455; AMFO.py L120-L122)
        // The real shots' positive-head cosines weigh the base covariances (L458; exemplar.py L172-L192).
        const torch::Tensor shot_rows = replay.is_real_shot().index_select(0, new_rows);
        confusion.record(new_positive.detach().index({shot_rows}), labels.index_select(0, new_rows).index({shot_rows}));
      }
      margin += loss.margin.item<double>();
      fusion_part += loss.fusion.item<double>();
      binary += loss.binary.item<double>();
      distillation += loss.distillation.item<double>();
      sparsity += loss.sparsity.item<double>();
      ++steps;
    }
    // After the epoch: calibrate and blend (L462-L465); no class earns extra draws
    // (statisitc_sample is commented out, L467).
    replay.end_epoch(epoch, confusion);
    const double n = std::max(steps, 1);
    context.log_epoch("session", epoch + 1, settings_.session_epochs,
                      {{"loss", (margin + fusion_part + binary + distillation + sparsity) / n},
                       {"margin", margin / n},
                       {"fusion", fusion_part / n},
                       {"binary", binary / n},
                       {"kd", distillation / n},
                       {"sparsity", sparsity / n},
                       {"gate_mean", supports_->gate(session).mean().item<double>()}});
    if (oracle.defined()) {
      torch::NoGradGuard no_grad;
      const double score = 100.0 * (fused_cosines(oracle).argmax(1) == oracle_labels).to(torch::kDouble).mean().item<double>();
      context.training_log.back().values["selection_score"] = score;
      if (best.consider("session", epoch + 1, score)) replay.keep(epoch);
    }
  }
  best.restore(context, "session");
  replay.finish();
  context.diagnostics["session_gate_mean"] = supports_->gate(session).mean().item<double>();
}

HeadCosines AmfoMethod::cosines(const torch::Tensor& embeddings, const torch::Tensor& first_stage,
                                const torch::Tensor& newest_gate) {
  return amfo_cosines(*head_, *supports_, *negative_heads_, embeddings, first_stage, settings_.gamma, newest_gate);
}

torch::Tensor AmfoMethod::fused_cosines(const torch::Tensor& embedded) {
  const std::int64_t dim = encoder_->embedding_size();
  const HeadCosines heads = cosines(embedded.slice(1, 0, dim), embedded.slice(1, dim));
  return fuse(fusion_->net(), heads.positive, heads.negative).mixed;
}

torch::Tensor AmfoMethod::embed(const torch::Tensor& features) { return embed_with_first_stage_in_batches(encoder_, features); }

// The fused cosines over every seen class with each session's stored gate (test() train.py
// L48-L84; test_continue Inc_train.py L100-L149 with the fused "atten" prediction, see
// docs/methods.md), scaled by the temperature as in training.
torch::Tensor AmfoMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return settings_.temperature * fused_cosines(embeddings);
}

MethodEntry amfo_entry() {
  MethodEntry entry{"amfo",
                    "AMFO: positive- and negative-margin cosine heads (deep and first-stage features) mixed by a fusion "
                    "net; sessions add DSN-style gated supports with both heads, trained on shots and Gaussian draws",
                    [](const ParameterSet& params) { return std::make_unique<AmfoMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const AmfoSettings amfo = AmfoSettings::from(read);
    StageWork sessions = session_work(sizes, 0);
    // 0.48 head steps per class and epoch (two heads, a fusion net): fitted as dsn's is.
    sessions.head_steps = gaussian_replay_head_steps(sizes, amfo.session_epochs, amfo.session_batch, 0.48, [&](int session) {
      return static_cast<double>(amfo.old_samples * sizes.classes_before(session) + (amfo.new_samples + sizes.shot) * sizes.way);
    });
    return std::vector<StageWork>{pretraining_work(read, sizes), base_embedding_work(sizes), sessions};
  };
  // Smoke runs 10 session epochs, not 130: a protocol that only checks the machinery (ours).
  entry.profile_defaults = pretraining_profiles({{"smoke", {{"amfo_session_epochs", "10"}}}});
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.session_only_parameters = {"amfo_session_fusion_weight", "amfo_session_margin_weight", "amfo_session_binary_weight",
                                   "amfo_gamma",         "amfo_r",          "amfo_session_epochs",
                                   "amfo_session_lr",    "amfo_session_batch", "amfo_refresh_every",
                                   "amfo_new_samples",   "amfo_old_samples"};
  return entry;
}

}  // namespace fscil
