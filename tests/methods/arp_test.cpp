// ARP's parts against hand-computed values, its episode, its early stop and a session's effect on a
// tiny protocol.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "methods/arp/arp_episode.h"
#include "methods/arp/arp_method.h"
#include "methods/arp/refinement_attention.h"
#include "methods/arp/relation_head.h"
#include "methods/arp/repeated_batch_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/module_state.h"
#include "methods/common/resnet18.h"
#include "metrics/convergence.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

namespace F = torch::nn::functional;

RefinementAttention identity_attention(std::int64_t dim) {
  RefinementAttention attention(dim);
  torch::NoGradGuard no_grad;
  for (auto* linear : {&attention->query, &attention->key, &attention->value, &attention->out}) {
    (*linear)->weight.copy_(torch::eye(dim));
  }
  return attention;
}

TEST(RefinementAttention, RowsAttendToThemselvesAndTheKeysWithAResidual) {
  // S = [q; k] = [(1, 0); (0, 1)]; scores (1, 0) / sqrt 2 -> softmax (0.669761, 0.330239); plus q.
  RefinementAttention attention = identity_attention(2);
  attention->eval();
  const torch::Tensor refined = attention->forward(torch::tensor({{1.0f, 0.0f}}), torch::tensor({{0.0f, 1.0f}}));
  EXPECT_TRUE(torch::allclose(refined, torch::tensor({{1.669761f, 0.330239f}}), 1e-5)) << refined;
}

TEST(RefinementAttention, DropsOutOnlyInTraining) {
  torch::manual_seed(1);
  RefinementAttention attention(8);
  const torch::Tensor rows = torch::randn({5, 8}), keys = torch::randn({5, 8});
  attention->eval();
  EXPECT_TRUE(torch::equal(attention->forward(rows, keys), attention->forward(rows, keys)));
  attention->train();
  EXPECT_FALSE(torch::equal(attention->forward(rows, keys), attention->forward(rows, keys)));
}

TEST(RefinementAttention, ATasksRowsAreTheMeansAndGetNoGradient) {
  // Rows 0 and 2 are replaced by the means and zeroed among the keys: the learned rows 0 and 2 reach
  // nothing, the means and row 1 everything.
  RefinementAttention attention = identity_attention(2);
  attention->eval();
  const torch::Tensor rows = torch::tensor({{1.0f, 2.0f}, {3.0f, -1.0f}, {0.5f, 0.5f}}, torch::requires_grad());
  const torch::Tensor means = torch::tensor({{-1.0f, 1.0f}, {2.0f, 0.0f}}, torch::requires_grad());
  const torch::Tensor refined = refine_task_rows(attention, rows, torch::tensor({0, 2}), means);
  refined.pow(2).sum().backward();
  EXPECT_EQ(rows.grad()[0].abs().sum().item<double>(), 0.0);
  EXPECT_EQ(rows.grad()[2].abs().sum().item<double>(), 0.0);
  EXPECT_GT(rows.grad()[1].abs().sum().item<double>(), 0.0);
  EXPECT_GT(means.grad().abs().min().item<double>(), 0.0);
  // With no attention at all (zero W_o), a task's rows are the means and the others the rows.
  {
    torch::NoGradGuard no_grad;
    attention->out->weight.zero_();
  }
  const torch::Tensor plain = refine_task_rows(attention, rows, torch::tensor({0, 2}), means);
  EXPECT_TRUE(torch::equal(plain, torch::tensor({{-1.0f, 1.0f}, {3.0f, -1.0f}, {2.0f, 0.0f}})));
}

TEST(RefinementAttention, AtTestTheNovelRowsAreQueriesWithZeroKeys) {
  // Base row b = (1, 0), novel mean n = (0, 1). S = [b; n; b; 0].
  // b: scores (1, 0, 1, 0) / sqrt 2 -> weights (e, 1, e, 1) / (2e + 2), e = exp(1/sqrt 2) = 2.028115;
  //    attended = (2e, 1) / (2e + 2) = (0.669761, 0.165119); plus b.
  // n: scores (0, 1, 0, 0) / sqrt 2 -> weights (1, e, 1, 1) / (e + 3); attended (2, e) / (e + 3)
  //    = (0.397763, 0.403355); plus n.
  RefinementAttention attention = identity_attention(2);
  attention->train();
  const torch::Tensor rows = torch::tensor({{1.0f, 0.0f}, {0.0f, 1.0f}});
  const torch::Tensor refined = refine_seen_rows(attention, rows, 1);
  EXPECT_TRUE(torch::allclose(refined, torch::tensor({{1.669761f, 0.165119f}, {0.397763f, 1.403355f}}), 1e-5))
      << refined;
  EXPECT_TRUE(attention->is_training());  // scored in eval mode, and left as it was
  // Every row a base row: the rows are queries and keys, as in base training's diagnostic.
  attention->eval();
  EXPECT_TRUE(torch::equal(refine_seen_rows(attention, rows, 2), attention->forward(rows, rows)));
}

TEST(RelationHead, ScoresTheConcatenatedUnitPairAsReleased) {
  torch::manual_seed(2);
  RelationHead head(4, 6);
  head->eval();  // running statistics and no dropout: one pair's logit does not depend on the others
  {
    torch::NoGradGuard no_grad;
    for (auto* norm : {&head->pair_norm, &head->hidden_norm}) {
      (*norm)->running_mean.uniform_(-0.5, 0.5);
      (*norm)->running_var.uniform_(0.5, 2.0);
    }
  }
  const torch::Tensor embeddings = torch::randn({3, 4}), rows = torch::randn({5, 4});
  const torch::Tensor logits = head->forward(embeddings, rows);
  // The release's form: cat(unit(x_i), unit(p_c)) through the layers, pair by pair.
  const torch::Tensor x = F::normalize(embeddings, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor p = F::normalize(rows, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor pairs = torch::cat({x.unsqueeze(1).expand({3, 5, 4}), p.unsqueeze(0).expand({3, 5, 4})}, 2).view({15, 8});
  torch::Tensor h = head->pair_norm->forward(head->pair->forward(pairs)).relu();
  h = head->hidden_norm->forward(head->hidden->forward(h)).relu();
  EXPECT_TRUE(torch::allclose(logits, head->score->forward(h).view({3, 5}), 1e-5, 1e-6));
  // Both sides are normalised: scale does not count, and a zero row is a zero half, not NaN.
  EXPECT_TRUE(torch::allclose(head->forward(3 * embeddings, 0.5 * rows), logits, 1e-5, 1e-6));
  EXPECT_TRUE(torch::isfinite(head->forward(embeddings, torch::zeros({2, 4}))).all().item<bool>());
  EXPECT_EQ(head->hidden->weight.sizes(), (std::vector<std::int64_t>{64, 6}));
}

TEST(RepeatedBatchStatistics, OnePassOfTheEncoderUpdatesItsStatisticsAsThreeDo) {
  torch::manual_seed(3);
  RunContext context = tiny_context(3);
  ResNet18Encoder three(encoder_options(context)), once(encoder_options(context));
  {
    torch::NoGradGuard no_grad;
    for (std::size_t i = 0; i < three->parameters().size(); ++i) once->parameters()[i].copy_(three->parameters()[i]);
  }
  const torch::Tensor x = torch::randn({8, 2, 4, 4}) * 2 + 1;
  torch::Tensor expected;
  for (int pass = 0; pass < 3; ++pass) expected = three->forward(x);
  torch::Tensor output;
  {
    const RepeatedBatchStatistics repeated(*once, 3);
    output = once->forward(x);
  }
  EXPECT_TRUE(torch::allclose(output, expected, 1e-5, 1e-6));
  const auto want = three->named_buffers(), got = once->named_buffers();
  ASSERT_EQ(want.size(), got.size());
  ASSERT_GT(want.size(), 20u);  // bn0, the stem and every block's norms, downsample ones included
  for (const auto& item : want) {
    EXPECT_TRUE(torch::allclose(got[item.key()].to(torch::kDouble), item.value().to(torch::kDouble), 1e-5, 1e-6))
        << item.key();
  }
  // Afterwards every norm is back at momentum 0.1: 1 - 0.9^3 = 0.271 held only for the pass.
  for (const auto& child : once->modules()) {
    if (auto norm = std::dynamic_pointer_cast<torch::nn::BatchNorm2dImpl>(child)) {
      EXPECT_NEAR(norm->options.momentum().value(), 0.1, 1e-12);
    }
  }
}

TEST(ArpEpisode, DrawsDistinctClassesTheirShotsAndEachTasksClasses) {
  const SessionData base = tiny_base();
  const ArpEpisodeSampler sampler(base, 6, 2, 3, 2);  // way 2, shot 3, 2 tasks: 4 classes x 3
  std::mt19937_64 generator(7);
  const ArpEpisode episode = sampler.draw(generator);
  ASSERT_EQ(episode.classes.size(0), 4);
  ASSERT_EQ(episode.features.size(0), 12);
  std::set<std::int64_t> classes;
  for (std::int64_t c = 0; c < 4; ++c) {
    const std::int64_t label = episode.classes[c].item<std::int64_t>();
    classes.insert(label);
    // Class-major: rows 3c..3c+2 are samples of that class.
    const torch::Tensor expected = base.features.gather(torch::nonzero(base.labels == label).view(-1));
    for (std::int64_t s = 0; s < 3; ++s) {
      const torch::Tensor row = episode.features[3 * c + s];
      EXPECT_TRUE((expected == row).flatten(1).all(1).any().item<bool>()) << "row " << 3 * c + s;
    }
  }
  EXPECT_EQ(classes.size(), 4u);
  // Shots without replacement: the 12 rows are 12 different samples.
  EXPECT_EQ(std::get<0>(torch::unique_dim(episode.features.flatten(1), 0)).size(0), 12);
  ASSERT_EQ(episode.task_slots.size(), 2u);
  for (const torch::Tensor& slots : episode.task_slots) {
    ASSERT_EQ(slots.size(0), 2);
    EXPECT_NE(slots[0].item<std::int64_t>(), slots[1].item<std::int64_t>());
    EXPECT_LT(slots.max().item<std::int64_t>(), 4);
  }
  // The support means are per class, in episode order.
  const torch::Tensor embeddings = torch::arange(12, torch::kFloat).view({12, 1});
  EXPECT_TRUE(torch::equal(support_means(embeddings, 3), torch::tensor({{1.0f}, {4.0f}, {7.0f}, {10.0f}})));
  // A protocol with fewer base classes than way + tasks gives all of them.
  EXPECT_EQ(ArpEpisodeSampler(base, 6, 5, 5, 3).draw(generator).classes.size(0), 6);
}

ParameterSet tiny_arp_params() {
  ParameterSet params;
  params.set("pretrain_epochs", "2");
  params.set("batch_size", "32");
  params.set("arp_way", "2");
  params.set("arp_tasks", "2");
  return params;
}

std::vector<double> logged(const RunContext& context, const std::string& value) {
  std::vector<double> values;
  for (const auto& epoch : context.training_log) {
    if (epoch.values.count(value) != 0) values.push_back(epoch.values.at(value));
  }
  return values;
}

TEST(ArpMethod, StopsOnceTheValidationLossHasNotFallenForMoreThanTheTolerance) {
  torch::manual_seed(4);
  const SessionData validation = tiny_validation();
  ParameterSet params = tiny_arp_params();
  params.set("pretrain_epochs", "12");
  params.set("arp_early_stop_tol", "0");
  ArpMethod method(params);
  RunContext context = tiny_context(4);
  context.validation = &validation;
  method.train_base(tiny_base(), context);
  const std::vector<double> losses = logged(context, "validation_ce");
  ASSERT_EQ(losses.size(), context.training_log.size());
  // Tolerance 0: training ends at the first epoch without a new lowest loss (a loss on random
  // labels that falls 12 epochs in a row does not happen).
  int without_lower = 0;
  double lowest = losses.front();
  for (std::size_t e = 1; e < losses.size(); ++e) {
    without_lower = losses[e] < lowest ? 0 : without_lower + 1;
    lowest = std::min(lowest, losses[e]);
    if (e + 1 < losses.size()) EXPECT_EQ(without_lower, 0) << "epoch " << e + 1 << " should have stopped";
  }
  ASSERT_LT(losses.size(), 12u);
  EXPECT_EQ(without_lower, 1);
  EXPECT_EQ(context.diagnostics.at("base_stopped_epoch"), static_cast<double>(losses.size()));
  EXPECT_EQ(context.diagnostics.count("base_kept_epoch"), 0u);  // --selection last keeps the stopped epoch
}

TEST(ArpMethod, ValidationSelectionKeepsTheLowestLossAndLastScoresOnlyTheBaseValidationAccuracy) {
  torch::manual_seed(5);
  const SessionData validation = tiny_validation();
  ParameterSet params = tiny_arp_params();
  params.set("pretrain_epochs", "4");
  ArpMethod selected(params);
  RunContext context = tiny_context(5);
  context.validation = &validation;
  context.selection = EpochSelection::validation;
  selected.train_base(tiny_base(), context);
  const std::vector<double> losses = logged(context, "validation_ce");
  ASSERT_EQ(losses.size(), 4u);
  const auto lowest = std::min_element(losses.rbegin(), losses.rend());  // ties to the later epoch
  EXPECT_EQ(context.diagnostics.at("base_kept_epoch"), static_cast<double>(losses.rend() - lowest));
  EXPECT_NEAR(context.diagnostics.at("base_selection_score"), -*lowest, 1e-9);
  // The kept epoch's loss is what the restored model scores.
  const torch::Tensor logits = selected.classify(selected.embed_rows(validation.features));
  EXPECT_NEAR(F::cross_entropy(logits, validation.labels).item<double>(), *lowest, 1e-5);

  // Under last with 4 epochs and tolerance 50 no stop can happen: no validation loss, only the
  // plain rows' accuracy every epoch (the training verdict's input), the last one the model's.
  torch::manual_seed(5);
  ArpMethod last(params);
  RunContext last_context = tiny_context(5);
  last_context.validation = &validation;
  last.train_base(tiny_base(), last_context);
  EXPECT_TRUE(logged(last_context, "validation_ce").empty());
  EXPECT_EQ(last_context.training_log.size(), 4u);
  const std::vector<double> accuracy = logged(last_context, kBaseValidationKey);
  ASSERT_EQ(accuracy.size(), 4u);
  EXPECT_NEAR(accuracy.back(), last.accuracy_on(validation), 1e-9);
}

// The release's optimiser (main_SPPR_Nsynth.py L60; Utils.py L130-L137): no momentum, the rate
// by a cosine over every step, the shared keys still overriding it.
TEST(ArpMethod, TrainsWithPlainSgdAndAPerStepCosineAsReleased) {
  const ArpSettings released = ArpSettings::from(ParameterSet());
  EXPECT_EQ(released.base.momentum, 0.0);
  EXPECT_FALSE(released.base.nesterov);
  EXPECT_EQ(released.base.decay, LearningRateDecay::cosine);
  ParameterSet stepped;
  stepped.set("lr_decay", "step");
  stepped.set("momentum", "0.9");
  EXPECT_EQ(ArpSettings::from(stepped).base.decay, LearningRateDecay::step);
  EXPECT_EQ(ArpSettings::from(stepped).base.momentum, 0.9);
  // 150 samples in batches of 64: 3 steps an epoch; the logged rate is each epoch's last step's.
  ParameterSet params = tiny_arp_params();
  params.set("pretrain_epochs", "2");
  params.set("batch_size", "64");
  torch::manual_seed(3);
  ArpMethod method(params);
  RunContext context = tiny_context(3);
  method.train_base(tiny_base(), context);
  const std::vector<double> rates = logged(context, "lr");
  ASSERT_EQ(rates.size(), 2u);
  const double lr = ArpSettings::from(params).base.learning_rate;
  EXPECT_NEAR(rates[0], 0.5 * lr * (1 + std::cos(M_PI * 2 / 6)), 1e-12);
  EXPECT_NEAR(rates[1], 0.5 * lr * (1 + std::cos(M_PI * 5 / 6)), 1e-12);
}

TEST(ArpMethod, BaseTrainingMovesTheEncoderTheRowsAndTheRelationHead) {
  ParameterSet untrained_params = tiny_arp_params();
  untrained_params.set("pretrain_epochs", "0");
  torch::manual_seed(7);
  ArpMethod untrained(untrained_params);
  RunContext untrained_context = tiny_context(7);
  untrained.train_base(tiny_base(), untrained_context);
  torch::manual_seed(7);
  ArpMethod trained(tiny_arp_params());
  RunContext context = tiny_context(7);
  trained.train_base(tiny_base(), context);
  const MethodState before = untrained.save_state(), after = trained.save_state();
  for (const std::string name : {"encoder.conv1.weight", "rows.rows", "relation.pair.weight", "relation.hidden.weight",
                                 "relation.score.weight"}) {
    ASSERT_EQ(before.count(name), 1u) << name;
    EXPECT_FALSE(torch::equal(before.at(name), after.at(name))) << name << " did not train";
  }
  // The refinement attention trains too: its change of the rows is recorded beside the rows' norm.
  EXPECT_GT(context.diagnostics.at("refinement_norm"), 0.0);
  EXPECT_GT(context.diagnostics.at("base_row_norm"), 0.0);
  EXPECT_EQ(untrained_context.diagnostics.at("base_row_norm"), 0.0);
}

TEST(ArpMethod, LearnsBaseRowsFromZeroAndASessionAddsTheShotMeansOnly) {
  torch::manual_seed(6);
  ArpMethod method(tiny_arp_params());
  RunContext context = tiny_context(6);
  method.train_base(tiny_base(), context);
  const MethodState base = method.save_state();
  EXPECT_GT(base.at("rows.rows").slice(0, 0, 6).abs().min().item<double>(), 0.0);  // every base row learned
  EXPECT_EQ(base.at("rows.rows").slice(0, 6).abs().max().item<double>(), 0.0);
  const SessionData support = tiny_support(6);
  method.learn_session(support, context);
  const MethodState after = method.save_state();
  EXPECT_TRUE(torch::allclose(after.at("rows.rows").slice(0, 6, 8),
                              class_means(method.embed_rows(support.features), support.labels, {6, 7}), 1e-5, 1e-6));
  for (const auto& [name, tensor] : base) {
    if (name == "rows.rows" || name == "seen_classes.count") continue;
    EXPECT_TRUE(torch::equal(after.at(name), tensor)) << name << " changed in a session";
  }
  EXPECT_TRUE(torch::equal(after.at("rows.rows").slice(0, 0, 6), base.at("rows.rows").slice(0, 0, 6)));
  EXPECT_TRUE(torch::equal(after.at("rows.rows").slice(0, 8), base.at("rows.rows").slice(0, 8)));
  // Test scores every seen row with the relation head, deterministically (eval mode).
  const torch::Tensor embeddings = method.embed_rows(support.features);
  const torch::Tensor logits = method.classify(embeddings);
  EXPECT_EQ(logits.sizes(), (std::vector<std::int64_t>{10, 8}));
  EXPECT_TRUE(torch::equal(logits, method.classify(embeddings)));
  // Under arp_test_rows=refined the same training (the option is read at test only) keeps the
  // attention in the model, and test scores the refined seen rows instead.
  EXPECT_EQ(after.count("attention.query.weight"), 0u);  // plain: not part of the model
  ParameterSet refined_params = tiny_arp_params();
  refined_params.set("arp_test_rows", "refined");
  torch::manual_seed(6);
  ArpMethod refined(refined_params);
  RunContext refined_context = tiny_context(6);
  refined.train_base(tiny_base(), refined_context);
  refined.learn_session(support, refined_context);
  const MethodState refined_state = refined.save_state();
  EXPECT_TRUE(torch::equal(refined_state.at("rows.rows"), after.at("rows.rows")));
  const torch::Tensor rows = refined_state.at("rows.rows").slice(0, 0, 8);
  torch::Tensor expected;
  {
    torch::NoGradGuard no_grad;
    torch::Tensor keys = rows.clone();
    keys.slice(0, 6).zero_();
    RefinementAttention attention(rows.size(1));
    take_module(refined_state, "attention.", *attention);
    attention->eval();
    RelationHead relation(rows.size(1));
    take_module(refined_state, "relation.", *relation);
    relation->eval();
    expected = relation->forward(embeddings, attention->forward(rows, keys));
  }
  const torch::Tensor refined_logits = refined.classify(embeddings);
  EXPECT_TRUE(torch::allclose(refined_logits, expected, 1e-5, 1e-6));
  EXPECT_FALSE(torch::allclose(refined_logits, logits, 1e-3, 1e-3));
}

}  // namespace
}  // namespace fscil
