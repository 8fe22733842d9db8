#pragma once
#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

namespace fscil {

// A module of a method by the name its tensors are saved under ("encoder" -> "encoder.conv.weight").
struct NamedModule {
  std::string name;
  std::shared_ptr<torch::nn::Module> module;
  // Counted as "trained in sessions" in the cost table: the module learn_session() trains.
  bool trained_in_sessions = false;
};
using NamedModules = std::vector<NamedModule>;

}  // namespace fscil
