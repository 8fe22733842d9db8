#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace fscil {

// Mean and covariance (np.cov, N - 1) of each class's rows, in the order of `classes`
// (DSN's Inc_train.py L165-L172 for the base classes, L192-L197 for a session's shots; LDC's
// helper.py L31-L38 and update_fc_avg in Network.py alike).
std::pair<torch::Tensor, torch::Tensor> class_statistics(const torch::Tensor& embeddings, const torch::Tensor& labels,
                                                          const std::vector<std::int64_t>& classes);

// np.cov of the rows (N x D), divided by N - 1; zeros for a single row (ours: np.cov gives NaN).
torch::Tensor sample_covariance(const torch::Tensor& rows);
// F with F F^T = covariance, from its eigendecomposition in float64 with negative eigenvalues (a
// few shots give a rank-deficient, barely indefinite estimate) set to zero. The releases draw with
// numpy's multivariate_normal, which factors by SVD: the same distribution for a positive
// semi-definite matrix.
torch::Tensor gaussian_factor(const torch::Tensor& covariance);

}  // namespace fscil
