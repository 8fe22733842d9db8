#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

namespace fscil {

// A signal as read from disk, channel-major (channels x length).
struct SignalData {
  std::int64_t channels = 0;
  std::int64_t length = 0;
  std::vector<float> values;
};

// One channel per file (LMT108's X/Y/Z files, a folder recording's TXT per channel), read with
// `read_channel` and stacked in file order. Throws DatasetError naming the file whose length
// differs from the first's.
SignalData stack_channel_files(const std::vector<std::filesystem::path>& files,
                               const std::function<SignalData(const std::filesystem::path&)>& read_channel);

}  // namespace fscil
