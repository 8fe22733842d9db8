#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "datasets/recording.h"

namespace fscil {

// sf-instruments: recorded instrument notes on every machine. One note per clip of 100 General
// MIDI melodic programs of MuseScore General (Debian's musescore-general-soundfont), rendered by
// libfluidsynth at 16 kHz, 4 s, in NS-100's shape and protocol (docs/datasets.md).

// General MIDI's melodic families, 8 programs each (0-111): a recording's group is its program / 8.
constexpr int kSfInstrumentFamilies = 14;

// Which note contexts base training never sees: none; high notes; soft notes.
enum class NoteContextShift { none, pitch, velocity };
NoteContextShift parse_note_context_shift(const std::string& text);
std::string to_string(NoteContextShift shift);

struct SfInstrumentsConfig {
  std::filesystem::path soundfont = "/usr/share/sounds/sf3/MuseScore_General_Full.sf3";
  std::string package = "musescore-general-soundfont";
  double sample_rate = 16000;
  double seconds = 4;       // a clip, as NSynth's notes
  double hold_seconds = 3;  // the key is released after 3 s, as in NSynth
  int classes = 100;
  int base_classes = 55;
  // NS-100's clips per class, times `scale`: base classes 200 train, 100 validation, 100 test;
  // novel classes 100 train (5 become shots), 100 validation, 100 test (NS-100 lists none for
  // validation of novel classes: the validation protocol needs them). At least 0.05, so that
  // under a context shift a novel class's held-out clips still give test, shots and validation.
  double scale = 0.25;
  std::uint64_t seed = 1;
  NoteContextShift context_shift = NoteContextShift::none;

  int train_clips(int class_index) const;
  int validation_clips() const;
  int test_clips() const;
  std::string describe() const;  // for the cache key: everything that shapes the clips
};

// The 100 programs (of the 112 melodic ones, 0-111) in class order, drawn from the seed: the
// first `base_classes` are the base classes.
std::vector<int> sf_instrument_programs(const SfInstrumentsConfig& config);

// One clip as drawn, before rendering.
struct SfClip {
  int class_index = 0;
  int program = 0;
  int pitch = 60;
  int velocity = 100;
  SplitHint split = SplitHint::none;  // the list it belongs to; none under a context shift
  bool held_out = false;              // in a context base training never sees
};
// Every clip, class by class; fixed by the seed alone.
std::vector<SfClip> sf_instrument_clips(const SfInstrumentsConfig& config);

// Renders the clips, `threads` at a time; the same config gives the same samples to the bit
// whatever the thread count. A note the instrument cannot play (silent in the font) is played at
// the nearest octave that sounds within the pitches its context allows, and its context says so.
// Each worker decodes the whole font.
std::vector<Recording> render_sf_instruments(const SfInstrumentsConfig& config, int threads = 0);

// The font's bytes as a digest (core/stable_hash.h): part of the cache key. require_soundfont() first.
std::string soundfont_digest(const std::filesystem::path& soundfont, const std::string& package);

}  // namespace fscil
