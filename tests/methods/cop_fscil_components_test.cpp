// The CoP-FSCIL components on their own: CPI's view and statistic transfer, PCQA's Householder
// quotient and its invariance loss, PSPC's stability weights.
#include <gtest/gtest.h>

#include "methods/cop_fscil/context_probe.h"
#include "methods/cop_fscil/quotient_adapter.h"
#include "methods/cop_fscil/stability_calibration.h"

namespace fscil {
namespace {

// The explicit D x D product H(v_m) ... H(v_1) for one sample.
torch::Tensor explicit_q(const torch::Tensor& v) {
  const std::int64_t d = v.size(1);
  torch::Tensor q = torch::eye(d, torch::kDouble);
  for (std::int64_t k = 0; k < v.size(0); ++k) {
    const torch::Tensor u = v[k].view({d, 1});
    q = torch::mm(torch::eye(d, torch::kDouble) - 2 * torch::mm(u, u.t()) / torch::mm(u.t(), u), q);
  }
  return q;
}

TEST(Householder, QIsOrthogonalAndEqualsTheExplicitProduct) {
  torch::manual_seed(1);
  const auto opts = torch::TensorOptions().dtype(torch::kDouble);
  const torch::Tensor v = torch::randn({4, 3, 6}, opts);  // 4 samples, m = 3, D = 6
  const torch::Tensor z = torch::randn({4, 6}, opts);
  const torch::Tensor p = apply_q(v, z);
  EXPECT_TRUE(torch::allclose(p.norm(2, 1), z.norm(2, 1), 1e-9, 1e-9));  // norms kept
  EXPECT_TRUE(torch::allclose(apply_q_transpose(v, p), z, 1e-9, 1e-9));  // Q^T Q = I
  for (std::int64_t i = 0; i < 4; ++i) {
    const torch::Tensor q = explicit_q(v[i]);
    EXPECT_TRUE(torch::allclose(torch::mm(q.t(), q), torch::eye(6, opts), 1e-9, 1e-9));
    EXPECT_TRUE(torch::allclose(p[i], torch::mv(q, z[i]), 1e-9, 1e-9));
  }
}

TEST(QuotientAdapter, KeepsTheInvariantBlockAndDropsTheSensitiveOne) {
  torch::manual_seed(2);
  QuotientAdapter adapter(QuotientAdapterOptions{8, 3, 6});
  const torch::Tensor z = torch::randn({5, 8});
  const torch::Tensor v = adapter->reflections_of(z);
  EXPECT_EQ(v.sizes(), (std::vector<std::int64_t>{5, 3, 8}));
  const auto projection = adapter->project(v, z);
  EXPECT_EQ(projection.invariant.sizes(), (std::vector<std::int64_t>{5, 6}));
  // z_hat = Q^T [p_inv; 0]: projecting it again gives [p_inv; 0] exactly, and its norm is |p_inv|.
  const torch::Tensor again = apply_q(v, projection.quotient);
  EXPECT_TRUE(torch::allclose(again.narrow(1, 0, 6), projection.invariant, 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(again.narrow(1, 6, 2), torch::zeros({5, 2}), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(projection.quotient.norm(2, 1), projection.invariant.norm(2, 1), 1e-4, 1e-5));
}

// With m reflections Q is the identity outside span(v_1..v_m), so at most m of the d_sen dropped
// directions can leave the fixed last coordinates; m >= d_sen can move them all. g's hidden width
// sets its size.
TEST(QuotientAdapter, FewReflectionsDropMostlyFixedCoordinatesAndTheHiddenWidthSetsGsSize) {
  torch::manual_seed(3);
  const torch::Tensor z = torch::randn({40, 16});
  QuotientAdapter few(QuotientAdapterOptions{16, 1, 8});  // d_sen 8, one reflection
  const double off = few->dropped_share_off_fixed_channels(z);
  EXPECT_GT(off, 0.0);
  EXPECT_LE(off, 1.0 / 8 + 1e-6);  // one of the eight directions at most
  QuotientAdapter many(QuotientAdapterOptions{16, 8, 8});
  EXPECT_GT(many->dropped_share_off_fixed_channels(z), off);
  QuotientAdapter none(QuotientAdapterOptions{16, 8, 16});  // nothing dropped
  EXPECT_EQ(none->dropped_share_off_fixed_channels(z), 0.0);

  const auto parameters = [](const QuotientAdapter& adapter) {
    std::int64_t count = 0;
    for (const auto& p : adapter->parameters()) count += p.numel();
    return count;
  };
  EXPECT_EQ(parameters(many), (16 * 16 + 16) + (16 * 8 * 16 + 8 * 16));  // hidden width D
  EXPECT_EQ(parameters(QuotientAdapter(QuotientAdapterOptions{16, 8, 8, 4})), (16 * 4 + 4) + (4 * 8 * 16 + 8 * 16));
}

TEST(ProbeInvarianceLoss, SendsNoGradientThroughTheProbeBranch) {
  const torch::Tensor original = torch::randn({4, 3}, torch::requires_grad());
  const torch::Tensor probes = torch::randn({2, 4, 3}, torch::requires_grad());
  const torch::Tensor loss = probe_invariance_loss(original, probes);
  EXPECT_NEAR(loss.item<double>(), (original.unsqueeze(0) - probes).pow(2).sum(2).mean().item<double>(), 1e-5);
  loss.backward();
  EXPECT_FALSE(probes.grad().defined() && probes.grad().abs().sum().item<double>() > 0);
  EXPECT_GT(original.grad().abs().sum().item<double>(), 0.0);
}

// The three spaces L_PIC can compare in, on a z whose dropped coordinates are made 10 times longer
// (what the encoder can do to lower L_PIC without making p_inv agree): raw p_inv stays, the
// normalised one shrinks, the invariant direction stays; scaling all of z moves raw only.
TEST(PicInvariant, OnlyTheInvariantDirectionIgnoresBothALongerDroppedPartAndZsLength) {
  torch::manual_seed(7);
  QuotientAdapter adapter(QuotientAdapterOptions{16, 4, 12, 0});
  const torch::Tensor z = torch::randn({5, 16});
  const torch::Tensor reflections = adapter->reflections_of(z);
  // z with its dropped part (in Q's coordinates) 10 times longer: Q^T [p_inv; 10 p_sen].
  const torch::Tensor p = apply_q(reflections, z);
  const torch::Tensor stretched = apply_q_transpose(
      reflections, torch::cat({p.slice(1, 0, 12), 10 * p.slice(1, 12)}, 1));
  const auto in = [&](PicSpace space, const torch::Tensor& x) {
    return pic_invariant(adapter->project(reflections, x).invariant, x, space);
  };
  EXPECT_TRUE(torch::allclose(in(PicSpace::raw, stretched), in(PicSpace::raw, z), 1e-4, 1e-5));
  EXPECT_LT(in(PicSpace::normalised, stretched).norm().item<double>(),
            0.5 * in(PicSpace::normalised, z).norm().item<double>());
  EXPECT_TRUE(torch::allclose(in(PicSpace::invariant, stretched), in(PicSpace::invariant, z), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(in(PicSpace::raw, 3 * z), 3 * in(PicSpace::raw, z), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(in(PicSpace::normalised, 3 * z), in(PicSpace::normalised, z), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(in(PicSpace::invariant, 3 * z), in(PicSpace::invariant, z), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(in(PicSpace::invariant, z).norm(2, 1), torch::ones({5}), 1e-4, 1e-5));
}

torch::Tensor ramp_features() {
  // 2 samples, 2 channels, 4 Mel bins, 16 frames; each frame holds its index, so shifts are visible.
  return torch::arange(16).to(torch::kFloat).view({1, 1, 1, 16}).expand({2, 2, 4, 16}).contiguous();
}

TEST(RandomView, EachPerturbationHasItsDocumentedEffect) {
  const torch::Tensor m = ramp_features();
  const double spread = m[0].std().item<double>();
  std::mt19937_64 generator(4);
  // Global bias only: the same offset everywhere in a sample, within +-a_g * std.
  ViewRanges bias_only{0.5, 0, 0, 0, 0};
  const torch::Tensor biased = random_view(m, bias_only, true, generator) - m;
  EXPECT_NEAR((biased[0] - biased[0][0][0][0]).abs().max().item<double>(), 0.0, 1e-5);
  EXPECT_LE(std::abs(biased[0][0][0][0].item<double>()), 0.5 * spread + 1e-5);
  // Tilt only: linear in the Mel bin, from -s to +s, the same in every frame and channel.
  ViewRanges tilt_only{0, 0, 0.5, 0, 0};
  const torch::Tensor tilted = random_view(m, tilt_only, true, generator) - m;
  const double s = tilted[0][0][3][0].item<double>();
  EXPECT_NEAR(tilted[0][0][0][0].item<double>(), -s, 1e-5);
  EXPECT_NEAR(tilted[0][0][1][5].item<double>(), -s / 3, 1e-5);
  EXPECT_NEAR(tilted[0][1][2][9].item<double>(), s / 3, 1e-5);
  // Shift only: content moves by whole frames, vacated frames repeat the edge (not circular).
  ViewRanges shift_only{0, 0, 0, 0, 0.25};
  const torch::Tensor shifted = random_view(m, shift_only, true, generator);
  for (std::int64_t i = 0; i < 2; ++i) {
    const auto row = shifted[i][0][0];
    const double dt = m[i][0][0][8].item<double>() - row[8].item<double>();
    EXPECT_LE(std::abs(dt), 4.0);
    for (std::int64_t t = 0; t < 16; ++t) {
      EXPECT_FLOAT_EQ(row[t].item<float>(), static_cast<float>(std::clamp(t - dt, 0.0, 15.0)));
    }
  }
  // Noise only: zero-mean with standard deviation s_eta * std.
  const torch::Tensor big = torch::randn({1, 4, 64, 64});
  ViewRanges noise_only{0, 0, 0, 0.1, 0};
  const torch::Tensor noise = random_view(big, noise_only, true, generator) - big;
  EXPECT_NEAR(noise.std().item<double>(), 0.1 * big.std().item<double>(), 0.005);
  // Shapes (and so labels, which the view never touches) are preserved.
  EXPECT_EQ(random_view(m, ViewRanges{}, true, generator).sizes(), m.sizes());
}

TEST(RandomView, InStandardisedUnitsTheRangesAreAbsolute) {
  // A map whose own spread is 100: in sample-spread units a bias of at most 0.5 could move it by
  // 50; in standardised units (after bn0) by 0.5 at most.
  const torch::Tensor m = 100 * torch::randn({8, 2, 4, 16});
  std::mt19937_64 generator(9);
  const ViewRanges bias_only{0.5, 0, 0, 0, 0};
  const torch::Tensor standardised = random_view(m, bias_only, false, generator) - m;
  EXPECT_LE(standardised.abs().max().item<double>(), 0.5 + 1e-3);
  const torch::Tensor spread_units = random_view(m, bias_only, true, generator) - m;
  EXPECT_GT(spread_units.abs().max().item<double>(), 1.0);
}

TEST(ContextStatisticBank, ReturnsTheFarthestEntryAndForgetsTheOldest) {
  ContextStatisticBank bank(3);
  bank.push(torch::tensor({{0.0f, 1.0f}, {5.0f, 1.0f}, {1.0f, 1.0f}}));
  EXPECT_TRUE(torch::equal(bank.farthest_from(torch::tensor({0.0f, 1.0f}))[0], torch::tensor({5.0f, 1.0f})));
  EXPECT_TRUE(torch::equal(bank.farthest_from(torch::tensor({6.0f, 1.0f}))[0], torch::tensor({0.0f, 1.0f})));
  bank.push(torch::tensor({{2.0f, 1.0f}}));  // pushes {0, 1} out
  EXPECT_EQ(bank.size(), 3);
  EXPECT_TRUE(torch::equal(bank.farthest_from(torch::tensor({6.0f, 1.0f}))[0], torch::tensor({1.0f, 1.0f})));
  // A batch of queries gets one reference each.
  const torch::Tensor batch = bank.farthest_from(torch::tensor({{6.0f, 1.0f}, {0.0f, 1.0f}}));
  EXPECT_TRUE(torch::equal(batch, torch::tensor({{1.0f, 1.0f}, {5.0f, 1.0f}})));
}

TEST(ContextStatisticBank, RanksCandidatesSoThatSeveralProbesTakeDistinctReferences) {
  ContextStatisticBank bank(4);
  bank.push(torch::tensor({{0.0f, 1.0f}, {5.0f, 1.0f}, {1.0f, 1.0f}, {3.0f, 1.0f}}));
  const torch::Tensor query = torch::tensor({0.0f, 1.0f});
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 0)[0], torch::tensor({5.0f, 1.0f})));
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 1)[0], torch::tensor({3.0f, 1.0f})));
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 2)[0], torch::tensor({1.0f, 1.0f})));
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 9)[0], torch::tensor({0.0f, 1.0f})));  // clamped: the nearest
}

TEST(ContextStatisticBank, StandardisedDistanceStopsOneLevelFromDominating) {
  // Statistic 0 spans 0..100 across the bank, statistic 1 spans 0..1. In raw distance the entry
  // farthest in statistic 0 always wins; standardised, a large move in statistic 1 counts as much.
  ContextStatisticBank bank(3);
  bank.push(torch::tensor({{0.0f, 0.5f}, {100.0f, 0.5f}, {50.0f, 1.0f}}));
  const torch::Tensor query = torch::tensor({60.0f, 0.0f});
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 0, false)[0], torch::tensor({0.0f, 0.5f})));
  EXPECT_TRUE(torch::equal(bank.farthest_from(query, 0, true)[0], torch::tensor({50.0f, 1.0f})));
}

TEST(StatisticTransfer, MovesChannelStatisticsTowardTheReference) {
  torch::manual_seed(5);
  const torch::Tensor m = 2 + 3 * torch::randn({1, 2, 8, 8});
  ContextStatisticBank bank;
  bank.push(torch::tensor({{10.0f, 10.0f, 0.5f, 0.5f}}));
  std::mt19937_64 generator(6);
  const torch::Tensor moved = transfer_statistics(m, bank, ContextProbeSettings{}, 0, generator);
  const torch::Tensor before = channel_statistics(m)[0], after = channel_statistics(moved)[0];
  const torch::Tensor target = torch::tensor({10.0f, 10.0f, 0.5f, 0.5f});
  // Each statistic lands on the segment between the sample's own and the reference's, with one lambda.
  const torch::Tensor fraction = (after - target) / (before - target);
  EXPECT_TRUE(torch::allclose(fraction, fraction[0].expand({4}), 1e-3, 1e-3));
  EXPECT_GE(fraction[0].item<double>(), -1e-4);
  EXPECT_LE(fraction[0].item<double>(), 1.0 + 1e-4);
}

TEST(StabilityWeights, AnUnstableSupportSampleWeighsLessAndWeightsSumToOnePerClass) {
  const torch::Tensor original = torch::zeros({4, 2});
  torch::Tensor probes = 0.1 * torch::ones({3, 4, 2});
  probes.select(1, 1).fill_(2.0);  // sample 1's probes wander far: unstable
  const torch::Tensor labels = torch::tensor(std::vector<std::int64_t>{7, 7, 7, 9});
  const torch::Tensor instability = probe_instability(original, probes, false);
  EXPECT_NEAR(instability[0].item<double>(), 0.02, 1e-6);
  EXPECT_NEAR(instability[1].item<double>(), 8.0, 1e-5);
  const torch::Tensor weights = stability_weights(instability, labels, 8.0);
  EXPECT_LT(weights[1].item<double>(), weights[0].item<double>() / 1e6);
  EXPECT_NEAR(weights[0].item<double>() + weights[1].item<double>() + weights[2].item<double>(), 1.0, 1e-6);
  EXPECT_NEAR(weights[3].item<double>(), 1.0, 1e-6);
  const torch::Tensor prototypes = calibrated_prototypes(original, probes, weights, labels, {7, 9}, true);
  // Class 7 ignores the unstable sample: its two stable samples average (0 + 3 * 0.1) / 4.
  EXPECT_NEAR(prototypes[0][0].item<double>(), 0.075, 1e-4);
  // With zbar_i = z_hat_i^(0) the prototype is the weighted originals: zero here.
  const torch::Tensor originals = calibrated_prototypes(original, probes, weights, labels, {7, 9}, false);
  EXPECT_NEAR(originals.abs().max().item<double>(), 0.0, 1e-7);
  // Class 7 effectively uses its two stable samples, class 9 its only one: (2 + 1) / 2.
  EXPECT_NEAR(effective_shots(weights, labels), 1.5, 1e-4);
}

TEST(StabilityWeights, NormalisedInstabilityIgnoresTheEmbeddingsScale) {
  torch::manual_seed(3);
  const torch::Tensor original = torch::randn({5, 6});
  const torch::Tensor probes = original.unsqueeze(0) + 0.1 * torch::randn({4, 5, 6});
  const torch::Tensor scaled = probe_instability(10 * original, 10 * probes, true);
  EXPECT_TRUE(torch::allclose(scaled, probe_instability(original, probes, true), 1e-4, 1e-6));
  // Unnormalised, a 10x larger embedding is 100x less stable, so softmax(-8 U) turns one-hot.
  EXPECT_TRUE(torch::allclose(probe_instability(10 * original, 10 * probes, false),
                              100 * probe_instability(original, probes, false), 1e-3, 1e-5));
}

}  // namespace
}  // namespace fscil
