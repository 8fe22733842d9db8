#include "methods/dsn/dsn_method.h"

#include <fmt/format.h>

#include "methods/common/base_validation.h"
#include "methods/common/best_epoch.h"
#include "methods/common/class_members.h"
#include "methods/common/class_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/session_order.h"
#include "methods/common/shuffled_batches.h"
#include "methods/dsn/gaussian_replay.h"
#include "methods/dsn/session_loss.h"
#include "methods/dsn/shot_confusion.h"

namespace fscil {

namespace F = torch::nn::functional;

DsnMethod::DsnMethod(const ParameterSet& params) : settings_(DsnSettings::from(params)) {}

NamedModules DsnMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  const std::int64_t dim = encoder_->embedding_size(), nodes = settings_.nodes > 0 ? settings_.nodes : dim;
  head_ = DsnHead(dim, nodes, context.base_classes);
  supports_ = SessionSupports();
  for (std::int64_t classes : sessions_to_build_) {
    supports_->add_session(torch::zeros({nodes, dim}), torch::zeros({classes, nodes}));
  }
  gaussians_ = ClassGaussians(context.total_classes, dim);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"head", head_.ptr()},
          {"supports", supports_.ptr(), true},
          {"gaussians", gaussians_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

// A checkpoint after session s holds s support branches: they are built before the state is read.
void DsnMethod::restore_state(const MethodState& state, RunContext& context) {
  sessions_to_build_.clear();
  for (int s = 1; state.count(fmt::format("supports.head{}", s)) > 0; ++s) {
    sessions_to_build_.push_back(state.at(fmt::format("supports.head{}", s)).size(0));
  }
  ModuleMethod::restore_state(state, context);
  sessions_to_build_.clear();
}

void DsnMethod::train_base(const SessionData& base, RunContext& context) {
  sessions_to_build_.clear();
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  // One SGD over the encoder, fc1 and the base rows (train.py L58): the shared schedule.
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& parameter : head_->parameters()) parameters.push_back(parameter);
  encoder_->train();
  head_->train();
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    return F::cross_entropy(settings_.temperature * head_->base_cosines(head_->project(encoder_->forward(features))),
                            labels);
  };
  // The release keeps the base epoch with the best test accuracy (train.py L90-L96): --selection.
  BestEpoch best({encoder_.get(), head_.get()});
  train_epochs(parameters, loss, base, settings_.base, context, "base", [&](int epoch) {
    score_base_epoch(best, "base", epoch, context, [&](const SessionData& data) {
      return head_->base_cosines(head_->project(embed_rows(data.features)));
    });
  });
  best.restore(context, "base");
  // One pass over the base training set keeps every base class's Gaussian (Inc_train.py L153-L175).
  const torch::Tensor embeddings = embed_in_batches(encoder_, base.features);
  const auto [means, covariances] = class_statistics(embeddings, base.labels, class_range(0, classes));
  gaussians_->insert(0, means, covariances);
  seen_classes_->add(classes);
  record_base_validation(*this, context);
}

void DsnMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const torch::Tensor shots = embed_in_batches(encoder_, support.features);
  const auto [means, covariances] = class_statistics(shots, support.labels, support.new_classes);
  // The session's support branch starts as fc1, its head rows as the shots' projected means
  // (Inc_train.py L206-L215); its gate at zero.
  {
    torch::NoGradGuard no_grad;
    supports_->add_session(head_->projection_weight(), dsn_l2_norm(head_->fc1->forward(means)));
  }
  gaussians_->insert(seen, means, covariances);
  train_session(shots, support.labels, seen, means, covariances, context);
  seen_classes_->add(static_cast<std::int64_t>(support.new_classes.size()));
}

// The session's epochs (Inc_train.py L277-L388). Everything but the newest branch and head is
// frozen (the "part" optimiser, L269-L271), so the network before the session, the distillation
// teacher (L265-L267, L337-L338), scores the old classes exactly as this one does: its logits are
// this network's old columns, detached.
void DsnMethod::train_session(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t first,
                              const torch::Tensor& shot_means, const torch::Tensor& shot_covariances,
                              RunContext& context) {
  const int session = supports_->sessions();
  const std::int64_t classes = supports_->classes_of(session), base = context.base_classes;
  for (auto& parameter : head_->parameters()) parameter.set_requires_grad(false);
  for (auto& parameter : supports_->parameters()) parameter.set_requires_grad(false);
  const std::vector<torch::Tensor> trained{supports_->head(session), supports_->branch(session)};
  for (auto tensor : trained) tensor.set_requires_grad(true);
  torch::optim::SGD optimizer(trained, torch::optim::SGDOptions(settings_.session_lr).momentum(0.9).dampening(0.5));
  DrawCounts counts;
  counts.current = settings_.new_samples;
  counts.base_cap = settings_.base_samples;
  counts.old_cap = settings_.old_samples;
  counts.regular = settings_.sample_k;
  // Under test-oracle, the epoch with the best accuracy on every seen class's test samples
  // (test_continue, L369-L388; ties to the later epoch); otherwise the last epoch (ours).
  torch::Tensor oracle, oracle_labels;
  if (context.selection == EpochSelection::test_oracle) {
    oracle = embed_in_batches(encoder_, context.oracle_test->features);
    oracle_labels = context.oracle_test->labels;
  }
  BestEpoch best({supports_.get()});
  GaussianReplay replay(*gaussians_, shots, shot_labels, first, base, shot_means, shot_covariances, counts,
                        settings_.refresh_every);
  for (int epoch = 0; epoch < settings_.session_epochs; ++epoch) {
    replay.start_epoch(epoch);
    const torch::Tensor &features = replay.features(), &labels = replay.labels();
    const std::vector<torch::Tensor> batches =
        shuffled_batches(features.size(0), settings_.session_batch, context.generator);
    ShotConfusion confusion(base, first, classes);
    double cross_entropy = 0, distillation = 0, compression = 0;
    int steps = 0;
    for (const torch::Tensor& rows : batches) {
      const torch::Tensor batch_labels = labels.index_select(0, rows), is_new = batch_labels >= first;
      const torch::Tensor old_rows = rows.index({~is_new}), new_rows = rows.index({is_new});
      // Old classes' rows (drawn) pass with the stored gate, the previous step's (L329-L335); the
      // session's rows (its shots and draws) set the training gate from their batch mean (L326-L328).
      std::vector<torch::Tensor> outputs;
      outputs.push_back(cosines(features.index_select(0, old_rows)));
      torch::Tensor gate, new_output;
      if (new_rows.size(0) > 0) {
        const torch::Tensor new_features = features.index_select(0, new_rows);
        gate = training_gate(supports_->branch_cosines(session, new_features), epoch);
        new_output = cosines(new_features, gate);
        outputs.push_back(new_output);
      }
      const torch::Tensor output = torch::cat(outputs);
      const torch::Tensor output_labels = torch::cat({labels.index_select(0, old_rows), labels.index_select(0, new_rows)});
      const DsnSessionLoss loss =
          dsn_session_loss(output, output_labels, output.slice(1, 0, first).detach(), gate, settings_.temperature);
      optimizer.zero_grad();
      loss.total().backward();
      optimizer.step();
      if (gate.defined()) {
        torch::NoGradGuard no_grad;
        supports_->gate(session).copy_(gate.detach());  // finish_train, L344 -> DSN.py L83-L84
        const torch::Tensor shot_rows = replay.is_real_shot().index_select(0, new_rows);
        confusion.record(new_output.detach().index({shot_rows}), labels.index_select(0, new_rows).index({shot_rows}));
      }
      cross_entropy += loss.cross_entropy.item<double>();
      distillation += loss.distillation.item<double>();
      compression += loss.compression.item<double>();
      ++steps;
    }
    // After the epoch: calibrate and blend, then give confused old classes one more draw (L352-L357).
    replay.end_epoch(epoch, confusion);
    for (std::int64_t c = 0; c < classes; ++c) {
      for (std::int64_t old : confused_old_classes(confusion.old_weights(c), settings_.top_k)) gaussians_->add_draw(old);
    }
    const double n = std::max(steps, 1);
    context.log_epoch("session", epoch + 1, settings_.session_epochs,
                      {{"loss", (cross_entropy + distillation + compression) / n},
                       {"ce", cross_entropy / n},
                       {"kd", distillation / n},
                       {"compression", compression / n},
                       {"gate_mean", supports_->gate(session).mean().item<double>()}});
    if (oracle.defined()) {
      torch::NoGradGuard no_grad;
      const double score = 100.0 * (cosines(oracle).argmax(1) == oracle_labels).to(torch::kDouble).mean().item<double>();
      context.training_log.back().values["selection_score"] = score;
      if (best.consider("session", epoch + 1, score)) replay.keep(epoch);
    }
  }
  best.restore(context, "session");
  replay.finish();  // L398
  context.diagnostics["session_gate_mean"] = supports_->gate(session).mean().item<double>();
}

torch::Tensor DsnMethod::cosines(const torch::Tensor& embeddings, const torch::Tensor& newest_gate) const {
  return dsn_cosines(*head_, *supports_, embeddings, settings_.gamma, supports_->sessions(), newest_gate);
}

torch::Tensor DsnMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

// Every seen class's cosine with each session's stored gate (Inc_train.py L78-L97), scaled by the
// temperature as in training.
torch::Tensor DsnMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return settings_.temperature * cosines(embeddings);
}

MethodEntry dsn_entry() {
  MethodEntry entry{"dsn",
                    "DSN: cosine head on a projection fc1; sessions add a gated support branch and a head, trained on "
                    "the shots and on features drawn from every seen class's Gaussian, with distillation",
                    [](const ParameterSet& params) { return std::make_unique<DsnMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const DsnSettings dsn = DsnSettings::from(read);
    StageWork sessions = session_work(sizes, 0);
    // 0.21 head steps per class and epoch: fitted on simtex, fast, seed 1 (docs/profiling.md).
    sessions.head_steps = gaussian_replay_head_steps(sizes, dsn.session_epochs, dsn.session_batch, 0.21, [&](int session) {
      return dsn.base_samples * sizes.base_classes_before(session) + dsn.old_samples * sizes.novel_classes_before(session) +
             (dsn.new_samples + sizes.shot) * sizes.way;
    });
    // Gaussians of the base classes, then validation.
    return std::vector<StageWork>{pretraining_work(read, sizes), base_embedding_work(sizes), sessions};
  };
  entry.profile_defaults = pretraining_profiles();
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.session_only_parameters = {"dsn_gamma",       "dsn_session_epochs", "dsn_session_lr",
                                   "dsn_session_batch", "dsn_refresh_every", "dsn_new_samples",
                                   "dsn_old_samples", "dsn_base_samples",  "dsn_sample_k",
                                   "dsn_top_k"};
  return entry;
}

}  // namespace fscil
