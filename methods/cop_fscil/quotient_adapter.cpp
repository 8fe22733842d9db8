#include "methods/cop_fscil/quotient_adapter.h"

#include "methods/common/module_cost.h"

namespace fscil {

namespace {

torch::Tensor reflect(const torch::Tensor& v, const torch::Tensor& x) {
  const torch::Tensor scale = 2 * (v * x).sum(1, true) / (v * v).sum(1, true).clamp_min(1e-12);
  return x - scale * v;
}

std::int64_t hidden_width(const QuotientAdapterOptions& options) {
  return options.hidden > 0 ? options.hidden : options.dim;
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
      hidden_(register_module("hidden", torch::nn::Linear(options.dim, hidden_width(options)))),
      output_(register_module("output", torch::nn::Linear(hidden_width(options), options.reflections * options.dim))) {
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

double QuotientAdapterImpl::dropped_share_off_fixed_channels(const torch::Tensor& originals) {
  torch::NoGradGuard no_grad;
  const std::int64_t dim = options_.dim, sensitive = dim - options_.invariant_dim;
  if (sensitive == 0 || originals.size(0) == 0) return 0.0;
  const torch::Tensor basis = torch::eye(dim, originals.options()).narrow(0, options_.invariant_dim, sensitive);
  constexpr std::int64_t chunk = 32;  // bounds the chunk x d_sen x m x D repeated reflections
  double overlap = 0;
  for (std::int64_t first = 0; first < originals.size(0); first += chunk) {
    const std::int64_t n = std::min(chunk, originals.size(0) - first);
    const torch::Tensor reflections = reflections_of(originals.narrow(0, first, n));
    const torch::Tensor moved = apply_q_transpose(reflections.repeat_interleave(sensitive, 0), basis.repeat({n, 1}));
    overlap += moved.narrow(1, options_.invariant_dim, sensitive).pow(2).sum().item<double>();
  }
  return 1.0 - overlap / static_cast<double>(sensitive * originals.size(0));
}

void QuotientAdapterImpl::count_cost(ModelCost& cost, const std::string& name) const {
  count_linear(cost, name + ".hidden", *hidden_);
  count_linear(cost, name + ".output", *output_);
  cost.add({name + ".reflections", "reflections", reflections_macs(options_.dim, 2 * options_.reflections)});
}

torch::Tensor pic_invariant(const torch::Tensor& invariant, const torch::Tensor& z, PicSpace space) {
  namespace F = torch::nn::functional;
  const auto unit = F::NormalizeFuncOptions().dim(1);
  switch (space) {
    case PicSpace::raw: return invariant;
    case PicSpace::normalised: return invariant / z.norm(2, 1, true).clamp_min(1e-12);
    case PicSpace::invariant: return F::normalize(invariant, unit);
  }
  return invariant;
}

torch::Tensor probe_invariance_loss(const torch::Tensor& original_invariant, const torch::Tensor& probe_invariants) {
  return (original_invariant.unsqueeze(0) - probe_invariants.detach()).pow(2).sum(2).mean();
}

}  // namespace fscil
