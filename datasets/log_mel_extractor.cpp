#include "datasets/log_mel_extractor.h"

#include <fftw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <thread>

#include "datasets/dataset_error.h"

namespace fscil {

namespace {

// FFTW's planner is not re-entrant: plan creation and destruction must be serialised.
std::mutex& fftw_planner_mutex() {
  static std::mutex mutex;
  return mutex;
}

constexpr float kPowerFloor = 1e-10f;

struct FftwBuffer {
  explicit FftwBuffer(std::size_t bytes) : data(fftwf_malloc(bytes)) {}
  ~FftwBuffer() { fftwf_free(data); }
  FftwBuffer(const FftwBuffer&) = delete;
  FftwBuffer& operator=(const FftwBuffer&) = delete;
  void* data;
};

}  // namespace

struct LogMelExtractor::Plan {
  fftwf_plan plan = nullptr;
};

LogMelExtractor::LogMelExtractor(const LogMelSettings& settings)
    : settings_(settings), filterbank_(MelFilterbank::build(settings)), plan_(std::make_unique<Plan>()) {
  if (settings.n_fft < 2 || settings.hop < 1 || settings.n_mels < 1 || settings.sample_rate <= 0) {
    throw DatasetError(fmt::format("log-Mel settings {}: n_fft >= 2, hop >= 1, n_mels >= 1 and a "
                                   "positive sample rate expected", settings.describe()));
  }
  window_.resize(settings.n_fft);
  for (std::int64_t n = 0; n < settings.n_fft; ++n) {
    window_[n] = static_cast<float>(0.5 - 0.5 * std::cos(2.0 * M_PI * n / settings.n_fft));
  }
  FftwBuffer in(sizeof(float) * settings.n_fft);
  FftwBuffer out(sizeof(fftwf_complex) * settings.frequency_bins());
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  plan_->plan = fftwf_plan_dft_r2c_1d(static_cast<int>(settings.n_fft), static_cast<float*>(in.data),
                                      static_cast<fftwf_complex*>(out.data), FFTW_MEASURE);
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

void LogMelExtractor::extract_rows(const float* signals, std::int64_t rows, std::int64_t length,
                                   float* out, int threads) const {
  const std::int64_t pad = settings_.center ? settings_.n_fft / 2 : 0;
  if (settings_.center && length <= pad) {
    throw DatasetError(fmt::format("signal of {} samples is too short to reflect-pad by {}", length, pad));
  }
  if (frames(length) < 1) {
    throw DatasetError(fmt::format("signal of {} samples is shorter than n_fft {}", length, settings_.n_fft));
  }
  for (std::int64_t i = 0; i < rows * length; ++i) {
    if (!std::isfinite(signals[i])) {
      throw DatasetError(fmt::format("signal row {} sample {} is {}: finite values expected",
                                     i / length, i % length, signals[i]));
    }
  }
  const int available = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int workers = static_cast<int>(std::min<std::int64_t>(available, rows));
  if (workers <= 1) {
    extract_range(signals, 0, rows, length, out);
    return;
  }
  std::vector<std::thread> pool;
  const std::int64_t chunk = (rows + workers - 1) / workers;
  for (int w = 0; w < workers; ++w) {
    const std::int64_t first = w * chunk, last = std::min(rows, first + chunk);
    if (first >= last) break;
    pool.emplace_back([=] { extract_range(signals, first, last, length, out); });
  }
  for (auto& thread : pool) thread.join();
}

void LogMelExtractor::extract_range(const float* signals, std::int64_t first, std::int64_t last,
                                    std::int64_t length, float* out) const {
  const std::int64_t n_fft = settings_.n_fft, hop = settings_.hop, n_mels = settings_.n_mels;
  const std::int64_t bins = settings_.frequency_bins();
  const std::int64_t frame_count = frames(length);
  const std::int64_t pad = settings_.center ? n_fft / 2 : 0;

  FftwBuffer frame_buffer(sizeof(float) * n_fft);
  FftwBuffer spectrum_buffer(sizeof(fftwf_complex) * bins);
  auto* frame = static_cast<float*>(frame_buffer.data);
  auto* spectrum = static_cast<fftwf_complex*>(spectrum_buffer.data);
  std::vector<float> padded(length + 2 * pad);
  std::vector<float> power(bins);

  for (std::int64_t row = first; row < last; ++row) {
    const float* x = signals + row * length;
    // torch's reflect padding mirrors around the edge sample without repeating it.
    for (std::int64_t i = 0; i < pad; ++i) padded[i] = x[pad - i];
    std::copy(x, x + length, padded.begin() + pad);
    for (std::int64_t i = 0; i < pad; ++i) padded[pad + length + i] = x[length - 2 - i];

    float* mel_out = out + row * n_mels * frame_count;
    for (std::int64_t t = 0; t < frame_count; ++t) {
      const float* start = padded.data() + t * hop;
      for (std::int64_t n = 0; n < n_fft; ++n) frame[n] = start[n] * window_[n];
      fftwf_execute_dft_r2c(plan_->plan, frame, spectrum);
      for (std::int64_t k = 0; k < bins; ++k) {
        power[k] = spectrum[k][0] * spectrum[k][0] + spectrum[k][1] * spectrum[k][1];
      }
      for (std::int64_t m = 0; m < n_mels; ++m) {
        double energy = 0.0;
        for (std::int64_t k = filterbank_.first_bin[m]; k < filterbank_.end_bin[m]; ++k) {
          energy += power[k] * filterbank_.weights[k * n_mels + m];
        }
        mel_out[m * frame_count + t] = 10.0f * std::log10(std::max(static_cast<float>(energy), kPowerFloor));
      }
    }
  }
}

}  // namespace fscil
