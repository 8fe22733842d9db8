// CoP-FSCIL as a method: its named settings, its variants, the episode coverage of CPI, PSPC's
// session update and its loss, seeded repeatability and base sharing between variants, on the tiny
// 10-class protocol (6 base, 2-way 5-shot).
#include <gtest/gtest.h>

#include <algorithm>

#include "methods/common/batch_norm_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/running_statistics_guard.h"
#include "methods/cop_fscil/cop_fscil_method.h"
#include "methods/cop_fscil/cop_fscil_settings.h"
#include "methods/cop_fscil/stability_calibration.h"
#include "methods/method_registry.h"
#include "methods/pits_sc/pseudo_incremental.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet tiny_params(int pit_epochs, int epochs_new) {
  ParameterSet params;
  for (const auto& [key, value] : {std::pair{"pretrain_epochs", "1"}, {"pit_episodes", "2"}, {"batch_size", "32"},
                                   {"pspc_probes", "6"}}) {
    params.set(key, value);
  }
  params.set("pit_epochs", std::to_string(pit_epochs));
  params.set("epochs_new", std::to_string(epochs_new));
  return params;
}

struct Trained {
  std::unique_ptr<Method> method;
  RunContext context;
};

Trained train(const std::string& name, ParameterSet params, std::uint64_t seed = 3) {
  torch::manual_seed(seed);
  Trained trained{create_method(name, params), tiny_context(seed)};
  trained.method->train_base(tiny_base(), trained.context);
  return trained;
}

torch::Tensor logits_on_fixed_probe(Method& method) {
  torch::manual_seed(99);
  return method.logits(torch::randn({12, 2, 4, 4}));
}

CopFscilMethod& as_cop(Method& method) { return dynamic_cast<CopFscilMethod&>(method); }

// After one session: the classifier's mu and the support's embeddings.
struct AfterSession {
  torch::Tensor mu, support_embeddings;
};
AfterSession learn(Trained& trained, const SessionData& support) {
  trained.method->learn_session(support, trained.context);
  return {as_cop(*trained.method).classifier()->mu.detach(), trained.method->embed(support.features.all())};
}

TEST(CopFscilVariants, AblationRunsPitsScPlusTheFourAndAllIncludesThem) {
  const std::vector<std::string> ablation = {"pits-sc", "cop-fscil/cpi", "cop-fscil/cpi+pspc", "cop-fscil/cpi+pcqa",
                                             "cop-fscil"};
  EXPECT_EQ(resolve_method_names("ablation"), ablation);
  const auto all = resolve_method_names("all");
  for (const auto& name : ablation) EXPECT_NE(std::find(all.begin(), all.end(), name), all.end()) << name;
  ParameterSet params;
  const std::vector<std::pair<std::string, CopFscilComponents>> expected = {
      {"cop-fscil/cpi", {false, false}},
      {"cop-fscil/cpi+pspc", {false, true}},
      {"cop-fscil/cpi+pcqa", {true, false}},
      {"cop-fscil", {true, true}}};
  for (const auto& [name, components] : expected) {
    auto method = create_method(name, params);
    EXPECT_EQ(as_cop(*method).components().pcqa, components.pcqa) << name;
    EXPECT_EQ(as_cop(*method).components().pspc, components.pspc) << name;
  }
}

// A named setting's default is the settings struct's own value (written once, in the header),
// every name reads as its value, and a name outside the list is one error naming the key.
TEST(CopFscilSettings, NamedSettingsDefaultToTheStructAndReadEveryName) {
  const ParameterSet defaults;
  const CopFscilSettings read = CopFscilSettings::from(defaults);
  EXPECT_EQ(defaults.used().at("cpi_kept"), "clean");
  EXPECT_EQ(read.kept, KeptCoverage::clean);
  EXPECT_EQ(defaults.used().at("cpi_bn_statistics"), "update");
  EXPECT_EQ(defaults.used().at("cpi_space"), "standardised");
  EXPECT_EQ(defaults.used().at("pspc_instability"), "normalised");
  EXPECT_EQ(defaults.used().at("pspc_mean"), "original");

  ParameterSet params;
  params.set("cpi_kept", "split");
  params.set("cpi_bn_statistics", "reestimate");
  params.set("cpi_reference", "random");
  params.set("cpi_space", "raw");
  params.set("pspc_mean", "views");
  const CopFscilSettings set = CopFscilSettings::from(params);
  EXPECT_EQ(set.kept, KeptCoverage::split);
  EXPECT_EQ(set.episode_statistics, EpisodeStatistics::reestimate);
  EXPECT_EQ(set.cpi.reference, ReferenceChoice::random);
  EXPECT_EQ(set.cpi.space, ProbeSpace::raw);
  EXPECT_TRUE(set.pspc_mean_of_views);

  ParameterSet bad;
  bad.set("cpi_kept", "queries");
  try {
    CopFscilSettings::from(bad);
    FAIL() << "cpi_kept=queries was accepted";
  } catch (const ProtocolError& error) {
    EXPECT_STREQ(error.what(), "parameter cpi_kept='queries': expected one of query, clean, split");
  }
}

TEST(CopFscilVariants, CpiActsOnlyInPseudoIncrementalEpisodes) {
  // Without episodes cop-fscil/cpi is pits-sc to the bit; with them it is not.
  auto pits = train("pits-sc", tiny_params(0, 0));
  auto cpi = train("cop-fscil/cpi", tiny_params(0, 0));
  EXPECT_TRUE(torch::equal(logits_on_fixed_probe(*pits.method), logits_on_fixed_probe(*cpi.method)));
  auto pits_episodes = train("pits-sc", tiny_params(1, 0));
  auto cpi_episodes = train("cop-fscil/cpi", tiny_params(1, 0));
  EXPECT_FALSE(torch::equal(logits_on_fixed_probe(*pits_episodes.method), logits_on_fixed_probe(*cpi_episodes.method)));
  // Without PSPC a new row starts at the mean support embedding, as in pits-sc.
  auto cpi_session = train("cop-fscil/cpi", tiny_params(1, 0));
  const AfterSession after = learn(cpi_session, tiny_support(6));
  EXPECT_TRUE(torch::allclose(after.mu[6], after.support_embeddings.narrow(0, 0, 5).mean(0), 1e-5, 1e-6));
}

TEST(CopFscilVariants, PspcChangesOnlySessionsAndPcqaChangesTheEmbedding) {
  for (const auto& [without_pspc, with_pspc] : {std::pair{"cop-fscil/cpi", "cop-fscil/cpi+pspc"},
                                                {"cop-fscil/cpi+pcqa", "cop-fscil"}}) {
    auto plain = train(without_pspc, tiny_params(1, 5));
    auto calibrated = train(with_pspc, tiny_params(1, 5));
    EXPECT_TRUE(torch::equal(logits_on_fixed_probe(*plain.method), logits_on_fixed_probe(*calibrated.method)))
        << with_pspc << " differs from " << without_pspc << " before any session";
    const SessionData support = tiny_support(6);
    plain.method->learn_session(support, plain.context);
    calibrated.method->learn_session(support, calibrated.context);
    EXPECT_FALSE(torch::equal(logits_on_fixed_probe(*plain.method), logits_on_fixed_probe(*calibrated.method)))
        << with_pspc << " and " << without_pspc << " after a session";
  }
  auto cpi = train("cop-fscil/cpi", tiny_params(1, 0));
  auto pcqa = train("cop-fscil/cpi+pcqa", tiny_params(1, 0));
  EXPECT_TRUE(as_cop(*cpi.method).adapter().is_empty());
  ASSERT_FALSE(as_cop(*pcqa.method).adapter().is_empty());
  // With PCQA the embedding is z_hat: rank-deficient by the D - d_inv dropped directions, so
  // its norm equals that of its invariant block and is below the encoder's.
  torch::manual_seed(7);
  const torch::Tensor features = torch::randn({4, 2, 4, 4});
  const torch::Tensor z_hat = pcqa.method->embed(features);
  const torch::Tensor z = embed_in_batches(as_cop(*pcqa.method).encoder(), features);
  EXPECT_TRUE(torch::all(z_hat.norm(2, 1) < z.norm(2, 1)).item<bool>());
  torch::NoGradGuard no_grad;
  const auto projection = as_cop(*pcqa.method).adapter()->project(as_cop(*pcqa.method).adapter()->reflections_of(z), z);
  EXPECT_TRUE(torch::allclose(z_hat, projection.quotient, 1e-5, 1e-6));
  EXPECT_EQ(projection.invariant.size(1), 192);
}

// The ablation adds one thing per row: every variant, with PSPC or without, fine-tunes its
// sessions by session_loss (the paper's L_New + L_Old by default); `joint` is PITS-SC's update,
// to the bit.
TEST(CopFscilSession, EveryVariantFollowsTheSessionLossAndJointIsPitsScs) {
  // Untrained (no pretraining, no episodes: every base is pits-sc's), so that embeddings have norms
  // near 1 and 5 steps move the rows (this tiny model's trained embeddings reach norms near 1e5,
  // where a cosine's gradient is nil).
  ParameterSet new_old = tiny_params(0, 5);
  new_old.set("pretrain_epochs", "0");
  ParameterSet joint = new_old;
  joint.set("session_loss", "joint");
  const SessionData support = tiny_support(6);
  // The stochastic classifier's draws come from torch's generator: each session starts from the same state.
  auto pits = train("pits-sc", new_old);
  torch::manual_seed(21);
  pits.method->learn_session(support, pits.context);
  const torch::Tensor pits_rows = dynamic_cast<PitsScMethod&>(*pits.method).classifier()->mu.detach();
  for (const std::string name : {"cop-fscil/cpi", "cop-fscil/cpi+pspc"}) {
    auto with_new_old = train(name, new_old);
    auto with_joint = train(name, joint);
    torch::manual_seed(21);
    const torch::Tensor new_old_rows = learn(with_new_old, support).mu;
    torch::manual_seed(21);
    const torch::Tensor joint_rows = learn(with_joint, support).mu;
    EXPECT_GT((new_old_rows - joint_rows).abs().max().item<double>(), 1e-3) << name;
    if (name == "cop-fscil/cpi") EXPECT_TRUE(torch::equal(joint_rows, pits_rows));
  }
}

TEST(CopFscilSession, WithoutContextProbesPspcIsThePlainSupportMean) {
  // All view ranges 0: every probe equals its sample, U = 0, weights are uniform.
  ParameterSet params = tiny_params(0, 0);
  for (const char* key : {"cpi_global_bias", "cpi_channel_bias", "cpi_tilt", "cpi_noise", "cpi_max_shift"}) {
    params.set(key, "0");
  }
  auto still = train("cop-fscil", params);
  const SessionData support = tiny_support(6);
  const AfterSession after = learn(still, support);
  EXPECT_TRUE(torch::allclose(after.mu[6], after.support_embeddings.narrow(0, 0, 5).mean(0), 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(after.mu[7], after.support_embeddings.narrow(0, 5, 5).mean(0), 1e-4, 1e-5));
  EXPECT_NEAR(still.context.diagnostics.at("pspc_effective_shots"), 5.0, 1e-5);  // uniform weights
  // That probes move it is StabilityWeights.AnUnstableSupportSampleWeighsLessAndWeightsSumToOnePerClass's,
  // on embeddings whose instability is known: this tiny model's embeddings reach norms near 1e5
  // after one epoch, where the probes' weights are uniform to within the rounding of the BLAS
  // kernel (0.14 against 0.03 without probes on an AMD EPYC with OpenBLAS's Haswell kernels).
}

TEST(CopFscilSession, ProbeCountFollowsTheInputShapeUnlessSet) {
  ParameterSet params;
  auto method = create_method("cop-fscil", params);
  EXPECT_EQ(as_cop(*method).probes_per_support_sample({5, 64, 24, 500}), 100);   // HapTex-shaped
  EXPECT_EQ(as_cop(*method).probes_per_support_sample({3, 64, 493, 8000}), 10);  // LMT108-shaped
  ParameterSet set;
  set.set("pspc_probes", "7");
  EXPECT_EQ(as_cop(*create_method("cop-fscil", set)).probes_per_support_sample({5, 64, 24, 500}), 7);
}

TEST(PspcLoss, NewClassesLearnOnlyFromTheSupportAndOldOnesOnlyFromTheirMeans) {
  torch::manual_seed(4);
  StochasticClassifier classifier(6, 8);
  {
    torch::NoGradGuard no_grad;
    classifier->sigma.fill_(-40.0);  // noise ~1e-17: the comparison below is deterministic
  }
  const torch::Tensor support = torch::randn({4, 8}), labels = torch::tensor(std::vector<std::int64_t>{3, 3, 4, 4});
  const torch::Tensor old_means = torch::randn({3, 8});
  namespace F = torch::nn::functional;
  new_and_old_loss(classifier, support, labels, old_means, 3, 5).backward();
  const torch::Tensor both = classifier->mu.grad().clone();
  classifier->mu.mutable_grad().zero_();
  F::cross_entropy(classifier->forward(support, 5, true).narrow(1, 3, 2), labels - 3).backward();
  const torch::Tensor from_new = classifier->mu.grad().clone();
  EXPECT_EQ(from_new.narrow(0, 0, 3).abs().sum().item<double>(), 0.0);  // the support never touches old rows
  EXPECT_TRUE(torch::allclose(both.narrow(0, 3, 2), from_new.narrow(0, 3, 2), 1e-5, 1e-7));
  EXPECT_GT(both.narrow(0, 0, 3).abs().sum().item<double>(), 0.0);  // old rows learn from their means
  EXPECT_EQ(both[5].abs().sum().item<double>(), 0.0);               // the unseen row does not move
}

// Exposes the episode hook and PSPC's embeddings.
class ExposedCop : public CopFscilMethod {
 public:
  using CopFscilMethod::CopFscilMethod;
  using CopFscilMethod::perturb_episode;
  using CopFscilMethod::pspc_embeddings;
};

// How many rows of each part an episode's CPI covers under `cpi_kept`.
struct Coverage {
  std::int64_t shots = 0, queries = 0, kept = 0;
};
Coverage episode_coverage(const std::string& kept) {
  const SessionData base = tiny_base();
  ParameterSet params;
  params.set("cpi_kept", kept);
  const PitEpisodeSampler sampler(base, 6, 10, PitsScSettings::from(params));
  std::mt19937_64 generator(8);
  PitEpisode episode = sampler.draw(generator, mean_front_end);
  const torch::Tensor mixed_before = episode.mixed_features.clone(), kept_before = episode.kept_features.clone();
  ExposedCop method(params, CopFscilComponents{false, false});
  RunContext context = tiny_context(8);
  method.perturb_episode(episode, context);
  // Choosing rows changes no sample: the network replaces them by probes where CPI acts.
  EXPECT_TRUE(torch::equal(episode.mixed_features, mixed_before));
  EXPECT_TRUE(torch::equal(episode.kept_features, kept_before));
  Coverage coverage;
  for (std::int64_t row : std::vector<std::int64_t>(episode.mixed_probe_rows.data_ptr<std::int64_t>(),
                                                    episode.mixed_probe_rows.data_ptr<std::int64_t>() +
                                                        episode.mixed_probe_rows.numel())) {
    (row % 20 < 5 ? coverage.shots : coverage.queries) += 1;
  }
  coverage.kept = episode.kept_probe_rows.defined() ? episode.kept_probe_rows.numel() : 0;
  return coverage;
}

TEST(CopFscilEpisode, ProbesSixtyPercentOfShotsEveryQueryAndTheKeptSamplesAsChosen) {
  // The tiny episode: 1 pair of 5 mixed shots + 15 queries, 4 kept classes x 20 samples.
  const Coverage as_queries = episode_coverage("query");
  EXPECT_EQ(as_queries.shots, 3);  // 60% of 5 shots
  EXPECT_EQ(as_queries.queries, 15);
  EXPECT_EQ(as_queries.kept, 80);
  EXPECT_EQ(episode_coverage("clean").kept, 0);
  EXPECT_EQ(episode_coverage("split").kept, 4 * (3 + 15));  // each kept class: 3 of its 5 "shots", all 15 others
}

// Every batch-norm buffer of the encoder (running means, variances, counters) in one vector.
torch::Tensor encoder_buffers(Method& method) {
  std::vector<torch::Tensor> flat;
  for (const auto& buffer : as_cop(method).encoder()->buffers()) flat.push_back(buffer.to(torch::kDouble).flatten());
  return torch::cat(flat);
}

TEST(CopFscilEpisode, GuardedEpisodesLeaveTheRunningStatisticsAsPretrainingLeftThem) {
  const auto buffers_after = [](int pit_epochs, const std::string& statistics) {
    ParameterSet params = tiny_params(pit_epochs, 0);
    params.set("cpi_bn_statistics", statistics);
    return encoder_buffers(*train("cop-fscil/cpi", params).method);
  };
  const torch::Tensor pretrained = buffers_after(0, "update");
  EXPECT_TRUE(torch::equal(buffers_after(1, "guarded"), pretrained));
  EXPECT_FALSE(torch::equal(buffers_after(1, "update"), pretrained));
}

TEST(CopFscilEpisode, ReestimatedStatisticsAreThoseOfTheCleanBaseData) {
  ParameterSet params = tiny_params(1, 0);
  params.set("cpi_bn_statistics", "reestimate");
  auto trained = train("cop-fscil/cpi", params);
  ResNet18Encoder& encoder = as_cop(*trained.method).encoder();
  const torch::Tensor after_training = encoder_buffers(*trained.method);
  // Estimating again on the clean base data changes nothing: they already are its statistics.
  torch::manual_seed(3);  // train() drew the base session's features first after this seed
  const SessionData base = tiny_base();
  reestimate_batch_norm_statistics(*encoder, base.features, 256,
                                   [&](const torch::Tensor& batch) { encoder->forward(batch); });
  EXPECT_TRUE(torch::allclose(encoder_buffers(*trained.method), after_training, 1e-5, 1e-6));
  // With the statistics the episodes left they are not.
  ParameterSet updated = tiny_params(1, 0);
  updated.set("cpi_bn_statistics", "update");
  EXPECT_FALSE(torch::allclose(encoder_buffers(*train("cop-fscil/cpi", updated).method), after_training, 1e-5, 1e-6));
}

TEST(CopFscilSession, PspcMapsEveryProbeWithTheQOfItsOriginal) {
  ParameterSet own_params = tiny_params(0, 0);
  own_params.set("pspc_q", "own");
  for (const auto& [params, from_original] : {std::pair{tiny_params(0, 0), true}, {own_params, false}}) {
    torch::manual_seed(3);
    ExposedCop method(params, CopFscilComponents{true, true});
    RunContext context = tiny_context(3);
    method.train_base(tiny_base(), context);
    torch::manual_seed(5);
    const torch::Tensor original = torch::randn({4, 256}), probes = torch::randn({3, 4, 256});
    const auto [original_hat, probes_hat] = method.pspc_embeddings(original, probes);
    torch::NoGradGuard no_grad;
    QuotientAdapter& adapter = method.adapter();
    const torch::Tensor q_of_original = adapter->reflections_of(original);
    EXPECT_TRUE(torch::allclose(original_hat, adapter->project(q_of_original, original).quotient, 1e-5, 1e-6));
    const torch::Tensor with_original_q = adapter->project(q_of_original, probes[1]).quotient;
    const torch::Tensor with_own_q = adapter->forward(probes[1]);
    EXPECT_EQ(torch::allclose(probes_hat[1], with_original_q, 1e-5, 1e-6), from_original);
    EXPECT_EQ(torch::allclose(probes_hat[1], with_own_q, 1e-5, 1e-6), !from_original);
  }
}

TEST(CopFscilSession, RecordsPspcsEffectiveShotsAndTheRowsAlignment) {
  auto trained = train("cop-fscil", tiny_params(0, 0));
  trained.method->learn_session(tiny_support(6), trained.context);
  ASSERT_EQ(trained.context.diagnostics.count("pspc_effective_shots"), 1u);
  const double shots = trained.context.diagnostics.at("pspc_effective_shots");
  EXPECT_GE(shots, 1.0);
  EXPECT_LE(shots, 5.0 + 1e-9);
  // No fine-tuning step: the rows are still the (calibrated) means the session started them at.
  EXPECT_NEAR(trained.context.diagnostics.at("old_rows_cosine_to_means"), 1.0, 1e-5);
  EXPECT_NEAR(trained.context.diagnostics.at("new_rows_cosine_to_means"), 1.0, 1e-5);
  // PCQA drops d_sen coordinates: z_hat is shorter than the encoder's z.
  EXPECT_LT(trained.context.diagnostics.at("support_embedding_norm"),
            trained.context.diagnostics.at("support_encoder_norm"));
}

TEST(RunningStatisticsGuard, UndoesTheBatchNormUpdatesOfATrainingForward) {
  torch::nn::BatchNorm1d norm(3);
  norm->train();
  const torch::Tensor mean_before = norm->running_mean.clone();
  {
    const RunningStatisticsGuard guard(*norm);
    norm->forward(5 + torch::randn({16, 3}));
    EXPECT_FALSE(torch::equal(norm->running_mean, mean_before));
  }
  EXPECT_TRUE(torch::equal(norm->running_mean, mean_before));
}

TEST(CopFscil, SeededRunsRepeatExactly) {
  const SessionData support = tiny_support(6);
  auto one = train("cop-fscil", tiny_params(1, 3), 4);
  one.method->learn_session(support, one.context);
  auto two = train("cop-fscil", tiny_params(1, 3), 4);
  two.method->learn_session(support, two.context);
  EXPECT_TRUE(torch::equal(logits_on_fixed_probe(*one.method), logits_on_fixed_probe(*two.method)));
  auto other = train("cop-fscil", tiny_params(1, 3), 5);
  other.method->learn_session(support, other.context);
  EXPECT_FALSE(torch::equal(logits_on_fixed_probe(*one.method), logits_on_fixed_probe(*other.method)));
}

TEST(CopFscil, AVariantContinuingAnotherVariantsBaseRunsExactlyAsOnItsOwnBase) {
  const SessionData first = tiny_support(6), second = tiny_support(8);
  auto own = train("cop-fscil", tiny_params(1, 3), 4);
  own.method->learn_session(first, own.context);
  own.method->learn_session(second, own.context);

  // cop-fscil/cpi+pcqa trains the same base and runs its own sessions; cop-fscil then takes over
  // that base as it stood before those sessions.
  auto donor = train("cop-fscil/cpi+pcqa", tiny_params(1, 3), 4);
  donor.method->learn_session(first, donor.context);
  donor.method->learn_session(second, donor.context);
  auto heir = create_method("cop-fscil", tiny_params(1, 3));
  RunContext context = tiny_context(4);
  context.generator.discard(17);  // whatever the runner's state, the base's random state comes back
  torch::manual_seed(123);
  ASSERT_TRUE(heir->continue_from_base(*donor.method, context));
  heir->learn_session(first, context);
  heir->learn_session(second, context);
  EXPECT_TRUE(torch::equal(logits_on_fixed_probe(*own.method), logits_on_fixed_probe(*heir)));

  // Without PCQA the base is a different one: no hand-over.
  auto other = create_method("cop-fscil/cpi+pspc", tiny_params(1, 3));
  EXPECT_NE(method_entry("cop-fscil/cpi+pspc").shared_base_key, method_entry("cop-fscil").shared_base_key);
  EXPECT_FALSE(other->continue_from_base(*heir, context));
}

}  // namespace
}  // namespace fscil
