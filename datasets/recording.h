#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace fscil {

// Which side of a dataset's own division a recording belongs to, when it has one (LMT108 ships
// training and testing recordings; LS-100 and NS-100 ship train/validation/test lists).
enum class SplitHint { none, train, test, validation };

// One continuous acquisition: a C x L signal of one class under one acquisition context.
struct Recording {
  std::string id;
  int class_index = 0;
  int group_index = 0;
  std::int64_t channels = 0;
  std::int64_t length = 0;
  std::vector<float> signal;  // channel-major, channels x length
  std::map<std::string, double> context;  // acquisition context values, when known
  SplitHint split_hint = SplitHint::none;
};

}  // namespace fscil
