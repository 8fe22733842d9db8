#include "datasets/simtex.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/parallel_for.h"
#include "datasets/simtex_random.h"

namespace fscil {

std::vector<std::string> SimtexConfig::channel_names() const {
  if (shape == SimtexShape::haptex) {
    return {"friction_force", "normal_force", "friction_coefficient", "displacement", "velocity"};
  }
  return {"acceleration_x", "acceleration_y", "acceleration_z"};
}

std::string SimtexConfig::describe() const {
  return fmt::format("simtex model=4 shape={} classes={} groups={} recordings={} seconds={} sr={} seed={} "
                     "context_strength={} context_shift={} devices={} operators={}",
                     shape == SimtexShape::haptex ? "haptex" : "lmt108", classes, groups, recordings_per_class,
                     recording_seconds, sample_rate, seed, context_strength, to_string(context_shift), devices, operators);
}

SimtexConfig simtex_haptex_config() { return SimtexConfig{}; }

SimtexConfig simtex_lmt_config() {
  SimtexConfig config;
  config.shape = SimtexShape::lmt108;
  config.classes = 108;
  config.groups = 9;
  config.recordings_per_class = 20;
  config.recording_seconds = 4.8;
  config.sample_rate = 10000;
  return config;
}

SimtexConfig simtex_mini_config() {
  SimtexConfig config;
  config.classes = 20;
  config.groups = 4;
  config.recordings_per_class = 6;
  config.recording_seconds = 2.5;
  return config;
}

std::vector<Recording> generate_simtex(const SimtexConfig& config, int threads) {
  std::vector<SimtexMaterial> materials;
  for (int y = 0; y < config.classes; ++y) materials.push_back(simtex_material(config, y));

  const int total = config.classes * config.recordings_per_class;
  std::vector<Recording> recordings(total);
  parallel_for(static_cast<std::size_t>(total), threads, [&](std::size_t index) {
    const int y = static_cast<int>(index) / config.recordings_per_class,
              r = static_cast<int>(index) % config.recordings_per_class;
    auto rng = simtex_random::generator(config.seed, simtex_random::Purpose::recording_signal, y, r);
    Recording recording = simulate_recording(config, materials[y], simtex_context(config, y, r), rng);
    recording.id = fmt::format("c{:03d}_r{:02d}", y, r);
    recording.class_index = y;
    recording.group_index = y * config.groups / config.classes;
    recordings[index] = std::move(recording);
  });
  return recordings;
}

}  // namespace fscil
