#pragma once
#include <torch/torch.h>

namespace fscil {

// DSN's session loss in its three parts (models/DSN.py L91-L107 at 5bc87b96).
struct DsnSessionLoss {
  torch::Tensor cross_entropy;  // CE of temperature x cosines over every seen class
  // Soft-target cross-entropy (not KL) between the network before the session and this one over
  // the old classes' columns, both scaled by the temperature and divided by T = 0.5 (L101-L107).
  // Under the release's "part" optimiser the two networks' old columns are equal, so the term has
  // no gradient and its value is the teacher's entropy.
  torch::Tensor distillation;
  // 0.1 x relu(|gate|_1 / N - r) with r = 0, i.e. 0.1 x the mean gate (L97-L99: the release's r is
  // a parameter at 0 that no optimiser holds, so --r is never read); zero without a new row.
  torch::Tensor compression;
  torch::Tensor total() const { return cross_entropy + distillation + compression; }
};

// `cosines`: rows x seen classes; `teacher_cosines`: the same rows x old classes as the network
// before the session scores them; `gate`: the newest session's training gate, undefined when the
// batch held no new-class row (Inc_train.py L331-L333 then drops the compression term).
DsnSessionLoss dsn_session_loss(const torch::Tensor& cosines, const torch::Tensor& labels,
                                const torch::Tensor& teacher_cosines, const torch::Tensor& gate, double temperature);

}  // namespace fscil
