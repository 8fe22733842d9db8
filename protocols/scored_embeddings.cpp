#include "protocols/scored_embeddings.h"

#include <stdexcept>
#include <utility>

namespace fscil {

ScoredEmbeddings::ScoredEmbeddings(SampleRows rows, std::vector<int> first_session, EmbeddingReuse reuse)
    : rows_(std::move(rows)),
      first_session_(std::move(first_session)),
      reuse_(reuse),
      kept_row_of_(first_session_.size(), -1) {
  if (static_cast<std::int64_t>(first_session_.size()) != rows_.count()) {
    throw std::invalid_argument("scored embeddings: one first session per scored sample");
  }
}

std::vector<std::int64_t> ScoredEmbeddings::first_seen_in(int from, int to) const {
  std::vector<std::int64_t> positions;
  for (std::size_t i = 0; i < first_session_.size(); ++i) {
    if (first_session_[i] >= from && first_session_[i] <= to) positions.push_back(static_cast<std::int64_t>(i));
  }
  return positions;
}

std::vector<std::int64_t> ScoredEmbeddings::positions_seen_by(int session) const { return first_seen_in(0, session); }

torch::Tensor ScoredEmbeddings::embed(Method& method, const std::vector<std::int64_t>& positions) const {
  const torch::Tensor index = torch::tensor(positions, torch::kLong);
  const SampleRows chosen(index.size(0), [this, index](const torch::Tensor& i) { return rows_.gather(index.index_select(0, i)); });
  return method.embed_rows(chosen, kBatch);
}

void ScoredEmbeddings::keep_up_to(Method& method, int session) {
  if (reuse_ != EmbeddingReuse::once_per_run) return;
  // Session by session from the first, so that the batches do not depend on the session a
  // resumed run starts at: session 0's are those of embedding all it scores at once.
  for (int next = static_cast<int>(kept_embeddings_.size()); next <= session; ++next) {
    const std::vector<std::int64_t> fresh = first_seen_in(next, next);
    for (std::int64_t position : fresh) kept_row_of_[static_cast<std::size_t>(position)] = kept_rows_++;
    kept_embeddings_.push_back(fresh.empty() ? torch::Tensor() : embed(method, fresh));
  }
}

torch::Tensor ScoredEmbeddings::embeddings_after(Method& method, int session) {
  const std::vector<std::int64_t> seen = positions_seen_by(session);
  if (reuse_ == EmbeddingReuse::every_session) return embed(method, seen);
  keep_up_to(method, session);
  std::vector<torch::Tensor> defined;
  for (const auto& part : kept_embeddings_) {
    if (part.defined()) defined.push_back(part);
  }
  std::vector<std::int64_t> rows;
  for (std::int64_t position : seen) rows.push_back(kept_row_of_[static_cast<std::size_t>(position)]);
  return torch::cat(defined).index_select(0, torch::tensor(rows, torch::kLong));
}

}  // namespace fscil
