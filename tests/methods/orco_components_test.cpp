// OrCo's parts on their own: pseudo-targets, the contrastive and orthogonality losses, target
// perturbation, target assignment and the masked views.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/common/masked_view.h"
#include "methods/orco/orco_losses.h"
#include "methods/orco/pseudo_targets.h"

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
