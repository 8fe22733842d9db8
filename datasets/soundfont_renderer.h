#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fscil {

// One note of a General MIDI program (bank 0), as a clip: held for `hold_seconds`, then released
// until `total_seconds`.
struct NoteRequest {
  int program = 0;
  int pitch = 60;  // MIDI key
  int velocity = 100;
  double hold_seconds = 3;
  double total_seconds = 4;
};

// DatasetError naming the file and `package` (which installs it) when the SoundFont is missing.
void require_soundfont(const std::filesystem::path& soundfont, const std::string& package);

// A SoundFont loaded by libfluidsynth, rendering notes offline: no reverb or chorus, mono (the
// mean of the synthesizer's two channels). Each note is rendered by a synthesizer made for it
// alone, as libfluidsynth's synthesizers carry state from one note to the next (a note rendered
// after others differs from the same note rendered first), so a note's samples depend on the
// request alone. One renderer per thread: the loaded font is not shared between threads.
class SoundfontRenderer {
 public:
  // require_soundfont(), then DatasetError naming the file when libfluidsynth cannot load it.
  // Every worker holds its own decoded copy of the font (hundreds of MB for MuseScore General).
  SoundfontRenderer(const std::filesystem::path& soundfont, double sample_rate, const std::string& package);
  ~SoundfontRenderer();
  SoundfontRenderer(const SoundfontRenderer&) = delete;
  SoundfontRenderer& operator=(const SoundfontRenderer&) = delete;

  std::vector<float> render(const NoteRequest& note) const;
  // The program's preset name in the font, e.g. "Grand Piano"; empty when it has none.
  std::string preset_name(int program) const;

 private:
  struct Loaded;
  std::unique_ptr<Loaded> loaded_;
  double sample_rate_;
};

}  // namespace fscil
