// sf-instruments rendered from the installed SoundFont: the same samples to the bit whatever the
// thread count, pinned to a digest (a new libfluidsynth or font shows here first), and notes an
// instrument cannot play moved an octave down. Slow: each renderer loads the whole font.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/stable_hash.h"
#include "datasets/sf_instruments.h"
#include "datasets/soundfont_renderer.h"

namespace fscil {
namespace {

SfInstrumentsConfig three_classes() {
  SfInstrumentsConfig config;
  config.classes = 3;
  config.base_classes = 2;
  config.scale = 0.05;  // 10 (base) or 5 (novel) training clips, 5 validation, 5 test
  return config;
}

std::string digest_of(const std::vector<Recording>& recordings) {
  std::string bytes;
  for (const Recording& recording : recordings) {
    bytes.append(reinterpret_cast<const char*>(recording.signal.data()), recording.signal.size() * sizeof(float));
  }
  return stable_hash(bytes);
}

TEST(SfRendering, TheSameSamplesWhateverTheThreadCountPinnedToADigest) {
  const std::vector<Recording> one = render_sf_instruments(three_classes(), 1);
  const std::vector<Recording> two = render_sf_instruments(three_classes(), 2);
  ASSERT_EQ(one.size(), 2u * 20 + 15);
  ASSERT_EQ(two.size(), one.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].id, two[i].id);
    ASSERT_EQ(one[i].length, 64000);
    ASSERT_EQ(two[i].signal.size(), one[i].signal.size());
    EXPECT_EQ(one[i].context, two[i].context) << one[i].id;
    ASSERT_EQ(std::memcmp(one[i].signal.data(), two[i].signal.data(), one[i].signal.size() * sizeof(float)), 0)
        << one[i].id;
    const float loudest = *std::max_element(one[i].signal.begin(), one[i].signal.end());
    EXPECT_GT(loudest, 1e-4f) << one[i].id << " is (nearly) silent";
  }
  // musescore-general-soundfont 0.2.1-1 and libfluidsynth 2.3.1 (Debian 12).
  EXPECT_EQ(soundfont_digest(three_classes().soundfont, three_classes().package), "e8060aaeff0bc83f");
  EXPECT_EQ(digest_of(one), "c3e951ceedaeb3a3");
}

TEST(SfRendering, ANoteOutsideTheInstrumentsRangeIsSilentInTheFont) {
  const SoundfontRenderer renderer(three_classes().soundfont, 16000, "musescore-general-soundfont");
  const auto peak = [&](int pitch) {
    const std::vector<float> samples = renderer.render({43, pitch, 100, 3, 4});  // 43: contrabass
    float most = 0;
    for (const float s : samples) most = std::max(most, std::abs(s));
    return most;
  };
  EXPECT_EQ(peak(84), 0.0f);  // why render_sf_instruments moves such notes an octave down
  EXPECT_GT(peak(72), 1e-3f);
  EXPECT_EQ(renderer.preset_name(0), "Grand Piano");
}

}  // namespace
}  // namespace fscil
