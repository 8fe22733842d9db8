#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// ARP's prototype refinement (`IL_attn`, chester-w-xie/APR FSCIL_model_define_V1.py L28-L96, L122
// at 78426ecf): one head, no biases, no LayerNorm. Rows Q (L x D) attend to themselves and to the
// keys K (M x D) together: with S = [Q; K], out = Q + drop(W_o (drop(softmax((Q W_q)(S W_k)^T /
// sqrt(D))) (S W_v))), both dropouts 0.1 (L31, L65, L122). The release's widths are 512 (d_model
// hard-coded at L122); ours are the encoder's D.
class RefinementAttentionImpl : public torch::nn::Module {
 public:
  explicit RefinementAttentionImpl(std::int64_t dim, double dropout = 0.1);
  torch::Tensor forward(const torch::Tensor& rows, const torch::Tensor& keys);

  torch::nn::Linear query{nullptr}, key{nullptr}, value{nullptr}, out{nullptr};

 private:
  std::int64_t dim_;
  double dropout_;
};
TORCH_MODULE(RefinementAttention);

// One task's refined classifier (FSCIL_model_define_V1.py L137-L149): the learned rows (C x D)
// with the task's classes replaced by `means` (their supports' means, differentiably: L146), attending
// to themselves and to the learned rows with the task's rows zeroed (L148-L149). The replaced rows
// of `rows` get no gradient from the task.
torch::Tensor refine_task_rows(RefinementAttention& attention, const torch::Tensor& rows,
                               const torch::Tensor& task_classes, const torch::Tensor& means);

// The rows a test scores under arp_test_rows=refined, in eval mode: the first `seen` rows, of which
// those from `base` on are the sessions' shot means. As a task's replaced rows in training, those
// means are queries whose keys are zero; the base rows are queries and keys.
torch::Tensor refine_seen_rows(RefinementAttention& attention, const torch::Tensor& rows, std::int64_t base);

}  // namespace fscil
