#include "protocols/scored_embeddings.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

// embed() is each sample's sum, scaled by how often the method was told a session passed; it
// records the size of every batch it is given.
class CountingMethod : public Method {
 public:
  void train_base(const SessionData&, RunContext&) override {}
  void learn_session(const SessionData&, RunContext&) override { ++sessions; }
  torch::Tensor embed(const torch::Tensor& features) override {
    batches.push_back(features.size(0));
    return features.flatten(1).sum(1, true) * (1 + sessions);
  }
  torch::Tensor classify(const torch::Tensor& embeddings) override { return embeddings; }
  MethodState save_state() const override { return {}; }
  void restore_state(const MethodState&, RunContext&) override {}
  ModelCost inference_cost(const InputShape&) const override { return {}; }

  int sessions = 0;
  std::vector<std::int64_t> batches;
};

// Six samples whose sums are 0..5; the classes of samples 0, 2, 5 are seen from session 0, of
// 1 and 4 from session 1, of 3 from session 2.
SampleRows six_samples() { return SampleRows(torch::arange(6, torch::kFloat).view({6, 1})); }
const std::vector<int> kFirstSession = {0, 1, 0, 2, 1, 0};

std::vector<float> values(const torch::Tensor& embeddings) {
  const torch::Tensor flat = embeddings.flatten().contiguous();
  return {flat.data_ptr<float>(), flat.data_ptr<float>() + flat.numel()};
}

TEST(ScoredEmbeddings, EmbedsEachSampleOnceForAMethodWhoseSessionsKeepItsEmbedding) {
  CountingMethod method;
  ScoredEmbeddings scored(six_samples(), kFirstSession, EmbeddingReuse::once_per_run);
  EXPECT_EQ(scored.positions_seen_by(1), (std::vector<std::int64_t>{0, 1, 2, 4, 5}));
  EXPECT_EQ(values(scored.embeddings_after(method, 0)), (std::vector<float>{0, 2, 5}));
  method.sessions = 1;  // would scale a fresh embedding: kept samples show the old value
  EXPECT_EQ(values(scored.embeddings_after(method, 1)), (std::vector<float>{0, 2, 2, 8, 5}));
  EXPECT_EQ(values(scored.embeddings_after(method, 2)), (std::vector<float>{0, 2, 2, 6, 8, 5}));
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{3, 2, 1}));
}

TEST(ScoredEmbeddings, AResumedRunEmbedsInTheBatchesOfARunFromTheStart) {
  CountingMethod method;
  ScoredEmbeddings scored(six_samples(), kFirstSession, EmbeddingReuse::once_per_run);
  EXPECT_EQ(values(scored.embeddings_after(method, 2)), (std::vector<float>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{3, 2, 1}));
}

TEST(ScoredEmbeddings, ARunContinuingAfterASessionCatchesUpInTheSameBatches) {
  CountingMethod method;
  ScoredEmbeddings scored(six_samples(), kFirstSession, EmbeddingReuse::once_per_run);
  scored.keep_up_to(method, 1);
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{3, 2}));
  method.sessions = 2;
  EXPECT_EQ(values(scored.embeddings_after(method, 2)), (std::vector<float>{0, 1, 2, 9, 4, 5}));
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{3, 2, 1}));
  ScoredEmbeddings recomputed(six_samples(), kFirstSession, EmbeddingReuse::every_session);
  recomputed.keep_up_to(method, 1);
  EXPECT_EQ(method.batches.size(), 3u);  // nothing to keep
}

TEST(ScoredEmbeddings, ASessionWithoutNewScoredSamplesAddsNone) {
  CountingMethod method;
  ScoredEmbeddings scored(six_samples(), {0, 2, 0, 2, 0, 0}, EmbeddingReuse::once_per_run);
  EXPECT_EQ(values(scored.embeddings_after(method, 1)), (std::vector<float>{0, 2, 4, 5}));
  EXPECT_EQ(values(scored.embeddings_after(method, 2)), (std::vector<float>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{4, 2}));
}

TEST(ScoredEmbeddings, EmbedsEverySeenSampleEachSessionOtherwise) {
  CountingMethod method;
  ScoredEmbeddings scored(six_samples(), kFirstSession, EmbeddingReuse::every_session);
  EXPECT_EQ(values(scored.embeddings_after(method, 0)), (std::vector<float>{0, 2, 5}));
  method.sessions = 1;
  EXPECT_EQ(values(scored.embeddings_after(method, 1)), (std::vector<float>{0, 2, 4, 8, 10}));
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{3, 5}));
}

TEST(ScoredEmbeddings, EmbedsInBatchesOfAtMostKBatch) {
  CountingMethod method;
  const std::int64_t count = ScoredEmbeddings::kBatch + 3;
  ScoredEmbeddings scored(SampleRows(torch::ones({count, 1})), std::vector<int>(count, 0), EmbeddingReuse::once_per_run);
  EXPECT_EQ(scored.embeddings_after(method, 0).size(0), count);
  EXPECT_EQ(method.batches, (std::vector<std::int64_t>{ScoredEmbeddings::kBatch, 3}));
}

TEST(ScoredEmbeddings, RejectsAFirstSessionListOfAnotherLength) {
  EXPECT_THROW(ScoredEmbeddings(six_samples(), {0, 1}, EmbeddingReuse::once_per_run), std::invalid_argument);
}

}  // namespace
}  // namespace fscil
