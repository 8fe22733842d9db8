#include "datasets/sf_instruments.h"

#include <fluidsynth.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <numeric>

#include "core/error.h"
#include "core/parallel_for.h"
#include "core/random_draws.h"
#include "core/seeded_shuffle.h"
#include "core/stable_hash.h"
#include "datasets/soundfont_renderer.h"

namespace fscil {

namespace {

constexpr int kMelodicPrograms = 8 * kSfInstrumentFamilies;  // 112-119 are percussive, 120-127 sound effects
constexpr int kLowestPitch = 36, kHighestPitch = 84;  // C2 to C6, inclusive
constexpr int kHeldOutPitch = 72;  // pitch shift: base training sees notes below C5 only
constexpr int kVelocities[] = {25, 50, 75, 100, 127};  // NSynth's
constexpr int kSoftVelocities = 2;  // velocity shift: base training never hears 25 or 50
constexpr float kSilence = 1e-6f;

enum Purpose : std::uint64_t { programs = 11, clip = 12 };

std::mt19937_64 generator(std::uint64_t seed, Purpose purpose, std::uint64_t a = 0, std::uint64_t b = 0) {
  return derived_generator(seed, purpose, a, b);
}

int scaled(int count, double scale, int least) {
  return std::max(least, static_cast<int>(std::lround(count * scale)));
}

struct PitchRange {
  int low, high;  // inclusive
};

// The pitches a clip may sound: under a pitch shift, open and held-out clips never share one.
PitchRange pitch_range(const SfInstrumentsConfig& config, bool held_out) {
  if (config.context_shift != NoteContextShift::pitch) return {kLowestPitch, kHighestPitch};
  return held_out ? PitchRange{kHeldOutPitch, kHighestPitch} : PitchRange{kLowestPitch, kHeldOutPitch - 1};
}

SfClip draw_clip(const SfInstrumentsConfig& config, int class_index, int program, int number, SplitHint split,
                 bool held_out) {
  auto rng = generator(config.seed, Purpose::clip, static_cast<std::uint64_t>(class_index),
                       static_cast<std::uint64_t>(number));
  const PitchRange pitches = pitch_range(config, held_out);
  int first_velocity = 0;
  int velocities = static_cast<int>(std::size(kVelocities));
  if (config.context_shift == NoteContextShift::velocity) {
    first_velocity = held_out ? 0 : kSoftVelocities;
    velocities = held_out ? kSoftVelocities : velocities - kSoftVelocities;
  }
  SfClip clip;
  clip.class_index = class_index;
  clip.program = program;
  clip.pitch = static_cast<int>(uniform_int(rng, pitches.low, pitches.high));
  clip.velocity = kVelocities[first_velocity + uniform_int(rng, 0, velocities - 1)];
  clip.split = split;
  clip.held_out = held_out;
  return clip;
}

Recording render_clip(const SfInstrumentsConfig& config, const SoundfontRenderer& renderer, const SfClip& clip,
                      int number) {
  // A key outside the instrument's range sounds nothing in the font: the nearest octave that
  // sounds, within the pitches the clip's context allows.
  const PitchRange allowed = pitch_range(config, clip.held_out);
  NoteRequest note{clip.program, clip.pitch, clip.velocity, config.hold_seconds, config.seconds};
  std::vector<float> samples;
  for (const int octaves : {0, -1, 1, -2, 2, -3, 3, -4, 4}) {
    note.pitch = clip.pitch + 12 * octaves;
    if (note.pitch < allowed.low || note.pitch > allowed.high) continue;
    samples = renderer.render(note);
    if (std::any_of(samples.begin(), samples.end(), [](float s) { return std::abs(s) >= kSilence; })) break;
    samples.clear();
  }
  if (samples.empty()) {
    throw DatasetError(fmt::format("{}: program {} sounds at no octave of key {} within {}-{}",
                                   config.soundfont.string(), clip.program, clip.pitch, allowed.low, allowed.high));
  }
  Recording recording;
  recording.id = fmt::format("gm{:03d}_{:04d}", clip.program, number);
  recording.class_index = clip.class_index;
  recording.group_index = clip.program / 8;
  recording.channels = 1;
  recording.length = static_cast<std::int64_t>(samples.size());
  recording.signal = std::move(samples);
  recording.context = {{"pitch", static_cast<double>(note.pitch)},
                       {"velocity", static_cast<double>(clip.velocity)},
                       {"held_out", clip.held_out ? 1.0 : 0.0}};
  recording.split_hint = clip.split;
  return recording;
}

}  // namespace

NoteContextShift parse_note_context_shift(const std::string& text) {
  if (text == "none") return NoteContextShift::none;
  if (text == "pitch") return NoteContextShift::pitch;
  if (text == "velocity") return NoteContextShift::velocity;
  throw DatasetError(fmt::format("context_shift='{}': expected none, pitch or velocity", text));
}

std::string to_string(NoteContextShift shift) {
  switch (shift) {
    case NoteContextShift::none: return "none";
    case NoteContextShift::pitch: return "pitch";
    case NoteContextShift::velocity: return "velocity";
  }
  return "none";
}

int SfInstrumentsConfig::train_clips(int class_index) const {
  // A novel class keeps at least the 5 clips its shots are drawn from.
  return class_index < base_classes ? scaled(200, scale, 2) : scaled(100, scale, 5);
}
int SfInstrumentsConfig::validation_clips() const { return scaled(100, scale, 1); }
int SfInstrumentsConfig::test_clips() const { return scaled(100, scale, 1); }

std::string SfInstrumentsConfig::describe() const {
  return fmt::format("sf-instruments model=1 soundfont={} fluidsynth={} sr={} seconds={} hold={} classes={} base={} "
                     "scale={} seed={} context_shift={} pitches={}-{} velocities=25,50,75,100,127",
                     soundfont.string(), fluid_version_str(), sample_rate, seconds, hold_seconds, classes,
                     base_classes, scale, seed, to_string(context_shift), kLowestPitch, kHighestPitch);
}

std::vector<int> sf_instrument_programs(const SfInstrumentsConfig& config) {
  if (config.classes > kMelodicPrograms) {
    throw DatasetError(fmt::format("sf-instruments: {} classes, at most {} melodic programs", config.classes,
                                   kMelodicPrograms));
  }
  std::vector<int> programs(kMelodicPrograms);
  std::iota(programs.begin(), programs.end(), 0);
  auto rng = generator(config.seed, Purpose::programs);
  shuffle_with(programs, rng);
  programs.resize(static_cast<std::size_t>(config.classes));
  return programs;
}

std::vector<SfClip> sf_instrument_clips(const SfInstrumentsConfig& config) {
  const std::vector<int> programs = sf_instrument_programs(config);
  std::vector<SfClip> clips;
  const bool shifted = config.context_shift != NoteContextShift::none;
  for (int y = 0; y < config.classes; ++y) {
    int number = 0;
    const auto add = [&](int count, SplitHint split, bool held_out) {
      for (int i = 0; i < count; ++i) {
        clips.push_back(draw_clip(config, y, programs[y], number++, shifted ? SplitHint::none : split, held_out));
      }
    };
    // Under a shift the protocol splits the clips itself (protocols/session_schedule.cpp): base
    // training and validation from the open contexts, shots, scored validation and test from
    // the held-out ones, where a novel class's every clip is.
    const bool novel = y >= config.base_classes;
    add(config.train_clips(y), SplitHint::train, shifted && novel);
    add(config.validation_clips(), SplitHint::validation, shifted);
    add(config.test_clips(), SplitHint::test, shifted);
  }
  return clips;
}

std::vector<Recording> render_sf_instruments(const SfInstrumentsConfig& config, int threads) {
  const std::vector<SfClip> clips = sf_instrument_clips(config);
  std::vector<std::size_t> class_start(static_cast<std::size_t>(config.classes) + 1, clips.size());
  for (std::size_t i = clips.size(); i-- > 0;) class_start[static_cast<std::size_t>(clips[i].class_index)] = i;
  // A renderer loads the whole font (seconds): one per worker, handed from class to class.
  std::mutex pool_lock;
  std::vector<std::unique_ptr<SoundfontRenderer>> idle;
  std::vector<Recording> recordings(clips.size());
  parallel_for(static_cast<std::size_t>(config.classes), threads, [&](std::size_t y) {
    std::unique_ptr<SoundfontRenderer> renderer;
    {
      const std::lock_guard<std::mutex> guard(pool_lock);
      if (!idle.empty()) {
        renderer = std::move(idle.back());
        idle.pop_back();
      }
    }
    if (!renderer) renderer = std::make_unique<SoundfontRenderer>(config.soundfont, config.sample_rate, config.package);
    for (std::size_t i = class_start[y]; i < class_start[y + 1]; ++i) {
      recordings[i] = render_clip(config, *renderer, clips[i], static_cast<int>(i - class_start[y]));
    }
    const std::lock_guard<std::mutex> guard(pool_lock);
    idle.push_back(std::move(renderer));
  });
  return recordings;
}

std::string soundfont_digest(const std::filesystem::path& soundfont, const std::string& package) {
  require_soundfont(soundfont, package);
  std::ifstream in(soundfont, std::ios::binary);
  if (!in) throw DatasetError(fmt::format("{}: cannot read the SoundFont", soundfont.string()));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return stable_hash(bytes);
}

}  // namespace fscil
