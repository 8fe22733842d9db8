#include "datasets/log_mel_extractor.h"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>

#include "core/error.h"
#include "core/parallel_for.h"
#include "datasets/finite_values.h"

namespace fscil {

namespace {

// FFTW's planner is not re-entrant: plan creation and destruction must be serialised.
std::mutex& fftw_planner_mutex() {
  static std::mutex mutex;
  return mutex;
}

constexpr float kPowerFloor = 1e-10f;
// Frames windowed and transformed together: their input and spectra stay in the L1/L2 caches.
constexpr std::int64_t kFrameBlock = 32;
// Every frame and spectrum of a block starts on a 64-byte boundary: the plan's SIMD kernels
// require the alignment of the arrays it was planned on (65 bins of 8 bytes would break it).
std::int64_t frame_stride_of(const LogMelSettings& settings) { return (settings.n_fft + 15) / 16 * 16; }
std::int64_t spectrum_stride_of(const LogMelSettings& settings) { return (settings.frequency_bins() + 7) / 8 * 8; }

struct FftwBuffer {
  explicit FftwBuffer(std::size_t bytes) : data(fftwf_malloc(bytes)) {}
  ~FftwBuffer() { fftwf_free(data); }
  FftwBuffer(const FftwBuffer&) = delete;
  FftwBuffer& operator=(const FftwBuffer&) = delete;
  void* data;
};

// 10 log10(max(x, floor)) for every element, in a form the compiler vectorises (std::log10 is a
// library call per element and took most of the front end's time). ln(m) for m in
// [sqrt(1/2), sqrt(2)) is 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.172: the series to s^9 is
// exact to float precision (next term 3e-10).
__attribute__((target_clones("avx2", "default"))) void decibels_in_place(float* values, std::int64_t count) {
  constexpr float kDecibelsPerLn = 4.3429448190325175f;  // 10 / ln(10)
  constexpr float kLn2 = 0.6931471805599453f;
  std::int32_t floor_bits;
  std::memcpy(&floor_bits, &kPowerFloor, sizeof floor_bits);
  for (std::int64_t i = 0; i < count; ++i) {
    // Powers are >= 0, whose bit patterns order like the values: an integer max clamps them
    // (a float comparison here stops GCC from vectorising the loop).
    std::int32_t bits;
    std::memcpy(&bits, values + i, sizeof bits);
    bits = std::max(bits, floor_bits);
    // Split x = m 2^e with m in [sqrt(1/2), sqrt(2)): subtracting sqrt(1/2)'s bits first makes
    // the exponent field round at sqrt(2) instead of at 2.
    const std::int32_t shifted = bits - 0x3f3504f3;
    const auto exponent = static_cast<float>(shifted >> 23);
    const std::int32_t mantissa_bits = (shifted & 0x007fffff) + 0x3f3504f3;
    float m;
    std::memcpy(&m, &mantissa_bits, sizeof m);
    const float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
    const float series = s * (2.0f + s2 * (2.0f / 3 + s2 * (2.0f / 5 + s2 * (2.0f / 7 + s2 * (2.0f / 9)))));
    values[i] = kDecibelsPerLn * (series + exponent * kLn2);
  }
}

constexpr std::int64_t kMaxFftSize = LogMelSettings::kMaxFftSize;
constexpr std::int64_t kMaxMelBins = LogMelSettings::kMaxMelBins;

// Checked before the filterbank is built from them.
const LogMelSettings& checked(const LogMelSettings& settings) {
  const bool valid_rate = std::isfinite(settings.sample_rate) && settings.sample_rate > 0;
  const bool valid_band = std::isfinite(settings.f_min) && std::isfinite(settings.f_max) && settings.f_min >= 0 &&
                          settings.f_max >= 0;
  const bool valid_sizes = settings.n_fft >= 2 && settings.n_fft <= kMaxFftSize && settings.hop >= 1 &&
                           settings.n_mels >= 1 && settings.n_mels <= kMaxMelBins;
  if (!valid_sizes || !valid_rate || !valid_band) {
    throw DatasetError(fmt::format("log-Mel settings {}: n_fft in [2, {}], hop >= 1, n_mels in [1, {}], a positive "
                                   "sample rate and finite band edges >= 0 expected", settings.describe(), kMaxFftSize,
                                   kMaxMelBins));
  }
  return settings;
}

}  // namespace

struct LogMelExtractor::Plan {
  fftwf_plan plan = nullptr;
};

LogMelExtractor::LogMelExtractor(const LogMelSettings& settings)
    : settings_(checked(settings)), filterbank_(MelFilterbank::build(settings)), plan_(std::make_unique<Plan>()) {
  // Some empty filters are a warning (torchaudio's too); all empty are features of nothing.
  if (filterbank_.empty_filters() == settings.n_mels) {
    throw DatasetError(fmt::format("sample rate {} Hz with n_fft {}: all {} Mel filters are empty, so every feature "
                                   "would be -100 dB; expected the recordings' sample rate in Hz", settings.sample_rate,
                                   settings.n_fft, settings.n_mels));
  }
  window_.resize(settings.n_fft);
  for (std::int64_t n = 0; n < settings.n_fft; ++n) {
    window_[n] = static_cast<float>(0.5 - 0.5 * std::cos(2.0 * M_PI * n / settings.n_fft));
  }
  for (std::int64_t m = 0; m < settings.n_mels; ++m) {
    filter_offset_.push_back(filter_weights_.size());
    for (std::int64_t k = filterbank_.first_bin[m]; k < filterbank_.end_bin[m]; ++k) {
      filter_weights_.push_back(static_cast<float>(filterbank_.weights[k * settings.n_mels + m]));
    }
  }
  FftwBuffer in(sizeof(float) * settings.n_fft);
  FftwBuffer out(sizeof(fftwf_complex) * settings.frequency_bins());
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  // FFTW_ESTIMATE picks the same algorithm on every run, so features are reproducible. For one
  // transform it picks SIMD kernels; for a batch (plan_many) it picks a scalar one.
  plan_->plan = fftwf_plan_dft_r2c_1d(static_cast<int>(settings.n_fft), static_cast<float*>(in.data),
                                      static_cast<fftwf_complex*>(out.data), FFTW_ESTIMATE);
  if (plan_->plan == nullptr) throw DatasetError("FFTW could not plan the log-Mel transform");
}

LogMelExtractor::~LogMelExtractor() {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  if (plan_ && plan_->plan != nullptr) fftwf_destroy_plan(plan_->plan);
}

FloatArray LogMelExtractor::extract(const FloatArray& signals, int threads) const {
  if (signals.shape.empty()) throw DatasetError("log-Mel input has no dimensions");
  const std::int64_t length = signals.shape.back();
  const std::int64_t rows = length == 0 ? 0 : signals.size() / length;
  std::vector<std::int64_t> shape(signals.shape.begin(), signals.shape.end() - 1);
  shape.push_back(settings_.n_mels);
  shape.push_back(frames(length));
  FloatArray out(shape);
  extract_rows(signals.values.data(), rows, length, out.values.data(), threads);
  return out;
}

void LogMelExtractor::check_length(std::int64_t length) const {
  const std::int64_t pad = settings_.center ? settings_.n_fft / 2 : 0;
  if (settings_.center && length <= pad) {
    throw DatasetError(fmt::format("signal of {} samples is too short to reflect-pad by {}", length, pad));
  }
  if (frames(length) < 1) {
    throw DatasetError(fmt::format("signal of {} samples is shorter than n_fft {}", length, settings_.n_fft));
  }
}

void LogMelExtractor::extract_rows(const float* signals, std::int64_t rows, std::int64_t length, float* out,
                                   int threads) const {
  check_length(length);
  if (rows == 0) return;
  const auto workers = std::min<std::int64_t>(thread_count(threads), rows);
  // One contiguous block of rows per worker: extract_range sets up its FFT buffers once per call.
  // Each row is checked for finite samples by its worker as it reaches it, rather than in a serial
  // pass over the whole input first (on NS-100's batch that pass was one more trip through memory).
  const std::int64_t chunk = (rows + workers - 1) / workers;
  std::atomic<bool> all_rows_finite{true};
  parallel_for(static_cast<std::size_t>((rows + chunk - 1) / chunk), static_cast<int>(workers), [&](std::size_t block) {
    const std::int64_t first = static_cast<std::int64_t>(block) * chunk, last = std::min(rows, first + chunk);
    if (!extract_range(signals, first, last, length, out)) all_rows_finite = false;
  });
  if (!all_rows_finite) {  // the first non-finite sample of all, whichever worker met one
    const std::int64_t i = first_non_finite(signals, rows * length);
    throw DatasetError(fmt::format("signal row {} sample {} is {}: finite values expected", i / length, i % length,
                                   signals[i]));
  }
}

// Compiled twice, for AVX2 and for any x86-64, chosen at load time: the windowing, power, Mel and
// decibel loops run on 8 floats at a time where the CPU allows it.
__attribute__((target_clones("avx2", "default")))
bool LogMelExtractor::extract_range(const float* signals, std::int64_t first, std::int64_t last,
                                    std::int64_t length, float* out) const {
  const std::int64_t n_fft = settings_.n_fft, hop = settings_.hop, n_mels = settings_.n_mels;
  const std::int64_t bins = settings_.frequency_bins();
  const std::int64_t frame_count = frames(length);
  const std::int64_t pad = settings_.center ? n_fft / 2 : 0;
  const std::int64_t block = std::min(kFrameBlock, frame_count);
  const std::int64_t frame_stride = frame_stride_of(settings_), spectrum_stride = spectrum_stride_of(settings_);
  FftwBuffer frame_buffer(sizeof(float) * frame_stride * block);
  FftwBuffer spectrum_buffer(sizeof(fftwf_complex) * spectrum_stride * block);
  auto* windowed = static_cast<float*>(frame_buffer.data);
  auto* spectrum = static_cast<fftwf_complex*>(spectrum_buffer.data);
  std::vector<float> power(bins * frame_count);

  for (std::int64_t row = first; row < last; ++row) {
    const float* x = signals + row * length;
    if (!all_finite(x, length)) return false;

    // Blocks of frames small enough to stay in cache.
    for (std::int64_t first_frame = 0; first_frame < frame_count; first_frame += block) {
      const std::int64_t count = std::min(block, frame_count - first_frame);
      for (std::int64_t t = 0; t < count; ++t) {
        // The frame's first sample in x; frames that reach into the padding read it in place (no
        // padded copy of the signal: for NS-100 that copy was a pass over the whole batch).
        const std::int64_t begin = (first_frame + t) * hop - pad;
        float* frame = windowed + t * frame_stride;
        if (begin >= 0 && begin + n_fft <= length) {
          const float* start = x + begin;
          for (std::int64_t n = 0; n < n_fft; ++n) frame[n] = start[n] * window_[n];
        } else {
          // torch's reflect padding mirrors around the edge sample without repeating it.
          for (std::int64_t n = 0; n < n_fft; ++n) {
            const std::int64_t i = begin + n;
            frame[n] = x[i < 0 ? -i : (i >= length ? 2 * length - 2 - i : i)] * window_[n];
          }
        }
      }
      for (std::int64_t t = 0; t < count; ++t) {
        fftwf_execute_dft_r2c(plan_->plan, windowed + t * frame_stride, spectrum + t * spectrum_stride);
      }
      // Bin-major power (bin k of frame t at k * frames + t): each Mel filter reads whole rows.
      for (std::int64_t t = 0; t < count; ++t) {
        const fftwf_complex* frame_spectrum = spectrum + t * spectrum_stride;
        float* column = power.data() + first_frame + t;
        for (std::int64_t k = 0; k < bins; ++k) {
          column[k * frame_count] =
              frame_spectrum[k][0] * frame_spectrum[k][0] + frame_spectrum[k][1] * frame_spectrum[k][1];
        }
      }
    }
    float* mel_out = out + row * n_mels * frame_count;
    for (std::int64_t m = 0; m < n_mels; ++m) {
      float* energy = mel_out + m * frame_count;
      std::fill(energy, energy + frame_count, 0.0f);
      const float* weights = filter_weights_.data() + filter_offset_[m];
      for (std::int64_t k = filterbank_.first_bin[m]; k < filterbank_.end_bin[m]; ++k) {
        const float weight = weights[k - filterbank_.first_bin[m]];
        const float* bin_power = power.data() + k * frame_count;
        for (std::int64_t t = 0; t < frame_count; ++t) energy[t] += weight * bin_power[t];
      }
    }
    decibels_in_place(mel_out, n_mels * frame_count);
  }
  return true;
}

}  // namespace fscil
