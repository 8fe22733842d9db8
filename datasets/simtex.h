#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "datasets/recording.h"

namespace fscil {

// Which real dataset the simulated one is shaped like.
enum class SimtexShape { haptex, lmt108 };

// Which acquisition contexts base training never sees (held out for shots and tests).
enum class ContextShift { none, device, speed };
ContextShift parse_context_shift(const std::string& text);
std::string to_string(ContextShift shift);

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
  ContextShift context_shift = ContextShift::none;
  int devices = 4;
  int operators = 6;

  int channels() const { return shape == SimtexShape::haptex ? 5 : 3; }
  std::vector<std::string> channel_names() const;
  std::string describe() const;
  // Recordings per class acquired in held-out contexts (0 without a context shift).
  int held_out_recordings() const;
};

SimtexConfig simtex_haptex_config();  // HapTex-shaped: 120 classes, 5 channels, 1 kHz
SimtexConfig simtex_lmt_config();     // LMT108-shaped: 108 classes, 3 channels, 10 kHz
SimtexConfig simtex_mini_config();    // 20 small classes for tests

// One sinusoidal component of a surface: amplitude (um) at a spatial frequency (1/mm), with the
// direction of its wave vector (radians) for anisotropic textures.
struct SurfaceComponent {
  double spatial_frequency;
  double amplitude;
  double orientation = 0;
};

struct SimtexMaterial {
  std::vector<SurfaceComponent> periodic;
  double anisotropy = 0;       // 0: direction does not matter; 1: pure gratings
  double roughness_rms = 0;    // um
  double roughness_slope = 2;  // power-spectrum slope of the fractal roughness
  double friction = 0.5;       // coefficient at 1 N
  double stick_slip = 0;       // relative amplitude of the stick-slip oscillation
  double stick_length = 0.1;   // mm slid per stick-slip cycle
  double compliance = 0.1;     // how strongly the profile modulates the normal force
};

// The acquisition context of one recording: who scanned how, with which device.
struct SimtexContext {
  double scan_speed = 40;   // mm/s
  double normal_force = 1;  // N
  double scan_direction = 0;  // radians
  int device = 0;
  int operator_id = 0;
  std::vector<double> channel_gain;
  double resonance_hz = 0;     // sensor resonance; 0 = none
  double resonance_pole = 0.97;  // closer to 1 = less damped
  double noise_floor = 0;      // noise RMS relative to the channel RMS
  double drift = 0;            // relative amplitude of the slow force drift
  bool held_out = false;       // acquired in a context base training never sees
};

SimtexMaterial simtex_material(const SimtexConfig& config, int class_index);
SimtexContext simtex_context(const SimtexConfig& config, int class_index, int recording);

// One recording of `material` under `context`; `rng` draws the surface spot and sensor noise.
Recording simulate_recording(const SimtexConfig& config, const SimtexMaterial& material,
                             const SimtexContext& context, std::mt19937_64& rng);

// Deterministic from config.seed; recordings are ordered by class, then recording number.
std::vector<Recording> generate_simtex(const SimtexConfig& config, int threads = 0);

}  // namespace fscil
