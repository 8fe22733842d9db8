#pragma once
#include <filesystem>

#include "methods/method.h"

namespace fscil {

// --save-model: a method's trained state as a file that Python's `torch.load(path)` reads as a
// dict of named tensors (names as Method::save_state() gives them, e.g. "encoder.conv1.weight")
// and load_saved_model reads back: LibTorch's pickle, the zip format of torch.save. Written
// atomically.
void save_model(const std::filesystem::path& path, const MethodState& state);

// ProtocolError naming the file when it is not a dict of named tensors.
MethodState load_saved_model(const std::filesystem::path& path);

}  // namespace fscil
