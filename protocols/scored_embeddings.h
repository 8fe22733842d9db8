#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "methods/method.h"
#include "methods/sample_rows.h"

namespace fscil {

// How often a scored sample is embedded: once per run (MethodEntry::sessions_keep_embedding) or
// after every session that scores it.
enum class EmbeddingReuse { once_per_run, every_session };

// The embeddings the runner scores a session on: embed() of the scored samples of every class
// seen so far, in the scored split's order. Most methods leave embed() unchanged after the base
// session (MethodEntry::sessions_keep_embedding); their samples are then embedded once per run, a
// session's new classes' samples when that session is scored, instead of every session again.
// The batches are those a run from the first session makes, so a run resumed after any session
// scores on the same embeddings to the bit.
class ScoredEmbeddings {
 public:
  static constexpr std::int64_t kBatch = 512;  // samples per embed() call

  // `rows`: features of the scored samples; `first_session`: each one's class's first session.
  ScoredEmbeddings(SampleRows rows, std::vector<int> first_session, EmbeddingReuse reuse);

  // The positions (in the scored split) of the samples first seen in sessions 0..session, in
  // scored order.
  std::vector<std::int64_t> positions_seen_by(int session) const;
  // Their embeddings, N x D in the same order. Sessions are scored in order from any first one.
  torch::Tensor embeddings_after(Method& method, int session);
  // With once_per_run, embeds now what embeddings_after(session) would keep (a run continuing
  // after `session` catches up outside the next session's test clock); nothing otherwise.
  void keep_up_to(Method& method, int session);

 private:
  // embed() of the samples at `positions`, in batches in that order.
  torch::Tensor embed(Method& method, const std::vector<std::int64_t>& positions) const;
  // Positions of the samples first seen in sessions from..to, in scored order.
  std::vector<std::int64_t> first_seen_in(int from, int to) const;

  SampleRows rows_;
  std::vector<int> first_session_;
  EmbeddingReuse reuse_;
  std::vector<torch::Tensor> kept_embeddings_;  // per session from the first, of its new samples
  std::vector<std::int64_t> kept_row_of_;       // a position's row among them, or -1
  std::int64_t kept_rows_ = 0;
};

}  // namespace fscil
