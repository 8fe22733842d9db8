#pragma once
#include <optional>
#include <string>

namespace fscil {

// PyTorch's (or torchaudio's) rate for one benchmark figure ("train/haptex_5x64x24",
// "log_mel/lmt108"), as pytorch_anchors.py measured it earlier in the same `bench` run and wrote
// to the JSON file named by FSCIL_PYTORCH_ANCHORS. Empty when that variable is unset; a file
// that cannot be read, was measured with other threads or lacks the figure ends the program
// with one error line.
std::optional<double> pytorch_rate(const std::string& figure);

// The label of a figure compared against its anchor: "1.35x PyTorch, target >= 1.2x: met", or
// why there is no comparison.
std::string anchor_label(double ours, const std::optional<double>& theirs, double target, const std::string& whose);

}  // namespace fscil
