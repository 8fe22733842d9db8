#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/recording.h"

namespace fscil {

// Which real dataset the simulated one is shaped like.
enum class SimtexShape { haptex, lmt108 };

struct SimtexConfig {
  SimtexShape shape = SimtexShape::haptex;
  int classes = 120;
  int groups = 10;
  int recordings_per_class = 10;
  double recording_seconds = 5.0;
  double sample_rate = 1000;
  std::uint64_t seed = 1;
  // 0: every recording of a class shares the class's context; larger: wider spread around it.
  double context_strength = 1.0;
  int devices = 3;

  int channels() const { return shape == SimtexShape::haptex ? 5 : 3; }
  std::vector<std::string> channel_names() const;
  std::string describe() const;
};

SimtexConfig simtex_haptex_config();  // HapTex-shaped: 120 classes, 5 channels, 1 kHz
SimtexConfig simtex_lmt_config();     // LMT108-shaped: 108 classes, 3 channels, 10 kHz
SimtexConfig simtex_mini_config();    // 20 small classes for tests

// Deterministic from config.seed; recordings are ordered by class, then recording number.
std::vector<Recording> generate_simtex(const SimtexConfig& config, int threads = 0);

}  // namespace fscil
