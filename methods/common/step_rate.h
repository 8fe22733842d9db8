#pragma once
#include <cstdint>

#include "methods/common/precision.h"

namespace fscil {

// How fast this machine runs the shared encoder on one input shape, per sample: a training step
// (forward, backward and a Nesterov SGD step through ResNet-18 and a cosine classifier, as the
// methods' base sessions train) and an inference pass (eval mode, no gradients). What
// `fscil-bench plan` multiplies by the samples each stage sees.
struct StepRate {
  double train_seconds_per_sample = 0;
  double infer_seconds_per_sample = 0;
  // One optimiser step of a small head on fixed embeddings (a D x D layer and a cosine classifier
  // over 100 classes, a batch of 256): what sessions that train no encoder take many of.
  double head_step_seconds = 0;
};

// Times whole batches of `batch` random log-Mel maps of channels x mel_bins x frames (one untimed
// warm-up step each, then the median of the steps until `seconds` have passed, at least seven),
// and the head step, on the threads torch is set to use, the encoder in `precision`. Draws nothing
// from torch's generator that a run would see.
StepRate measure_step_rate(std::int64_t channels, std::int64_t mel_bins, std::int64_t frames, std::int64_t batch,
                           double seconds = 1.0, Precision precision = Precision::fp32);

}  // namespace fscil
