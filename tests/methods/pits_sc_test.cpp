#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "methods/common/mixing.h"
#include "methods/common/stochastic_classifier.h"
#include "methods/pits_sc/pits_sc_method.h"
#include "methods/pits_sc/pseudo_incremental.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

TEST(StochasticClassifier, EvalLogitsAreTemperatureTimesCosineAgainstMu) {
  StochasticClassifier classifier(3, 2, 16.0);
  classifier->set_mu_rows(0, torch::tensor({{1.0f, 0.0f}, {0.0f, 2.0f}, {1.0f, 1.0f}}));
  const torch::Tensor logits = classifier->forward(torch::tensor({{3.0f, 4.0f}}), 2, false);
  ASSERT_EQ(logits.sizes(), (std::vector<std::int64_t>{1, 2}));  // the unseen third row is masked out
  EXPECT_NEAR(logits[0][0].item<float>(), 16.0 * 0.6, 1e-5);
  EXPECT_NEAR(logits[0][1].item<float>(), 16.0 * 0.8, 1e-5);
  // Deterministic mode repeats exactly.
  EXPECT_TRUE(torch::equal(logits, classifier->forward(torch::tensor({{3.0f, 4.0f}}), 2, false)));
}

TEST(StochasticClassifier, TrainingNoiseHasStandardDeviationSoftplusOfSigmaMinusFour) {
  torch::manual_seed(3);
  const std::int64_t rows = 4000;
  StochasticClassifier classifier(rows, 8, 16.0);
  EXPECT_NEAR(classifier->noise_scale()[0][0].item<float>(), std::log1p(std::exp(-4.0)), 1e-6);  // 0.01815
  // mu = e0 in every row; against x = e1 the logit is 16 * noise_1 / |W| ~ 16 * 0.01815 * N(0, 1).
  classifier->set_mu_rows(0, torch::zeros({rows, 8}).index_fill_(1, torch::tensor({std::int64_t{0}}), 1.0));
  const torch::Tensor x = torch::zeros({1, 8}).index_fill_(1, torch::tensor({std::int64_t{1}}), 1.0);
  const torch::Tensor logits = classifier->forward(x, rows, true);
  EXPECT_NEAR(logits.std().item<double>(), 16.0 * std::log1p(std::exp(-4.0)), 0.03 * 16.0 * 0.01815);
  EXPECT_NEAR(logits.mean().item<double>(), 0.0, 0.05);
  // Raising sigma raises the noise: softplus(2 - 4) = 0.127.
  {
    torch::NoGradGuard no_grad;
    classifier->sigma.fill_(2.0);
  }
  EXPECT_GT(classifier->forward(x, rows, true).std().item<double>(), 16.0 * 0.1);
}

TEST(CutMix, PastesOneBoxFromAPartnerAndReportsTheKeptArea) {
  std::mt19937_64 generator(5);
  const torch::Tensor features = torch::arange(4).to(torch::kFloat).view({4, 1, 1, 1}).expand({4, 1, 8, 10}).contiguous();
  const CutMixPlan plan = plan_cutmix(4, 8, 10, 1.0, generator);
  const torch::Tensor mixed = plan.apply(features);
  for (std::int64_t i = 0; i < 4; ++i) {
    const auto sample = mixed[i];
    const double own = (sample == static_cast<float>(i)).to(torch::kDouble).mean().item<double>();
    const double partner = plan.partners[i].item<double>();
    const double from_partner = (sample == static_cast<float>(partner)).to(torch::kDouble).mean().item<double>();
    if (partner == i) continue;
    EXPECT_NEAR(own, plan.kept_fraction, 1e-9);
    EXPECT_NEAR(own + from_partner, 1.0, 1e-9);
  }
}

TEST(PitEpisodeShape, IsPitsScsTwentyTenFiveAndShrinksForSmallProtocols) {
  const PitsScSettings settings;
  const PitEpisodeShape full = pit_episode_shape(settings, 60, 40);
  EXPECT_EQ(full.way, 20);
  EXPECT_EQ(full.kept, 10);
  EXPECT_EQ(full.pairs, 5);
  EXPECT_EQ(full.per_class(), 20);
  const PitEpisodeShape small = pit_episode_shape(settings, 10, 10);
  EXPECT_EQ(small.way, 10);
  EXPECT_EQ(small.pairs, 2);
  EXPECT_EQ(small.kept, 6);
}

TEST(PitEpisode, HasTheDocumentedCompositionAndMixesRawSignals) {
  const SessionData base = tiny_base();
  PitsScSettings settings;
  const PitEpisodeSampler sampler(base, 6, 10, settings);
  ASSERT_EQ(sampler.shape().kept, 4);
  ASSERT_EQ(sampler.shape().pairs, 1);
  std::mt19937_64 generator(1);
  const PitEpisode episode = sampler.draw(generator, mean_front_end);

  // Kept classes: 4 classes x (5 shots + 15 queries), labels unchanged.
  ASSERT_EQ(episode.kept_labels.size(0), 80);
  std::set<std::int64_t> kept;
  for (std::int64_t i = 0; i < 80; ++i) kept.insert(episode.kept_labels[i].item<std::int64_t>());
  EXPECT_EQ(kept.size(), 4u);
  for (std::int64_t c : kept) EXPECT_EQ((episode.kept_labels == c).sum().item<std::int64_t>(), 20);

  // One pair of two other base classes, one lambda for the episode, mixed on the raw signal.
  const std::int64_t a = episode.first_class[0], b = episode.second_class[0];
  EXPECT_NE(a, b);
  EXPECT_EQ(kept.count(a) + kept.count(b), 0u);
  EXPECT_GT(episode.lambda, 0.0);
  EXPECT_LT(episode.lambda, 1.0);
  ASSERT_EQ(episode.mixed_signals.size(0), 20);
  const auto class_channel = episode.mixed_signals.select(1, 0);
  EXPECT_TRUE(torch::allclose(class_channel, torch::full_like(class_channel, episode.lambda * a + (1 - episode.lambda) * b)));
  std::set<std::int64_t> partners;
  for (std::int64_t i = 0; i < 20; ++i) {  // each mixture combines one sample of a with one of b
    const double index_mix = episode.mixed_signals[i][1][0].item<double>();
    bool found = false;
    for (std::int64_t p = a * 25; p < a * 25 + 25 && !found; ++p) {
      const double q = (index_mix - episode.lambda * p) / (1 - episode.lambda);
      found = std::abs(q - std::round(q)) < 1e-3 && std::round(q) >= b * 25 && std::round(q) < b * 25 + 25;
    }
    EXPECT_TRUE(found) << i;
  }
  EXPECT_TRUE(torch::allclose(episode.mixed_features, mean_front_end(episode.mixed_signals)));

  // The pair's 15 queries are labelled with one novel row among 6..9.
  ASSERT_EQ(episode.novel_rows.size(), 1u);
  EXPECT_GE(episode.novel_rows[0], 6);
  EXPECT_LT(episode.novel_rows[0], 10);
  EXPECT_EQ(episode.query_labels.size(0), 15);
  EXPECT_TRUE(torch::all(episode.query_labels == episode.novel_rows[0]).item<bool>());
}

TEST(PitEpisodeLoss, WritesThePairPrototypeIntoItsNovelRowAndZeroesTheOthers) {
  torch::manual_seed(0);
  const SessionData base = tiny_base();
  const PitsScSettings settings;
  const PitEpisodeSampler sampler(base, 6, 10, settings);
  std::mt19937_64 generator(2);
  const PitEpisode episode = sampler.draw(generator, mean_front_end);
  ResNet18Encoder encoder(ResNet18Options{2, 4});
  StochasticClassifier classifier(10, 256);
  encoder->train();
  const TrainingEmbedder embedder = [&](const torch::Tensor& features, const torch::Tensor& /*probe_rows*/) {
    return TrainingEmbedding{encoder->forward(features), {}};
  };
  const torch::Tensor loss = pit_episode_loss(embedder, classifier, episode, sampler.shape(), 6, 10).total();
  EXPECT_TRUE(std::isfinite(loss.item<double>()));
  for (std::int64_t row = 6; row < 10; ++row) {
    const double norm = classifier->mu[row].norm().item<double>();
    if (row == episode.novel_rows[0]) {
      EXPECT_GT(norm, 0.0);
    } else {
      EXPECT_EQ(norm, 0.0) << row;
    }
  }
  loss.backward();
  EXPECT_GT(encoder->parameters().front().grad().abs().sum().item<double>(), 0.0);
}

// A whole PITS-SC on a tiny 10-class problem: 6 base classes, 2 sessions of 2-way 5-shot.
class TinyPitsSc : public ::testing::Test {
 protected:
  static ParameterSet tiny_params(int epochs_new) {
    ParameterSet params;
    for (const auto& [key, value] : {std::pair{"pretrain_epochs", "1"}, {"pit_epochs", "1"}, {"pit_episodes", "2"},
                                     {"batch_size", "32"}}) {
      params.set(key, value);
    }
    params.set("epochs_new", std::to_string(epochs_new));
    return params;
  }

  std::unique_ptr<PitsScMethod> train(std::uint64_t seed, int epochs_new) {
    torch::manual_seed(seed);
    auto method = std::make_unique<PitsScMethod>(tiny_params(epochs_new));
    context = tiny_context(seed);
    method->train_base(base, context);
    return method;
  }

  static SessionData support(std::int64_t first_class) { return tiny_support(first_class); }

  SessionData base = tiny_base();
  RunContext context;
};

TEST_F(TinyPitsSc, SessionLeavesTheEncoderUnchangedAndSetsNewRowsToSupportMeans) {
  auto method = train(1, 0);
  std::vector<torch::Tensor> before;
  for (const auto& tensor : method->encoder()->parameters()) before.push_back(tensor.clone());
  for (const auto& tensor : method->encoder()->buffers()) before.push_back(tensor.clone());
  const torch::Tensor mu_before = method->classifier()->mu.detach().clone();

  const SessionData first = support(6);
  method->learn_session(first, context);
  std::size_t k = 0;
  for (const auto& tensor : method->encoder()->parameters()) EXPECT_TRUE(torch::equal(tensor, before[k++]));
  for (const auto& tensor : method->encoder()->buffers()) EXPECT_TRUE(torch::equal(tensor, before[k++]));
  // With no fine-tuning steps old rows stay put and new rows are the mean support embeddings.
  const torch::Tensor mu = method->classifier()->mu.detach();
  EXPECT_TRUE(torch::equal(mu.narrow(0, 0, 6), mu_before.narrow(0, 0, 6)));
  const torch::Tensor embeddings = method->embed(first.features.all());
  EXPECT_TRUE(torch::allclose(mu[6], embeddings.narrow(0, 0, 5).mean(0), 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(mu[7], embeddings.narrow(0, 5, 5).mean(0), 1e-5, 1e-6));
  EXPECT_EQ(method->classify(embeddings).size(1), 8);
  // Rows that did not move still point at the class means they started from.
  EXPECT_NEAR(context.diagnostics.at("old_rows_cosine_to_means"), 1.0, 1e-5);
  EXPECT_NEAR(context.diagnostics.at("new_rows_cosine_to_means"), 1.0, 1e-5);
  EXPECT_NEAR(context.diagnostics.at("support_embedding_norm"), embeddings.norm(2, 1).mean().item<double>(), 1e-4);
  EXPECT_NEAR(context.diagnostics.at("new_rows_norm"), mu.narrow(0, 6, 2).norm(2, 1).mean().item<double>(), 1e-4);
  EXPECT_NEAR(context.diagnostics.at("old_rows_norm"), mu.narrow(0, 0, 6).norm(2, 1).mean().item<double>(), 1e-4);
}

TEST_F(TinyPitsSc, FineTuningMovesSeenRowsThroughTheLossAndNeverUnseenOnes) {
  auto method = train(1, 10);
  const torch::Tensor mu_before = method->classifier()->mu.detach().clone();
  const torch::Tensor sigma_before = method->classifier()->sigma.detach().clone();
  method->learn_session(support(6), context);
  const torch::Tensor mu = method->classifier()->mu.detach();
  EXPECT_FALSE(torch::equal(mu.narrow(0, 0, 6), mu_before.narrow(0, 0, 6)));  // old rows move with the support loss
  EXPECT_FALSE(torch::equal(method->classifier()->sigma.detach().narrow(0, 0, 8), sigma_before.narrow(0, 0, 8)));
  EXPECT_TRUE(torch::equal(mu.narrow(0, 8, 2), mu_before.narrow(0, 8, 2)));  // classes 8, 9 not seen yet
  EXPECT_TRUE(torch::equal(method->classifier()->sigma.detach().narrow(0, 8, 2), sigma_before.narrow(0, 8, 2)));
  // The diagnostic is the mean cosine of each old row to the mean it started at (the base rows
  // were those means), here computed again in double precision.
  const torch::Tensor moved = mu.narrow(0, 0, 6).to(torch::kDouble), start = mu_before.narrow(0, 0, 6).to(torch::kDouble);
  const double expected = ((moved * start).sum(1) / (moved.norm(2, 1) * start.norm(2, 1))).mean().item<double>();
  EXPECT_NEAR(context.diagnostics.at("old_rows_cosine_to_means"), expected, 1e-6);
}

// bn0's running statistics depend only on the batches it normalises. With CutMix after bn0 (the
// released placement) every batch reaches bn0 clean, so one pretraining epoch in which every
// batch is CutMixed leaves bn0 exactly as an epoch without CutMix. Before bn0 they agree up to
// rounding: the box is the same for the whole batch and its partners are a permutation of it,
// so each Mel bin's batch holds the same values, summed in another order.
TEST_F(TinyPitsSc, CutMixAfterTheInputNormLeavesItsStatisticsThoseOfTheCleanBatches) {
  const auto bn0_after_pretraining = [&](const char* p_cutmix, const char* space) {
    ParameterSet params = tiny_params(0);
    params.set("pit_epochs", "0");
    params.set("p_cutmix", p_cutmix);
    params.set("cutmix_space", space);
    params.set("cutmix_alpha", "1");
    torch::manual_seed(2);
    PitsScMethod method(params);
    context = tiny_context(2);
    method.train_base(base, context);
    const auto buffers = method.encoder()->named_buffers();
    return torch::cat({buffers["bn0.running_mean"], buffers["bn0.running_var"]});
  };
  const torch::Tensor clean = bn0_after_pretraining("0", "standardised");
  EXPECT_TRUE(torch::equal(bn0_after_pretraining("1", "standardised"), clean));
  EXPECT_TRUE(torch::allclose(bn0_after_pretraining("1", "raw"), clean, 1e-5, 1e-6));
}

TEST_F(TinyPitsSc, SeededRunsRepeatExactly) {
  const SessionData first = support(6);
  const torch::Tensor probe = torch::randn({7, 2, 4, 4});
  auto one = train(4, 10);
  one->learn_session(first, context);
  auto two = train(4, 10);
  two->learn_session(first, context);
  EXPECT_TRUE(torch::equal(one->logits(probe), two->logits(probe)));
  auto other = train(5, 10);
  other->learn_session(first, context);
  EXPECT_FALSE(torch::equal(one->logits(probe), other->logits(probe)));
}

}  // namespace
}  // namespace fscil
