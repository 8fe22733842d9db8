#include "datasets/soundfont_renderer.h"

#include <fluidsynth.h>
#include <fmt/format.h>

#include <cmath>
#include <mutex>

#include "core/error.h"

namespace fscil {

namespace {

// libfluidsynth prints its messages to stderr by default; a dataset's errors are ours to report,
// in one line.
void silence_library_log() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int level : {FLUID_PANIC, FLUID_ERR, FLUID_WARN, FLUID_INFO, FLUID_DBG}) {
      fluid_set_log_function(level, nullptr, nullptr);
    }
  });
}

}  // namespace

void require_soundfont(const std::filesystem::path& soundfont, const std::string& package) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(soundfont, error)) {
    throw DatasetError(fmt::format("{}: no such SoundFont (Debian's package {} installs it; tools/bootstrap.sh "
                                   "does)", soundfont.string(), package));
  }
}

struct SoundfontRenderer::Loaded {
  fluid_settings_t* settings = nullptr;
  fluid_synth_t* owner = nullptr;  // holds the font; notes are rendered by synthesizers of their own
  fluid_sfont_t* font = nullptr;

  ~Loaded() {
    if (owner != nullptr) delete_fluid_synth(owner);
    if (settings != nullptr) delete_fluid_settings(settings);
  }
};

SoundfontRenderer::SoundfontRenderer(const std::filesystem::path& soundfont, double sample_rate,
                                     const std::string& package)
    : loaded_(std::make_unique<Loaded>()), sample_rate_(sample_rate) {
  require_soundfont(soundfont, package);
  silence_library_log();
  Loaded& loaded = *loaded_;
  loaded.settings = new_fluid_settings();
  fluid_settings_setnum(loaded.settings, "synth.sample-rate", sample_rate);
  fluid_settings_setint(loaded.settings, "synth.reverb.active", 0);
  fluid_settings_setint(loaded.settings, "synth.chorus.active", 0);
  // Every sample decoded at load: rendering then only reads the font.
  fluid_settings_setint(loaded.settings, "synth.dynamic-sample-loading", 0);
  loaded.owner = new_fluid_synth(loaded.settings);
  const int id = loaded.owner == nullptr ? FLUID_FAILED : fluid_synth_sfload(loaded.owner, soundfont.c_str(), 0);
  if (id == FLUID_FAILED) {
    throw DatasetError(fmt::format("{}: libfluidsynth cannot load it as a SoundFont (SF2 or SF3)", soundfont.string()));
  }
  loaded.font = fluid_synth_get_sfont_by_id(loaded.owner, id);
}

SoundfontRenderer::~SoundfontRenderer() = default;

std::string SoundfontRenderer::preset_name(int program) const {
  fluid_preset_t* preset = fluid_sfont_get_preset(loaded_->font, 0, program);
  return preset == nullptr ? std::string() : std::string(fluid_preset_get_name(preset));
}

std::vector<float> SoundfontRenderer::render(const NoteRequest& note) const {
  const auto total = static_cast<int>(std::lround(note.total_seconds * sample_rate_));
  const auto held = static_cast<int>(std::lround(note.hold_seconds * sample_rate_));
  std::vector<float> left(static_cast<std::size_t>(total)), right(static_cast<std::size_t>(total));
  // Nothing below throws until the synthesizer is deleted. It borrows the owner's font and gives
  // it back before it goes, so the font is freed once, with the owner.
  fluid_synth_t* synth = new_fluid_synth(loaded_->settings);
  if (synth == nullptr) throw DatasetError("libfluidsynth could not make a synthesizer");
  const int id = fluid_synth_add_sfont(synth, loaded_->font);
  bool played = id != FLUID_FAILED && fluid_synth_program_select(synth, 0, id, 0, note.program) == FLUID_OK &&
                fluid_synth_noteon(synth, 0, note.pitch, note.velocity) == FLUID_OK &&
                fluid_synth_write_float(synth, held, left.data(), 0, 1, right.data(), 0, 1) == FLUID_OK;
  if (played) {
    fluid_synth_noteoff(synth, 0, note.pitch);  // fails when the note has died away already (a pizzicato)
    played = fluid_synth_write_float(synth, total - held, left.data(), held, 1, right.data(), held, 1) == FLUID_OK;
  }
  if (id != FLUID_FAILED) fluid_synth_remove_sfont(synth, loaded_->font);  // the owner frees it
  delete_fluid_synth(synth);
  if (!played) {
    throw DatasetError(fmt::format("libfluidsynth could not play program {} key {} velocity {}", note.program,
                                   note.pitch, note.velocity));
  }
  std::vector<float> mono(left.size());
  for (std::size_t i = 0; i < mono.size(); ++i) mono[i] = 0.5f * (left[i] + right[i]);
  return mono;
}

}  // namespace fscil
