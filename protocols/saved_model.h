#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "methods/method.h"

namespace fscil {

// What a saved model says about itself, so it can be used without the run's other files.
struct SavedModelMetadata {
  std::string method, dataset, identity, git_commit;  // identity: the run's (its checkpoint's)
  std::uint64_t seed = 0;
  std::vector<std::int64_t> input_shape;  // channels, mel bins, frames of one input segment
  // The class each output index stands for: output p is class_order[p] of the dataset, named so.
  std::vector<std::string> class_order;
};

struct SavedModel {
  MethodState state;
  SavedModelMetadata metadata;
};

// The format name a saved model carries ("format"), raised when its layout changes.
inline constexpr const char* kSavedModelFormat = "fscil-bench model 1";

// --save-model: a method's trained state as a file that Python's `torch.load(path)` reads as a
// dict {"format": kSavedModelFormat, "metadata": {...}, "state": {name: tensor}}, the state's names
// as Method::save_state() gives them ("encoder.conv1.weight"; a count a method keeps as
// "NAME.count", e.g. "seen_classes.count"), and load_saved_model reads back: LibTorch's pickle,
// the zip format of torch.save. Written atomically.
void save_model(const std::filesystem::path& path, const SavedModel& model);

// ProtocolError naming the file when it is not a saved model of this format.
SavedModel load_saved_model(const std::filesystem::path& path);

}  // namespace fscil
