#include "datasets/readers/wav_file.h"

#include <fmt/format.h>
#include <sndfile.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "core/error.h"
#include "datasets/readers/regular_file.h"

namespace fscil {

namespace {

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};

// libsndfile opens a truncated WAV and quietly shrinks its frame count; its header log keeps
// the evidence as "data : <declared> (should be <present>)".
bool header_promises_more_than_present(SNDFILE* file) {
  std::array<char, 4096> log{};
  sf_command(file, SFC_GET_LOG_INFO, log.data(), static_cast<int>(log.size()));
  const std::string text(log.data());
  const auto data_line = text.find("data :");
  if (data_line == std::string::npos) return false;
  const auto line_end = text.find('\n', data_line);
  return text.substr(data_line, line_end - data_line).find("should be") != std::string::npos;
}

}  // namespace

std::vector<float> read_mono_audio(const std::filesystem::path& path, double expected_rate) {
  if (!names_a_regular_file(path)) {
    throw DatasetError(fmt::format("{}: {}, expected an audio file", path.string(), why_not_a_regular_file(path)));
  }
  SF_INFO info{};
  std::unique_ptr<SNDFILE, SndfileCloser> file(sf_open(path.c_str(), SFM_READ, &info));
  if (!file) {
    throw DatasetError(fmt::format("{}: not a readable audio file ({})", path.string(), sf_strerror(nullptr)));
  }
  if (info.channels != 1) {
    throw DatasetError(fmt::format("{}: {} channels, expected mono", path.string(), info.channels));
  }
  if (info.samplerate != static_cast<int>(std::lround(expected_rate))) {
    throw DatasetError(fmt::format("{}: sample rate {} Hz, expected {} Hz (resample it first; fscil-bench does not "
                                   "resample silently)", path.string(), info.samplerate, expected_rate));
  }
  if (header_promises_more_than_present(file.get())) {
    throw DatasetError(fmt::format("{}: truncated, the header declares more audio data than the file holds",
                                   path.string()));
  }
  if (info.frames <= 0) throw DatasetError(fmt::format("{}: no audio samples, expected a non-empty clip", path.string()));
  std::vector<float> samples(static_cast<std::size_t>(info.frames));
  const sf_count_t read = sf_readf_float(file.get(), samples.data(), info.frames);
  if (read != info.frames) {
    throw DatasetError(fmt::format("{}: truncated, read {} of {} samples", path.string(), read, info.frames));
  }
  if (!std::all_of(samples.begin(), samples.end(), [](float v) { return std::isfinite(v); })) {
    throw DatasetError(fmt::format("{}: NaN or Inf sample, expected finite audio", path.string()));
  }
  return samples;
}

}  // namespace fscil
