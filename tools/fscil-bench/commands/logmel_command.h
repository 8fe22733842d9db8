#pragma once
#include <string>

#include "datasets/log_mel_settings.h"

namespace fscil {

struct LogMelOptions {
  std::string input;
  std::string output;
  LogMelSettings settings;
  std::string mel_scale = "htk";
  std::string mel_norm = "none";
  int threads = 0;
};

// Reads /signal (float32, C x L) from input, writes /logmel (float32, C x n_mels x T) to output.
void run_logmel(LogMelOptions options);

}  // namespace fscil
