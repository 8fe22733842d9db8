// OrCo's parts on their own: pseudo-targets, the contrastive, orthogonality and cross-entropy
// losses, target perturbation, target assignment, the masked views, the session learning-rate
// schedule and the replay memory's choice of base exemplars.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "methods/common/masked_view.h"
#include "methods/orco/orco_losses.h"
#include "methods/orco/orco_settings.h"
#include "methods/orco/pseudo_targets.h"
#include "methods/orco/replay_memory.h"

namespace fscil {
namespace {

namespace F = torch::nn::functional;

double mean_pairwise_cosine(const torch::Tensor& unit) {
  const std::int64_t n = unit.size(0);
  const torch::Tensor cosine = unit.matmul(unit.t());
  return ((cosine.sum() - cosine.diagonal().sum()) / (n * (n - 1))).item<double>();
}

TEST(OrcoPseudoTargets, OptimisationSpreadsThemAndKeepsThemUnitNorm) {
  std::mt19937_64 start_generator(5), optimised_generator(5);
  // 30 targets in 8 dimensions cannot all be orthogonal: the optimum has a negative mean cosine.
  const torch::Tensor start = make_pseudo_targets(30, 8, 0, 1.0, start_generator);
  const torch::Tensor optimised = make_pseudo_targets(30, 8, 300, 1.0, optimised_generator);
  EXPECT_TRUE(torch::allclose(start.norm(2, 1), torch::ones({30}), 0, 1e-5));
  EXPECT_TRUE(torch::allclose(optimised.norm(2, 1), torch::ones({30}), 0, 1e-5));
  EXPECT_LT(mean_pairwise_cosine(optimised), mean_pairwise_cosine(start));
  EXPECT_LT(mean_pairwise_cosine(optimised), -0.02);  // the optimum is -1/29 = -0.034
  EXPECT_LT(spread_loss(optimised).item<double>(), spread_loss(start).item<double>());
}

// The loss written as scalar loops straight from the paper's formula.
double supcon_by_loops(const torch::Tensor& views, const std::vector<int>& labels, double temperature) {
  const std::int64_t n = views.size(0), v = views.size(1);
  std::vector<torch::Tensor> anchors;
  std::vector<int> anchor_labels;
  for (std::int64_t view = 0; view < v; ++view) {
    for (std::int64_t i = 0; i < n; ++i) {
      anchors.push_back(views[i][view]);
      anchor_labels.push_back(labels[static_cast<std::size_t>(i)]);
    }
  }
  double total = 0;
  int counted = 0;
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    double denominator = 0;
    for (std::size_t b = 0; b < anchors.size(); ++b) {
      if (b != a) denominator += std::exp(anchors[a].dot(anchors[b]).item<double>() / temperature);
    }
    double positive_sum = 0;
    int positives = 0;
    for (std::size_t p = 0; p < anchors.size(); ++p) {
      if (p == a || anchor_labels[p] != anchor_labels[a]) continue;
      positive_sum += anchors[a].dot(anchors[p]).item<double>() / temperature - std::log(denominator);
      ++positives;
    }
    if (positives == 0) continue;
    total += -positive_sum / positives;
    ++counted;
  }
  return total / counted;
}

TEST(OrcoLosses, SupervisedContrastiveEqualsTheFormulaWrittenAsLoops) {
  torch::manual_seed(2);
  const torch::Tensor views = F::normalize(torch::randn({5, 2, 6}, torch::kDouble), F::NormalizeFuncOptions().dim(2));
  const std::vector<int> labels = {0, 1, 0, 2, 1};
  const double expected = supcon_by_loops(views, labels, 0.5);
  const torch::Tensor label_tensor = torch::tensor(std::vector<std::int64_t>{0, 1, 0, 2, 1});
  EXPECT_NEAR(supervised_contrastive_loss(views, label_tensor, 0.5).item<double>(), expected, 1e-9);
}

TEST(OrcoLosses, SupervisedContrastiveIsLowerWhenClassesClusterApart) {
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{0, 0, 1, 1});
  const torch::Tensor east = torch::tensor({1.0, 0.0}), north = torch::tensor({0.0, 1.0});
  const torch::Tensor clustered = torch::stack({torch::stack({east, east}), torch::stack({east, east}),
                                                torch::stack({north, north}), torch::stack({north, north})});
  const torch::Tensor mixed = torch::stack({torch::stack({east, north}), torch::stack({north, east}),
                                            torch::stack({east, north}), torch::stack({north, east})});
  EXPECT_LT(supervised_contrastive_loss(clustered, labels, 0.1).item<double>(),
            supervised_contrastive_loss(mixed, labels, 0.1).item<double>());
}

TEST(OrcoLosses, OrthogonalityIsTheSpreadOfBatchClassMeansAbsentTargetsAndFreeTargets) {
  torch::manual_seed(4);
  const torch::Tensor projections = torch::randn({6, 4});
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{2, 0, 2, 0, 0, 2});
  const torch::Tensor assigned = F::normalize(torch::randn({3, 4}), F::NormalizeFuncOptions().dim(1));
  const torch::Tensor free = F::normalize(torch::randn({2, 4}), F::NormalizeFuncOptions().dim(1));
  const torch::Tensor unit = F::normalize(projections, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor class0 = unit.index({labels == 0}).mean(0), class2 = unit.index({labels == 2}).mean(0);
  // Class 1 is not in the batch, so its target joins; classes 0 and 2 come as batch means.
  const torch::Tensor expected = spread_loss(torch::cat({torch::stack({class0, class2}), assigned.slice(0, 1, 2), free}));
  const torch::Tensor got = orthogonality_loss(projections, labels, assigned, torch::arange(3), free);
  EXPECT_NEAR(got.item<double>(), expected.item<double>(), 1e-6);
  // Spread by hand for two orthogonal directions: each row is log(e^1 + e^0).
  EXPECT_NEAR(spread_loss(torch::eye(2)).item<double>(), std::log(std::exp(1.0) + 1.0), 1e-6);
}

TEST(OrcoLosses, SessionOrthogonalitySeesTheNewClassesSamplesOnly) {
  torch::manual_seed(6);
  const torch::Tensor projections = torch::randn({6, 4}).requires_grad_();
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{0, 3, 1, 3, 4, 0});  // 3, 4 are new
  const torch::Tensor assigned = F::normalize(torch::randn({5, 4}), F::NormalizeFuncOptions().dim(1));
  const torch::Tensor free = F::normalize(torch::randn({2, 4}), F::NormalizeFuncOptions().dim(1));
  const torch::Tensor targets_of = torch::arange(5);
  const torch::Tensor novel = labels >= 3;
  const torch::Tensor got = orthogonality_loss_from(3, projections, labels, assigned, targets_of, free);
  const torch::Tensor expected =
      orthogonality_loss(projections.index({novel}), labels.index({novel}), assigned, targets_of, free);
  EXPECT_NEAR(got.item<double>(), expected.item<double>(), 1e-7);
  got.backward();
  const torch::Tensor gradient_norms = projections.grad().norm(2, 1);
  for (std::int64_t i = 0; i < 6; ++i) {
    if (novel[i].item<bool>()) {
      EXPECT_GT(gradient_norms[i].item<double>(), 0) << "row " << i;
    } else {
      EXPECT_EQ(gradient_norms[i].item<double>(), 0) << "row " << i;
    }
  }
  // From class 0 it is the whole batch's; with no new sample in the batch it is zero.
  EXPECT_NEAR(orthogonality_loss_from(0, projections, labels, assigned, targets_of, free).item<double>(),
              orthogonality_loss(projections, labels, assigned, targets_of, free).item<double>(), 1e-7);
  EXPECT_EQ(orthogonality_loss_from(5, projections, labels, assigned, targets_of, free).item<double>(), 0.0);
}

TEST(OrcoLosses, SplitCrossEntropyWeighsBaseAndNewSamplesApartAndSendsGradientOnlyThroughItsOwnRows) {
  torch::manual_seed(8);
  const torch::Tensor logits = torch::randn({6, 5}).requires_grad_();
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{0, 3, 1, 4, 2, 3});
  const torch::Tensor base = labels < 3;
  const double base_mean = F::cross_entropy(logits.index({base}), labels.index({base})).item<double>();
  const double novel_mean = F::cross_entropy(logits.index({~base}), labels.index({~base})).item<double>();
  EXPECT_NEAR(split_cross_entropy(logits, labels, 3, 0.6, 0.5).item<double>(), 0.6 * base_mean + 0.5 * novel_mean,
              1e-6);

  for (const auto& [base_weight, novel_weight] : {std::pair{0.5, 0.0}, std::pair{0.0, 0.5}}) {
    if (logits.grad().defined()) logits.grad().zero_();
    split_cross_entropy(logits, labels, 3, base_weight, novel_weight).backward();
    const torch::Tensor moved = logits.grad().abs().sum(1) > 0;
    EXPECT_TRUE(torch::equal(moved, base_weight > 0 ? base : ~base)) << base_weight << " " << novel_weight;
  }
  // Weight 0 on both, or no sample on the weighted side: nothing.
  EXPECT_EQ(split_cross_entropy(logits, labels, 3, 0.0, 0.0).item<double>(), 0.0);
  EXPECT_EQ(split_cross_entropy(logits, labels, 9, 0.0, 1.0).item<double>(), 0.0);
}

TEST(OrcoSchedule, SessionsWarmUpLinearlyFromThreeTimesTenToTheMinusFiveThenDecayByCosine) {
  ProjectorSchedule session{100, 0.1, 0.0, 1e-4, 0.9, 0.9, 64, 10};
  EXPECT_DOUBLE_EQ(session.rate_at(0), 3e-5);
  EXPECT_NEAR(session.rate_at(1), 3e-5 + (0.1 - 3e-5) / 9, 1e-12);
  EXPECT_NEAR(session.rate_at(9), 0.1, 1e-12);
  EXPECT_NEAR(session.rate_at(10), 0.1, 1e-12);
  EXPECT_NEAR(session.rate_at(55), 0.05, 1e-12);  // half way through the 90 cosine epochs
  EXPECT_NEAR(session.rate_at(99), 0.05 * (1 + std::cos(M_PI * 89 / 90)), 1e-12);
  // Without warmup it is the plain cosine from the first epoch.
  ProjectorSchedule plain = session;
  plain.warmup_epochs = 0;
  EXPECT_DOUBLE_EQ(plain.rate_at(0), 0.1);
  EXPECT_NEAR(plain.rate_at(50), 0.05, 1e-12);
}

// Phase 2 as released (base_schedule Milestone, Network.py L1101-L1102 at 6608340): the rate
// falls tenfold after epochs 60 and 80, so the paper-era 10 epochs run at a constant 0.25.
TEST(OrcoSchedule, ThePhaseTwoProjectorKeepsItsRateForItsTenEpochsAsReleased) {
  const OrcoSettings released = OrcoSettings::from(ParameterSet());
  EXPECT_EQ(released.base.epochs, 10);
  EXPECT_EQ(released.base.decay, ProjectorDecay::milestone);
  for (int epoch = 0; epoch < 10; ++epoch) EXPECT_DOUBLE_EQ(released.base.rate_at(epoch), 0.25) << epoch;
  EXPECT_DOUBLE_EQ(released.base.rate_at(59), 0.25);
  EXPECT_NEAR(released.base.rate_at(60), 0.025, 1e-15);
  EXPECT_NEAR(released.base.rate_at(80), 0.0025, 1e-15);
  ParameterSet cosine;
  cosine.set("orco_base_schedule", "cosine");
  const ProjectorSchedule decayed = OrcoSettings::from(cosine).base;
  EXPECT_NEAR(decayed.rate_at(5), 1e-5 + (0.25 - 1e-5) / 2, 1e-12);
  // The sessions keep their warm-up and cosine.
  EXPECT_EQ(released.session.decay, ProjectorDecay::cosine);
}

// 2 classes: class 0 from 8 recordings of 4 consecutive segments, class 1 from 2 recordings of 10.
SessionData segmented_base() {
  SessionData base;
  std::vector<std::int64_t> labels;
  for (int recording = 0; recording < 10; ++recording) {
    const int segments = recording < 8 ? 4 : 10;
    for (int k = 0; k < segments; ++k) {
      labels.push_back(recording < 8 ? 0 : 1);
      base.recordings.push_back(recording);
    }
  }
  base.labels = torch::tensor(labels);
  base.features = torch::arange(static_cast<std::int64_t>(labels.size())).to(torch::kFloat).view({-1, 1, 1, 1});
  base.new_classes = {0, 1};
  return base;
}

std::vector<std::set<std::int64_t>> recordings_per_class(const ReplayMemory& memory, const SessionData& base) {
  std::vector<std::set<std::int64_t>> recordings(2);
  const torch::Tensor rows = memory.features().flatten().to(torch::kLong);
  for (std::int64_t i = 0; i < rows.size(0); ++i) {
    const std::int64_t row = rows[i].item<std::int64_t>();
    recordings[static_cast<std::size_t>(base.labels[row].item<std::int64_t>())].insert(
        base.recordings[static_cast<std::size_t>(row)]);
  }
  return recordings;
}

TEST(OrcoReplayMemory, BaseExemplarsComeFromAsManyDistinctRecordingsAsTheClassHasUpToFive) {
  const SessionData base = segmented_base();
  std::mt19937_64 generator(1);
  ReplayMemory memory;
  memory.keep_base_exemplars(base, 2, 5, ExemplarSource::recordings, generator);
  ASSERT_EQ(memory.samples(), 10);
  EXPECT_EQ(memory.labels().eq(0).sum().item<std::int64_t>(), 5);
  const auto spread = recordings_per_class(memory, base);
  EXPECT_EQ(spread[0].size(), 5u);  // min(5, 8)
  EXPECT_EQ(spread[1].size(), 2u);  // min(5, 2): both, then round again
  EXPECT_EQ(std::set<float>(memory.features().data_ptr<float>(), memory.features().data_ptr<float>() + 10).size(),
            10u) << "no segment twice";

  // The same seed picks the same; another seed other ones.
  std::mt19937_64 same(1), other(2);
  ReplayMemory again, elsewhere;
  again.keep_base_exemplars(base, 2, 5, ExemplarSource::recordings, same);
  elsewhere.keep_base_exemplars(base, 2, 5, ExemplarSource::recordings, other);
  EXPECT_TRUE(torch::equal(again.features(), memory.features()));
  EXPECT_FALSE(torch::equal(elsewhere.features(), memory.features()));

  // The reference's "first five": consecutive segments, two recordings of class 0.
  ReplayMemory first;
  first.keep_base_exemplars(base, 2, 5, ExemplarSource::first, generator);
  EXPECT_EQ(recordings_per_class(first, base)[0], (std::set<std::int64_t>{0, 1}));
}

TEST(OrcoLosses, PerturbedTargetsKeepTheirLabelsStayUnitAndCycleWhenTooFew) {
  std::mt19937_64 generator(8);
  const torch::Tensor targets = F::normalize(torch::randn({3, 5}), F::NormalizeFuncOptions().dim(1));
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{10, 11, 12});
  const PerturbedTargets exact = perturb_targets(targets, labels, 7, 0.0, 0.5, generator);
  ASSERT_EQ(exact.views.sizes(), (std::vector<std::int64_t>{7, 2, 5}));
  for (std::int64_t i = 0; i < 7; ++i) {
    const std::int64_t row = exact.labels[i].item<std::int64_t>() - 10;
    EXPECT_TRUE(torch::allclose(exact.views[i][0], targets[row], 0, 1e-6));
    EXPECT_TRUE(torch::allclose(exact.views[i][1], targets[row], 0, 1e-6));
  }
  // The first three draws are a permutation: every target before any repeats.
  EXPECT_EQ(std::get<0>(torch::_unique(exact.labels.slice(0, 0, 3))).size(0), 3);
  const PerturbedTargets noisy = perturb_targets(targets, labels, 3, 0.5, 0.5, generator);
  EXPECT_TRUE(torch::allclose(noisy.views.norm(2, 2), torch::ones({3, 2}), 0, 1e-5));
  EXPECT_FALSE(torch::allclose(noisy.views.select(1, 0), noisy.views.select(1, 1)));
}

TEST(OrcoAssignment, ClassesGoToTheirClosestFreeTargetsWithoutSharing) {
  const torch::Tensor targets = torch::eye(4);
  // Class 0 points at target 2, class 1 mostly at target 2 too but also at target 3.
  const torch::Tensor means = torch::tensor({{0.0, 0.0, 1.0, 0.0}, {0.0, 0.0, 0.9, 0.6}});
  EXPECT_EQ(assign_to_targets(means, targets, {0, 1, 2, 3}), (std::vector<std::int64_t>{2, 3}));
  // With target 2 taken, class 0 falls back to the best remaining one.
  EXPECT_EQ(assign_to_targets(means.slice(0, 0, 1), targets, {0, 1, 3}).size(), 1u);
  EXPECT_EQ(assign_to_targets(means.slice(0, 1, 2), targets, {0, 1, 3}), (std::vector<std::int64_t>{3}));
}

TEST(MaskedView, MasksOneTimeBandAndOneMelBandWithTheSampleMean) {
  std::mt19937_64 generator(1);
  const torch::Tensor features = torch::arange(2 * 3 * 10 * 20, torch::kFloat).view({2, 3, 10, 20});
  const torch::Tensor view = masked_view(features, 0.5, 0.5, generator);
  ASSERT_EQ(view.sizes(), features.sizes());
  for (std::int64_t n = 0; n < 2; ++n) {
    const torch::Tensor changed = view[n] != features[n];  // 3 x 10 x 20
    const float mean = features[n].mean().item<float>();
    EXPECT_TRUE(torch::all(view[n].index({changed}) == mean).item<bool>());
    // Changed cells form whole time columns or whole Mel rows, the same on every channel.
    EXPECT_TRUE(torch::equal(changed[0], changed[1]));
    const torch::Tensor columns = changed[0].all(0), rows = changed[0].all(1);
    EXPECT_TRUE(torch::equal(changed[0], columns.view({1, 20}) | rows.view({10, 1})));
    EXPECT_LE(columns.sum().item<std::int64_t>(), 10);
    EXPECT_LE(rows.sum().item<std::int64_t>(), 5);
  }
  std::mt19937_64 unmasked(1);
  EXPECT_TRUE(torch::equal(masked_view(features, 0.0, 0.0, unmasked), features));
}

}  // namespace
}  // namespace fscil
