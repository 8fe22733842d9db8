#include "datasets/log_mel_extractor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "core/error.h"
#include "core/random_draws.h"

namespace fscil {
namespace {

// An independent double-precision reference: direct DFT of each periodic-Hann frame, Mel
// filters from the textbook formulas, written without any code of the extractor.
double reference_mel(double hz, bool slaney) {
  if (!slaney) return 2595.0 * std::log10(1.0 + hz / 700.0);
  const double f_sp = 200.0 / 3.0, break_hz = 1000.0, log_step = std::log(6.4) / 27.0;
  return hz < break_hz ? hz / f_sp : break_hz / f_sp + std::log(hz / break_hz) / log_step;
}
double reference_hz(double mel, bool slaney) {
  if (!slaney) return 700.0 * (std::pow(10.0, mel / 2595.0) - 1.0);
  const double f_sp = 200.0 / 3.0, break_hz = 1000.0, log_step = std::log(6.4) / 27.0;
  return mel < break_hz / f_sp ? mel * f_sp : break_hz * std::exp(log_step * (mel - break_hz / f_sp));
}

std::vector<double> reference_log_mel(const std::vector<float>& x, const LogMelSettings& s, bool slaney_scale,
                                      bool slaney_norm, std::int64_t* frames_out) {
  const std::int64_t n = s.n_fft, bins = n / 2 + 1, pad = s.center ? n / 2 : 0;
  std::vector<double> padded;
  for (std::int64_t i = pad; i >= 1; --i) padded.push_back(x[i]);
  padded.insert(padded.end(), x.begin(), x.end());
  for (std::int64_t i = 0; i < pad; ++i) padded.push_back(x[x.size() - 2 - i]);
  const std::int64_t frames = 1 + (static_cast<std::int64_t>(padded.size()) - n) / s.hop;
  *frames_out = frames;

  std::vector<double> edges(s.n_mels + 2);
  const double low = reference_mel(0.0, slaney_scale), high = reference_mel(s.sample_rate / 2, slaney_scale);
  for (std::int64_t m = 0; m < s.n_mels + 2; ++m) edges[m] = reference_hz(low + (high - low) * m / (s.n_mels + 1), slaney_scale);

  std::vector<double> out(s.n_mels * frames);
  for (std::int64_t t = 0; t < frames; ++t) {
    std::vector<double> power(bins);
    for (std::int64_t k = 0; k < bins; ++k) {
      std::complex<double> sum = 0;
      for (std::int64_t j = 0; j < n; ++j) {
        const double window = 0.5 - 0.5 * std::cos(2 * M_PI * j / n);
        sum += padded[t * s.hop + j] * window * std::polar(1.0, -2 * M_PI * k * j / n);
      }
      power[k] = std::norm(sum);
    }
    for (std::int64_t m = 0; m < s.n_mels; ++m) {
      double energy = 0;
      for (std::int64_t k = 0; k < bins; ++k) {
        const double f = (s.sample_rate / 2) * k / (bins - 1);
        const double weight = std::max(0.0, std::min((f - edges[m]) / (edges[m + 1] - edges[m]),
                                                     (edges[m + 2] - f) / (edges[m + 2] - edges[m + 1])));
        energy += power[k] * weight * (slaney_norm ? 2.0 / (edges[m + 2] - edges[m]) : 1.0);
      }
      out[m * frames + t] = 10.0 * std::log10(std::max(energy, 1e-10));
    }
  }
  return out;
}

// Broadband noise plus tones: every Mel band carries energy well above float rounding.
std::vector<float> test_signal(std::int64_t length, double sample_rate, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<float> x(length);
  for (std::int64_t i = 0; i < length; ++i) {
    const double t = i / sample_rate;
    x[i] = static_cast<float>(std::sin(2 * M_PI * 0.05 * sample_rate * t) + 0.5 * std::sin(2 * M_PI * 0.21 * sample_rate * t) +
                              normal(rng, 0.0, 0.3));
  }
  return x;
}

struct PresetCase {
  const char* preset;
  std::int64_t length;
  std::int64_t expected_frames;
  bool slaney;
};

void PrintTo(const PresetCase& param, std::ostream* out) {
  *out << param.preset << (param.slaney ? " (Slaney)" : " (HTK)");
}

class LogMelAgreesWithReference : public ::testing::TestWithParam<PresetCase> {};

TEST_P(LogMelAgreesWithReference, WithinOneHundredthOfADecibel) {
  const PresetCase param = GetParam();
  LogMelSettings settings = log_mel_preset(param.preset);
  if (param.slaney) settings.scale = MelScale::slaney, settings.norm = MelNorm::slaney;
  const LogMelExtractor extractor(settings);
  const std::vector<float> x = test_signal(param.length, settings.sample_rate, 7);

  FloatArray signals({1, param.length});
  signals.values = x;
  const FloatArray got = extractor.extract(signals);
  std::int64_t frames = 0;
  const std::vector<double> expected = reference_log_mel(x, settings, param.slaney, param.slaney, &frames);

  ASSERT_EQ(frames, param.expected_frames);
  ASSERT_EQ(got.shape, (std::vector<std::int64_t>{1, settings.n_mels, param.expected_frames}));
  double worst = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) worst = std::max(worst, std::abs(got.values[i] - expected[i]));
  EXPECT_LT(worst, 0.01) << param.preset;
}

// Segment lengths of the paper: 0.5 s at 1 kHz, 0.8 s at 10 kHz, 2 s and 4 s at 16 kHz.
INSTANTIATE_TEST_SUITE_P(
    Presets, LogMelAgreesWithReference,
    ::testing::Values(PresetCase{"haptex", 500, 24, false}, PresetCase{"lmt108", 8000, 493, false},
                      PresetCase{"ls100", 32000, 178, false}, PresetCase{"ns100", 64000, 63, false},
                      PresetCase{"haptex", 500, 24, true}, PresetCase{"ls100", 32000, 178, true}),
    [](const ::testing::TestParamInfo<PresetCase>& info) {
      return std::string(info.param.preset) + (info.param.slaney ? "_slaney" : "_htk");
    });

TEST(LogMelExtractor, BatchesMatchSingleRowsAcrossThreads) {
  const LogMelExtractor extractor(log_mel_preset("haptex"));
  FloatArray batch({6, 5, 500});
  for (std::int64_t row = 0; row < 30; ++row) {
    const auto x = test_signal(500, 1000, static_cast<unsigned>(row));
    std::copy(x.begin(), x.end(), batch.row(0) + row * 500);
  }
  const FloatArray together = extractor.extract(batch, 2);
  ASSERT_EQ(together.shape, (std::vector<std::int64_t>{6, 5, 64, 24}));
  for (std::int64_t row : {0, 17, 29}) {
    FloatArray single({1, 500});
    std::copy(batch.values.begin() + row * 500, batch.values.begin() + (row + 1) * 500, single.values.begin());
    const FloatArray alone = extractor.extract(single, 1);
    for (std::int64_t i = 0; i < 64 * 24; ++i) ASSERT_EQ(alone.values[i], together.values[row * 64 * 24 + i]);
  }
}

TEST(LogMelExtractor, NarrowLowFiltersAreEmptyAndStayAtTheFloor) {
  // LMT108: 65 FFT bins 78 Hz apart, but the lowest HTK filters are ~45 Hz wide, so some
  // catch no bin. HapTex's filters (~12 Hz wide, bins 7.8 Hz apart) all catch one.
  const LogMelExtractor extractor(log_mel_preset("lmt108"));
  EXPECT_GT(extractor.empty_filters(), 0);
  EXPECT_EQ(LogMelExtractor(log_mel_preset("haptex")).empty_filters(), 0);
  EXPECT_GT(LogMelExtractor(log_mel_preset("ls100")).empty_filters(), 0);
  FloatArray signals({1, 8000});
  signals.values = test_signal(8000, 10000, 3);
  const FloatArray out = extractor.extract(signals);
  const MelFilterbank bank = MelFilterbank::build(log_mel_preset("lmt108"));
  int floor_rows = 0;
  for (std::int64_t m = 0; m < 64; ++m) {
    if (bank.end_bin[m] != 0) {
      EXPECT_GT(out.values[m * 493], -100.0f);
      continue;
    }
    ++floor_rows;
    for (std::int64_t t = 0; t < 493; ++t) EXPECT_FLOAT_EQ(out.values[m * 493 + t], -100.0f);
  }
  EXPECT_EQ(floor_rows, extractor.empty_filters());
}

TEST(LogMelExtractor, SilenceIsClampedAtMinusOneHundredDecibels) {
  const LogMelExtractor extractor(log_mel_preset("lmt108"));
  FloatArray silence({2, 8000});
  const FloatArray out = extractor.extract(silence);
  for (float value : out.values) ASSERT_FLOAT_EQ(value, -100.0f);
}

TEST(LogMelExtractor, RejectsNonFiniteSamplesAndTooShortSignals) {
  const LogMelExtractor extractor(log_mel_preset("haptex"));
  FloatArray signals({1, 500});
  signals.values[123] = std::nanf("");
  EXPECT_THROW(extractor.extract(signals), DatasetError);
  FloatArray short_signal({1, 100});
  EXPECT_THROW(extractor.extract(short_signal), DatasetError);

  // Rows are checked in the workers as they are copied; the error names the first bad sample of
  // all, whichever worker met one first.
  FloatArray rows({8, 500});
  rows.values[6 * 500 + 7] = INFINITY;
  rows.values[2 * 500 + 499] = -INFINITY;
  rows.values[5 * 500 + 0] = std::nanf("");
  for (const int threads : {1, 2, 4}) {
    try {
      extractor.extract(rows, threads);
      ADD_FAILURE() << "accepted, " << threads << " threads";
    } catch (const DatasetError& error) {
      EXPECT_STREQ(error.what(), "signal row 2 sample 499 is -inf: finite values expected") << threads;
    }
  }
}

TEST(LogMelSettings, FrameCountsGiveThePapersInputShapes) {
  EXPECT_EQ(log_mel_preset("haptex").frames(500), 24);
  EXPECT_EQ(log_mel_preset("lmt108").frames(8000), 493);
  EXPECT_EQ(log_mel_preset("ls100").frames(32000), 178);
  EXPECT_EQ(log_mel_preset("ns100").frames(64000), 63);
  EXPECT_THROW(log_mel_preset("imagenet"), DatasetError);
}

}  // namespace
}  // namespace fscil
