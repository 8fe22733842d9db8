#include "datasets/log_mel_settings.h"

#include <fmt/format.h>

#include "core/error.h"

namespace fscil {

std::int64_t LogMelSettings::frames(std::int64_t length) const {
  if (center) return 1 + length / hop;
  if (length < n_fft) return 0;
  return 1 + (length - n_fft) / hop;
}

std::string LogMelSettings::describe() const {
  return fmt::format("sr={} n_fft={} hop={} n_mels={} f_min={} f_max={} center={} scale={} norm={}",
                     sample_rate, n_fft, hop, n_mels, f_min, f_max, center,
                     scale == MelScale::htk ? "htk" : "slaney",
                     norm == MelNorm::none ? "none" : "slaney");
}

LogMelSettings log_mel_preset(const std::string& name) {
  LogMelSettings settings;
  if (name == "haptex") {
    settings.sample_rate = 1000, settings.n_fft = 128, settings.hop = 16, settings.n_mels = 64;
    settings.center = false;
  } else if (name == "lmt108") {
    settings.sample_rate = 10000, settings.n_fft = 128, settings.hop = 16, settings.n_mels = 64;
    settings.center = false;
  } else if (name == "ls100") {
    settings.sample_rate = 16000, settings.n_fft = 400, settings.hop = 180, settings.n_mels = 128;
    settings.center = true;
  } else if (name == "ns100") {
    settings.sample_rate = 16000, settings.n_fft = 2048, settings.hop = 1024, settings.n_mels = 128;
    settings.center = true;
  } else {
    throw DatasetError(fmt::format("unknown log-Mel preset '{}': expected one of {}", name,
                                   fmt::join(log_mel_preset_names(), ", ")));
  }
  return settings;
}

std::vector<std::string> log_mel_preset_names() { return {"haptex", "lmt108", "ls100", "ns100"}; }

MelScale parse_mel_scale(const std::string& text) {
  if (text == "htk") return MelScale::htk;
  if (text == "slaney") return MelScale::slaney;
  throw DatasetError(fmt::format("Mel scale '{}': expected htk or slaney", text));
}

MelNorm parse_mel_norm(const std::string& text) {
  if (text == "none") return MelNorm::none;
  if (text == "slaney") return MelNorm::slaney;
  throw DatasetError(fmt::format("Mel norm '{}': expected none or slaney", text));
}

}  // namespace fscil
