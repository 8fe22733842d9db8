#include "datasets/readers/signal_data.h"

#include <fmt/format.h>

#include "core/error.h"

namespace fscil {

SignalData stack_channel_files(const std::vector<std::filesystem::path>& files,
                               const std::function<SignalData(const std::filesystem::path&)>& read_channel) {
  SignalData signal;
  for (const auto& file : files) {
    const SignalData channel = read_channel(file);
    if (signal.channels > 0 && channel.length != signal.length) {
      throw DatasetError(fmt::format("{}: {} samples, expected {} like {} (channels of a recording must align)",
                                     file.string(), channel.length, signal.length, files.front().string()));
    }
    signal.length = channel.length;
    signal.channels += channel.channels;
    signal.values.insert(signal.values.end(), channel.values.begin(), channel.values.end());
  }
  return signal;
}

}  // namespace fscil
