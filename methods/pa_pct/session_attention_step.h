#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace fscil {

// The loss of PA-PCT's one attention step in an adding session (cgq2971-afk/FCIAC CANetwork.py
// L469-L485 at 6ccc2082), with the student off (`stk: false`, the NSynth-100 config, L14; the
// release's LS-100 student is never trained, docs/compared_methods.md): the session's class means
// are the only prototype tokens, each class's first shot is the query of its class, and the loss
// is the cross-entropy of temperature x cos after `attend` (the gated PQA), only `inc_attn` and the
// gate training (L379-L393). `shots` N x D (the frozen encoder's), `labels` N, the session's classes
// in `classes` order.
torch::Tensor session_attention_loss(const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                                     const torch::Tensor& shots, const torch::Tensor& labels,
                                     const std::vector<std::int64_t>& classes, double temperature);

}  // namespace fscil
