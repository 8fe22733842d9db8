// sf-instruments' plan (which instruments, notes and lists; no rendering) follows NS-100 and the
// seed, and keeps the held-out contexts apart under a context shift.
#include "datasets/sf_instruments.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "core/error.h"

namespace fscil {
namespace {

TEST(SfInstruments, ASeedDrawsOneHundredDistinctMelodicProgramsAndAnotherSeedOthers) {
  SfInstrumentsConfig config;
  const std::vector<int> programs = sf_instrument_programs(config);
  ASSERT_EQ(programs.size(), 100u);
  EXPECT_EQ(std::set<int>(programs.begin(), programs.end()).size(), 100u);
  for (const int program : programs) EXPECT_TRUE(program >= 0 && program < 112) << program;
  EXPECT_EQ(sf_instrument_programs(config), programs);
  config.seed = 2;
  EXPECT_NE(sf_instrument_programs(config), programs);
}

TEST(SfInstruments, AQuarterOfNs100sClipsPerClassInItsLists) {
  const SfInstrumentsConfig config;  // scale 0.25
  std::map<int, std::map<SplitHint, int>> lists;
  for (const SfClip& clip : sf_instrument_clips(config)) {
    ++lists[clip.class_index][clip.split];
    EXPECT_FALSE(clip.held_out);
    EXPECT_TRUE(clip.pitch >= 36 && clip.pitch <= 84) << clip.pitch;
    EXPECT_TRUE(std::set<int>({25, 50, 75, 100, 127}).count(clip.velocity)) << clip.velocity;
  }
  ASSERT_EQ(lists.size(), 100u);
  const std::map<SplitHint, int> base = {{SplitHint::train, 50}, {SplitHint::validation, 25}, {SplitHint::test, 25}};
  const std::map<SplitHint, int> novel = {{SplitHint::train, 25}, {SplitHint::validation, 25}, {SplitHint::test, 25}};
  EXPECT_EQ(lists[0], base);
  EXPECT_EQ(lists[54], base);
  EXPECT_EQ(lists[55], novel);
  EXPECT_EQ(lists[99], novel);
}

TEST(SfInstruments, UnderAShiftBaseTrainingNotesNeverShareTheHeldOutContexts) {
  SfInstrumentsConfig config;
  config.scale = 0.1;
  for (const NoteContextShift shift : {NoteContextShift::pitch, NoteContextShift::velocity}) {
    config.context_shift = shift;
    int held_out = 0, open = 0;
    for (const SfClip& clip : sf_instrument_clips(config)) {
      EXPECT_EQ(clip.split, SplitHint::none);  // the protocol splits around the held-out contexts
      const bool high = clip.pitch >= 72, soft = clip.velocity <= 50;
      EXPECT_EQ(clip.held_out, shift == NoteContextShift::pitch ? high : soft) << clip.pitch << " " << clip.velocity;
      (clip.held_out ? held_out : open) += 1;
    }
    // A base class's validation and test clips (10 + 10) in the held-out contexts, its 20 training
    // clips not; a novel class's every clip (10 + 10 + 10), as its shots come from there too.
    EXPECT_EQ(held_out, 55 * 20 + 45 * 30) << to_string(shift);
    EXPECT_EQ(open, 55 * 20) << to_string(shift);
  }
}

TEST(SfInstruments, AMissingSoundfontIsOneErrorNamingTheFileAndThePackage) {
  SfInstrumentsConfig config;
  config.soundfont = "/nonexistent/General.sf3";
  config.classes = 1;
  try {
    render_sf_instruments(config, 1);
    FAIL() << "rendered without a SoundFont";
  } catch (const DatasetError& error) {
    EXPECT_STREQ(error.what(), "/nonexistent/General.sf3: no such SoundFont (Debian's package "
                               "musescore-general-soundfont installs it; tools/bootstrap.sh does)");
  }
  // The cache key's digest reads the font first: the same line.
  try {
    soundfont_digest(config.soundfont, config.package);
    FAIL() << "a digest of no SoundFont";
  } catch (const DatasetError& error) {
    EXPECT_NE(std::string(error.what()).find("musescore-general-soundfont installs it"), std::string::npos);
  }
  EXPECT_THROW(parse_note_context_shift("device"), DatasetError);
}

}  // namespace
}  // namespace fscil
