#pragma once
#include <cstdint>
#include <vector>

namespace fscil {

// A signal as read from disk, channel-major (channels x length).
struct SignalData {
  std::int64_t channels = 0;
  std::int64_t length = 0;
  std::vector<float> values;
};

}  // namespace fscil
