#pragma once
#include <map>
#include <string>

namespace fscil {

// The one line a diverged training ends with: where (`what`: a stage and epoch, a session's
// step), then the loss and the other values logged with it (the learning rate), and what to lower.
std::string diverged_training(const std::string& what, const std::map<std::string, double>& values);

}  // namespace fscil
