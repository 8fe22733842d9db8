#include "tools/fscil-bench/commands/logmel_command.h"

#include <fmt/format.h>

#include <filesystem>

#include "core/error.h"
#include "datasets/hdf5_file.h"
#include "datasets/log_mel_extractor.h"

namespace fscil {

void run_logmel(LogMelOptions options) {
  options.settings.scale = parse_mel_scale(options.mel_scale);
  options.settings.norm = parse_mel_norm(options.mel_norm);
  std::error_code ignored;
  if (std::filesystem::equivalent(options.input, options.output, ignored)) {
    throw DatasetError(fmt::format("--output {}: is the input file; write the log-Mel features elsewhere",
                                   options.output));
  }
  const FloatArray signal = read_hdf5_floats(options.input, "/signal", 2);
  if (signal.shape[0] < 1 || signal.shape[1] < 1) {
    throw DatasetError(fmt::format("{}: dataset '/signal' is {} x {}, expected C x L with C, L >= 1", options.input,
                                   signal.shape[0], signal.shape[1]));
  }
  const LogMelExtractor extractor(options.settings);
  if (extractor.empty_filters() > 0) {
    fmt::print(stderr, "warning: {} of {} Mel filters are empty at n_fft={}; their rows stay at -100 dB\n",
               extractor.empty_filters(), options.settings.n_mels, options.settings.n_fft);
  }
  FloatArray logmel;
  try {
    logmel = extractor.extract(signal, options.threads);
  } catch (const DatasetError& error) {
    throw DatasetError(fmt::format("{}: dataset '/signal': {}", options.input, error.what()));
  }
  Hdf5Contents contents;
  contents.floats["logmel"] = &logmel;
  const LogMelSettings& settings = options.settings;
  contents.attributes = {{"format_version", "1"},
                         {"source", options.input + ":/signal"},
                         {"sample_rate", fmt::format("{}", settings.sample_rate)},
                         {"n_fft", std::to_string(settings.n_fft)},
                         {"hop", std::to_string(settings.hop)},
                         {"n_mels", std::to_string(settings.n_mels)},
                         {"center", settings.center ? "true" : "false"},
                         {"mel_scale", options.mel_scale},
                         {"mel_norm", options.mel_norm},
                         {"layout", "channels x mel bins x frames, dB"}};
  write_hdf5_atomically(options.output, contents);
}

}  // namespace fscil
