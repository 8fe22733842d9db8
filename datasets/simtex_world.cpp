// The simulated world: material families and materials, operators and devices, and the
// acquisition context of every recording. docs/datasets.md gives the equations.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "datasets/simtex.h"
#include "datasets/simtex_random.h"

namespace fscil {

using namespace simtex_random;

namespace {

struct Family {
  double base_frequency;  // 1/mm
  double roughness_slope;
  double friction;
  double anisotropy;
  double compliance;
};

struct Operator {
  double speed;  // mm/s
  double force;  // N
  double direction;  // radians
  double drift;
};

struct Device {
  std::vector<double> channel_gain;
  double resonance_fraction;  // of the sample rate
  double resonance_pole;
  double noise_floor;
};

double log_uniform(std::mt19937_64& rng, double low, double high) {
  return std::exp(uniform(rng, std::log(low), std::log(high)));
}

Family family_of(const SimtexConfig& config, int group) {
  auto rng = generator(config.seed, Purpose::family, group);
  Family family;
  family.base_frequency = config.shape == SimtexShape::haptex ? log_uniform(rng, 0.5, 3.5) : log_uniform(rng, 1.0, 12.0);
  family.roughness_slope = uniform(rng, 1.0, 2.5);
  family.friction = uniform(rng, 0.2, 0.8);
  family.anisotropy = uniform(rng, 0.0, 0.8);
  family.compliance = uniform(rng, 0.03, 0.15);
  return family;
}

Operator operator_of(const SimtexConfig& config, int index) {
  auto rng = generator(config.seed, Purpose::operator_habit, index);
  return {40.0 * std::exp(0.25 * normal(rng)), std::exp(0.3 * normal(rng)), uniform(rng, -M_PI / 6, M_PI / 6),
          uniform(rng, 0.01, 0.05)};
}

Device device_of(const SimtexConfig& config, int index) {
  auto rng = generator(config.seed, Purpose::device, index);
  Device device;
  for (int c = 0; c < config.channels(); ++c) device.channel_gain.push_back(std::exp(0.25 * normal(rng)));
  device.resonance_fraction = uniform(rng, 0.15, 0.4);
  device.resonance_pole = uniform(rng, 0.93, 0.985);
  device.noise_floor = uniform(rng, 0.005, 0.03);
  return device;
}

}  // namespace

ContextShift parse_context_shift(const std::string& text) {
  if (text == "none") return ContextShift::none;
  if (text == "device") return ContextShift::device;
  if (text == "speed") return ContextShift::speed;
  throw DatasetError(fmt::format("context_shift='{}': expected none, device or speed", text));
}

std::string to_string(ContextShift shift) {
  return shift == ContextShift::none ? "none" : shift == ContextShift::device ? "device" : "speed";
}

int SimtexConfig::held_out_recordings() const {
  if (context_shift == ContextShift::none) return 0;
  return std::max(2, static_cast<int>(std::lround(0.4 * recordings_per_class)));
}

SimtexMaterial simtex_material(const SimtexConfig& config, int class_index) {
  const int group = class_index * config.groups / config.classes;
  const Family family = family_of(config, group);
  auto rng = generator(config.seed, Purpose::material, class_index);
  SimtexMaterial material;
  for (int k = 0; k < 3; ++k) {
    const double harmonic = k == 0 ? 1.0 : uniform(rng, 1.4, 3.0);
    material.periodic.push_back({family.base_frequency * harmonic * std::exp(0.4 * normal(rng)),
                                 uniform(rng, 0.3, 1.0) / (1 + k), uniform(rng, 0.0, M_PI)});
  }
  material.anisotropy = family.anisotropy;
  material.roughness_rms = uniform(rng, 0.1, 0.6);
  material.roughness_slope = family.roughness_slope + 0.3 * normal(rng);
  material.friction = std::clamp(family.friction * std::exp(0.2 * normal(rng)), 0.05, 1.5);
  material.stick_slip = uniform(rng, 0.0, 0.5);
  material.stick_length = log_uniform(rng, 0.05, 0.5);
  material.compliance = family.compliance * std::exp(0.3 * normal(rng));
  return material;
}

SimtexContext simtex_context(const SimtexConfig& config, int class_index, int recording) {
  // Base training never sees the last device under a device shift.
  const int open_devices = config.context_shift == ContextShift::device ? config.devices - 1 : config.devices;
  auto nominal = generator(config.seed, Purpose::nominal_context, class_index);
  const int home_operator = pick(nominal, config.operators);
  const int home_device = pick(nominal, open_devices);

  const double s = config.context_strength;
  auto rng = generator(config.seed, Purpose::recording_context, class_index, recording);
  const double switch_probability = std::min(1.0, 0.3 * s);
  const bool other_operator = bernoulli(rng, switch_probability);
  const int operator_choice = pick(rng, config.operators);
  const bool other_device = bernoulli(rng, switch_probability);
  const int device_choice = pick(rng, open_devices);

  SimtexContext context;
  context.operator_id = other_operator ? operator_choice : home_operator;
  context.device = other_device ? device_choice : home_device;
  const Operator habits = operator_of(config, context.operator_id);
  context.scan_speed = habits.speed * std::exp(0.15 * s * normal(rng));
  context.normal_force = habits.force * std::exp(0.2 * s * normal(rng));
  context.scan_direction = habits.direction + s * (M_PI / 12) * normal(rng);
  context.drift = habits.drift;
  std::vector<double> jitter;
  for (int c = 0; c < config.channels(); ++c) jitter.push_back(std::exp(0.05 * s * normal(rng)));

  context.held_out = recording >= config.recordings_per_class - config.held_out_recordings();
  if (context.held_out && config.context_shift == ContextShift::device) context.device = config.devices - 1;
  if (context.held_out && config.context_shift == ContextShift::speed) context.scan_speed *= 2.5;

  const Device device = device_of(config, context.device);
  for (int c = 0; c < config.channels(); ++c) context.channel_gain.push_back(device.channel_gain[c] * jitter[c]);
  context.resonance_hz = device.resonance_fraction * config.sample_rate;
  context.resonance_pole = device.resonance_pole;
  context.noise_floor = device.noise_floor;
  return context;
}

}  // namespace fscil
