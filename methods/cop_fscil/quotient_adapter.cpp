#include "methods/cop_fscil/quotient_adapter.h"

#include "methods/common/module_cost.h"

namespace fscil {

namespace {

torch::Tensor reflect(const torch::Tensor& v, const torch::Tensor& x) {
  const torch::Tensor scale = 2 * (v * x).sum(1, true) / (v * v).sum(1, true).clamp_min(1e-12);
  return x - scale * v;
}

}  // namespace

torch::Tensor apply_q(const torch::Tensor& reflections, const torch::Tensor& x) {
  torch::Tensor y = x;
  for (std::int64_t k = 0; k < reflections.size(1); ++k) y = reflect(reflections.select(1, k), y);
  return y;
}

torch::Tensor apply_q_transpose(const torch::Tensor& reflections, const torch::Tensor& x) {
  torch::Tensor y = x;
  for (std::int64_t k = reflections.size(1) - 1; k >= 0; --k) y = reflect(reflections.select(1, k), y);
  return y;
}

QuotientAdapterImpl::QuotientAdapterImpl(const QuotientAdapterOptions& options)
    : options_(options),
      hidden_(register_module("hidden", torch::nn::Linear(options.dim, options.dim))),
      output_(register_module("output", torch::nn::Linear(options.dim, options.reflections * options.dim))) {
  TORCH_CHECK(options.invariant_dim > 0 && options.invariant_dim <= options.dim, "invariant_dim must be in [1, dim]");
}

torch::Tensor QuotientAdapterImpl::reflections_of(const torch::Tensor& original) {
  return output_->forward(torch::relu(hidden_->forward(original))).view({-1, options_.reflections, options_.dim});
}

QuotientAdapterImpl::Projection QuotientAdapterImpl::project(const torch::Tensor& reflections,
                                                             const torch::Tensor& z) const {
  const torch::Tensor p = apply_q(reflections, z);
  Projection projection;
  projection.invariant = p.narrow(1, 0, options_.invariant_dim);
  const torch::Tensor kept = torch::cat(
      {projection.invariant, torch::zeros({z.size(0), options_.dim - options_.invariant_dim}, z.options())}, 1);
  projection.quotient = apply_q_transpose(reflections, kept);
  return projection;
}

void QuotientAdapterImpl::count_cost(ModelCost& cost, const std::string& name) const {
  count_linear(cost, name + ".hidden", *hidden_);
  count_linear(cost, name + ".output", *output_);
  cost.add({name + ".reflections", "reflections", reflections_macs(options_.dim, 2 * options_.reflections)});
}

torch::Tensor probe_invariance_loss(const torch::Tensor& original_invariant, const torch::Tensor& probe_invariants) {
  return (original_invariant.unsqueeze(0) - probe_invariants.detach()).pow(2).sum(2).mean();
}

}  // namespace fscil
