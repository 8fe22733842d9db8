// PAN's parts against hand-computed values, and its session update on a tiny protocol.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "methods/common/embedding.h"
#include "methods/pan/attention_prototypes.h"
#include "methods/pan/new_row_finetune.h"
#include "methods/pan/pan_attention.h"
#include "methods/pan/pan_episode.h"
#include "methods/pan/pan_method.h"
#include "methods/pan/pan_settings.h"
#include "methods/pan/prototype_query_attention.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

// W_q = W_k = 0 (every token attends uniformly), W_v = W_o = I, b_o = 0.
PanAttention uniform_attention(std::int64_t dim) {
  PanAttention attention(dim);
  torch::NoGradGuard no_grad;
  attention->query->weight.zero_();
  attention->key->weight.zero_();
  attention->value->weight.copy_(torch::eye(dim));
  attention->out->weight.copy_(torch::eye(dim));
  attention->out->bias.zero_();
  attention->eval();
  return attention;
}

TEST(PanAttention, PqaScoresTheQueryAgainstEachPrototypeAfterAttendingTogether) {
  // Tokens e1, e2 and the query e1: each output is LayerNorm(token + (2/3, 1/3, 0)).
  // p1' = x' = LN(5/3, 1/3, 0), p2' = LN(2/3, 4/3, 0): cos(x', p2') = 0.46291 x 1.22474 / 3.
  PanAttention attention = uniform_attention(3);
  const torch::Tensor prototypes = torch::tensor({{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}});
  const torch::Tensor logits = pqa_logits(attention, prototypes, torch::tensor({{1.0f, 0.0f, 0.0f}}), 16.0);
  EXPECT_NEAR(logits[0][0].item<double>(), 16.0, 1e-3);
  EXPECT_NEAR(logits[0][1].item<double>(), 3.0237, 1e-3);
}

TEST(PanAttention, SoftmaxScalesTheScoresByOneOverRootD) {
  // W_q = W_k = W_v = W_o = I in D = 4, tokens 2e1 and 2e2: raw scores 4 and 0, softmax of 4/2
  // and 0 gives 0.880797 and 0.119203 (without the scaling: 0.982 and 0.018).
  PanAttention attention = uniform_attention(4);
  {
    torch::NoGradGuard no_grad;
    attention->query->weight.copy_(torch::eye(4));
    attention->key->weight.copy_(torch::eye(4));
  }
  const torch::Tensor tokens = torch::tensor({{{2.0f, 0.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f, 0.0f}}});
  const torch::Tensor first = attention->forward(tokens).tokens[0][0];
  const torch::Tensor expected =
      torch::layer_norm(torch::tensor({2.0f + 2 * 0.880797f, 2 * 0.119203f, 0.0f, 0.0f}), {4});
  EXPECT_TRUE(torch::allclose(first, expected, 1e-4, 1e-5)) << first << expected;
}

TEST(PanAttention, RawScoresAreUnscaledAndQueriesAreIndependent) {
  torch::manual_seed(2);
  PanAttention attention(3);
  {
    torch::NoGradGuard no_grad;
    attention->query->weight.copy_(torch::eye(3));
    attention->key->weight.copy_(torch::eye(3));
  }
  attention->eval();
  const AttentionOutput out = attention->forward(torch::tensor({{{1.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}}}));
  EXPECT_TRUE(torch::allclose(out.raw_scores[0], torch::tensor({{1.0f, 0.0f}, {0.0f, 4.0f}})));

  PanAttention random(8);
  random->eval();
  const torch::Tensor prototypes = torch::randn({5, 8}), queries = torch::randn({7, 8});
  const torch::Tensor together = pqa_logits(random, prototypes, queries, 16.0, 256);
  EXPECT_TRUE(torch::allclose(pqa_logits(random, prototypes, queries, 16.0, 1), together, 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(pqa_logits(random, prototypes.unsqueeze(0).expand({7, 5, 8}), queries, 16.0), together,
                              1e-5, 1e-6));
}

TEST(AttentionPrototypes, GroupSupportsByTheirRowModuloTheSlotsAsReleased) {
  torch::manual_seed(3);
  PanAttention attention(4);
  attention->eval();
  const std::int64_t shot = 2, slots = 3, supports = shot * slots;
  const torch::Tensor support_rows = torch::randn({supports, 4}), queries = torch::randn({2, 4});
  const torch::Tensor built = attention_prototypes(attention, support_rows, queries, shot);
  ASSERT_EQ(built.sizes(), (std::vector<std::int64_t>{2, slots, 4}));
  for (std::int64_t n = 0; n < 2; ++n) {
    const AttentionOutput out = attention->forward(torch::cat({support_rows, queries[n].unsqueeze(0)}).unsqueeze(0));
    for (std::int64_t g = 0; g < slots; ++g) {
      // Supports g and g + slots: their raw scores against the query, softmaxed between the two.
      const double l0 = out.raw_scores[0][g][supports].item<double>();
      const double l1 = out.raw_scores[0][g + slots][supports].item<double>();
      const double w0 = 1.0 / (1.0 + std::exp(l1 - l0));
      const torch::Tensor expected = w0 * out.tokens[0][g] + (1 - w0) * out.tokens[0][g + slots];
      EXPECT_TRUE(torch::allclose(built[n][g], expected, 1e-5, 1e-6)) << n << " " << g;
    }
  }
}

TEST(AttentionPrototypes, TheReplacementIsSeenForwardAndTheMeansGetTheGradient) {
  const torch::Tensor means = torch::tensor({{1.0f, 2.0f}, {3.0f, 4.0f}}, torch::requires_grad());
  const torch::Tensor replacement = torch::tensor({{0.1f, 0.2f}, {0.3f, 0.4f}}, torch::requires_grad());
  const torch::Tensor used = straight_through(means, replacement);
  EXPECT_TRUE(torch::equal(used, replacement.detach()));
  const torch::Tensor direction = torch::tensor({{1.0f, -1.0f}, {2.0f, 0.5f}});
  (used * direction).sum().backward();
  EXPECT_TRUE(torch::equal(means.grad(), direction));
  EXPECT_FALSE(replacement.grad().defined());
}

TEST(PanSettings, TemporaryBaseClassesKeepTheReleasedShare) {
  EXPECT_EQ(temporary_base_classes(60), 35);  // the release's 35 of 60
  EXPECT_EQ(temporary_base_classes(55), 32);  // NS-100: 32.08
  EXPECT_EQ(temporary_base_classes(6), 4);    // 3.5 rounds up
  EXPECT_EQ(temporary_base_classes(2), 1);
}

TEST(PanSettings, AnExplicitTemporarySplitMustLeaveANovelClass) {
  EXPECT_EQ(temporary_base_classes(55, 30), 30);
  EXPECT_EQ(temporary_base_classes(55, 54), 54);
  try {
    temporary_base_classes(55, 55);
    FAIL() << "a split without temporary novel classes was accepted";
  } catch (const MethodError& error) {
    EXPECT_NE(std::string(error.what()).find("pan_temporary_base is 55: the protocol has 55 base classes"),
              std::string::npos)
        << error.what();
  }
}

TEST(PanEpisodeSampler, LaysEachPartOutSampleMajorFromItsOwnClasses) {
  SessionData base;
  const std::int64_t n = 6 * 25;
  base.labels = torch::div(torch::arange(n), 25, "floor");
  base.features = torch::arange(n).to(torch::kFloat).view({n, 1, 1, 1});  // each row shows its index
  const PanEpisodeSampler sampler(base, 4, 6, 5, 2, 3);
  std::mt19937_64 generator(7);
  const PanEpisode episode = sampler.draw(generator);
  ASSERT_EQ(episode.way, 2);  // 2 temporary novel classes: both parts shrink to 2 slots
  ASSERT_EQ(episode.base_features.size(0), (2 + 3) * 2);
  const auto check = [&](const torch::Tensor& part, std::int64_t low, std::int64_t high) {
    std::set<std::int64_t> rows;
    for (std::int64_t slot = 0; slot < 2; ++slot) {
      const std::int64_t label = part[slot].item<std::int64_t>() / 25;
      EXPECT_GE(label, low);
      EXPECT_LT(label, high);
      for (std::int64_t sample = 0; sample < 5; ++sample) {
        const std::int64_t row = part[sample * 2 + slot].item<std::int64_t>();
        EXPECT_EQ(row / 25, label);
        rows.insert(row);
      }
    }
    EXPECT_EQ(rows.size(), 10u);  // without replacement
  };
  check(episode.base_features.view(-1), 0, 4);
  check(episode.novel_features.view(-1), 4, 6);
}

TEST(FinetuneNewRows, TrainsTheNewRowsOnlyAndLowersTheShotsLoss) {
  torch::manual_seed(4);
  const torch::Tensor old_rows = torch::randn({3, 4}), new_rows = torch::randn({2, 4});
  const torch::Tensor shots = torch::randn({4, 4}), labels = torch::tensor({3, 3, 4, 4});
  EXPECT_TRUE(torch::equal(finetune_new_rows(shots, labels, old_rows, new_rows, 16.0, 0, 0.1), new_rows));
  std::vector<double> losses;
  const torch::Tensor trained = finetune_new_rows(shots, labels, old_rows, new_rows, 16.0, 10, 0.1,
                                                  [&](int, double loss) { losses.push_back(loss); });
  ASSERT_EQ(losses.size(), 10u);
  EXPECT_LT(losses.back(), losses.front());
  EXPECT_FALSE(torch::allclose(trained, new_rows));
}

TEST(FinetuneNewRows, StepsAreDampedMomentumSgdOnTheNewRows) {
  // Step 1: rows - lr g1 (the buffer starts at g1); step 2: buffer 0.9 g1 + 0.1 g2.
  torch::manual_seed(6);
  const torch::Tensor old_rows = torch::randn({2, 3}), new_rows = torch::randn({1, 3});
  const torch::Tensor shots = torch::randn({2, 3}), labels = torch::tensor({2, 2});
  const auto gradient = [&](const torch::Tensor& rows) {
    torch::Tensor trained = rows.clone().set_requires_grad(true);
    const torch::Tensor all = torch::nn::functional::normalize(torch::cat({old_rows, trained}),
                                                               torch::nn::functional::NormalizeFuncOptions().dim(-1));
    const torch::Tensor unit = torch::nn::functional::normalize(shots, torch::nn::functional::NormalizeFuncOptions().dim(-1));
    torch::nn::functional::cross_entropy(16.0 * unit.matmul(all.t()), labels).backward();
    return trained.grad();
  };
  const torch::Tensor g1 = gradient(new_rows);
  const torch::Tensor after_one = new_rows - 0.1 * g1;
  EXPECT_TRUE(torch::allclose(finetune_new_rows(shots, labels, old_rows, new_rows, 16.0, 1, 0.1), after_one, 1e-5, 1e-6));
  const torch::Tensor after_two = after_one - 0.1 * (0.9 * g1 + 0.1 * gradient(after_one));
  EXPECT_TRUE(torch::allclose(finetune_new_rows(shots, labels, old_rows, new_rows, 16.0, 2, 0.1), after_two, 1e-5, 1e-6));
}

ParameterSet tiny_pan_params() {
  ParameterSet params;
  params.set("pretrain_epochs", "1");
  params.set("batch_size", "32");
  params.set("pan_pit_episodes", "2");
  return params;
}

TEST(PanMethod, ASessionFineTunesOnlyItsNewRowsAndLeavesBn0Untrained) {
  torch::manual_seed(5);
  PanMethod method(tiny_pan_params());
  RunContext context = tiny_context(5);
  const SessionData base_data = tiny_base();
  method.train_base(base_data, context);
  const MethodState base = method.save_state();
  EXPECT_TRUE(torch::equal(base.at("encoder.bn0.weight"), torch::ones_like(base.at("encoder.bn0.weight"))));
  EXPECT_TRUE(torch::equal(base.at("encoder.bn0.bias"), torch::zeros_like(base.at("encoder.bn0.bias"))));
  EXPECT_EQ(context.diagnostics.at("temporary_base_classes"), 4);
  // Base rows are the plain, unnormalised means of each class's embeddings.
  const torch::Tensor means =
      class_means(method.embed_rows(base_data.features), base_data.labels, {0, 1, 2, 3, 4, 5});
  EXPECT_TRUE(torch::allclose(base.at("classifier.weight").slice(0, 0, 6), means, 1e-5, 1e-6));
  method.learn_session(tiny_support(6), context);
  const MethodState after = method.save_state();
  EXPECT_TRUE(torch::equal(after.at("classifier.weight").slice(0, 0, 6), base.at("classifier.weight").slice(0, 0, 6)));
  EXPECT_FALSE(torch::equal(after.at("classifier.weight").slice(0, 6, 8), base.at("classifier.weight").slice(0, 6, 8)));
  EXPECT_TRUE(torch::equal(after.at("attention.query.weight"), base.at("attention.query.weight")));
  EXPECT_EQ(method.classify(torch::randn({3, 256})).sizes(), (std::vector<std::int64_t>{3, 8}));
  // Cost: PQA's four projections over 8 rows + the sample, their scores, the cosine rows.
  const ModelCost cost = method.inference_cost(InputShape{2, 4, 4});
  EXPECT_EQ(cost.macs_of("attention"), 2 * 9 * 9 * 256);
  EXPECT_EQ(cost.macs_of("cosine"), 256 + 256 * 8 + 256 * 8);
  EXPECT_EQ(cost.macs_of("layer_norm"), 9 * 256);
}

}  // namespace
}  // namespace fscil
