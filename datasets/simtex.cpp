#include "datasets/simtex.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <thread>

namespace fscil {

namespace {

// splitmix64: derives independent generator seeds for each (purpose, class, recording).
std::uint64_t mix_seed(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ULL;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
  return value ^ (value >> 31);
}

std::mt19937_64 generator_for(std::uint64_t seed, std::uint64_t purpose, std::uint64_t a, std::uint64_t b = 0) {
  return std::mt19937_64(mix_seed(mix_seed(mix_seed(seed ^ purpose) + a) + b));
}

double uniform(std::mt19937_64& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}
double normal(std::mt19937_64& rng) { return std::normal_distribution<double>(0.0, 1.0)(rng); }

// One sinusoidal component of a surface profile: amplitude (um) at a spatial frequency (1/mm).
struct SurfaceComponent {
  double spatial_frequency;
  double amplitude;
};

// Material traits shared by a coarse group, so fine classes of one group look alike.
struct GroupTraits {
  double base_frequency;  // 1/mm
  double roughness_slope;
  double friction;
};

struct Material {
  std::vector<SurfaceComponent> periodic;
  double roughness_rms;
  double roughness_slope;
  double friction;
  double stick_slip;
  double compliance;
};

struct Device {
  std::vector<double> channel_gain;
  double resonance_hz;
  double noise_floor;
};

// The acquisition context of one recording.
struct Context {
  double speed;  // mm/s
  double force;  // N
  int device;
  std::vector<double> gain_jitter;
};

GroupTraits group_traits(const SimtexConfig& config, int group) {
  auto rng = generator_for(config.seed, 1, group);
  const double max_frequency = config.shape == SimtexShape::haptex ? 4.0 : 12.0;
  return {uniform(rng, 0.4, max_frequency), uniform(rng, 1.0, 2.5), uniform(rng, 0.2, 0.8)};
}

Material material_of(const SimtexConfig& config, int class_index, const GroupTraits& group) {
  auto rng = generator_for(config.seed, 2, class_index);
  Material material;
  const int components = 3;
  for (int k = 0; k < components; ++k) {
    const double harmonic = k == 0 ? 1.0 : uniform(rng, 1.3, 3.2);
    material.periodic.push_back(
        {group.base_frequency * harmonic * std::exp(0.25 * normal(rng)), uniform(rng, 0.3, 1.0) / (1 + k)});
  }
  material.roughness_rms = uniform(rng, 0.2, 0.8);
  material.roughness_slope = group.roughness_slope + 0.3 * normal(rng);
  material.friction = std::clamp(group.friction * std::exp(0.15 * normal(rng)), 0.05, 1.5);
  material.stick_slip = uniform(rng, 0.0, 0.4);
  material.compliance = uniform(rng, 0.02, 0.2);
  return material;
}

Device device_of(const SimtexConfig& config, int device) {
  auto rng = generator_for(config.seed, 3, device);
  Device result;
  for (int c = 0; c < config.channels(); ++c) result.channel_gain.push_back(std::exp(0.3 * normal(rng)));
  result.resonance_hz = config.sample_rate * uniform(rng, 0.15, 0.35);
  result.noise_floor = uniform(rng, 0.005, 0.03);
  return result;
}

Context context_of(const SimtexConfig& config, int class_index, int recording) {
  // The class's nominal context: where its operator tends to scan, with which device.
  auto nominal = generator_for(config.seed, 4, class_index);
  const double speed = 40.0 * std::exp(0.3 * normal(nominal));
  const double force = 1.0 * std::exp(0.3 * normal(nominal));
  const int device = static_cast<int>(uniform(nominal, 0, config.devices)) % config.devices;

  auto rng = generator_for(config.seed, 5, class_index, recording);
  const double spread = config.context_strength;
  Context context;
  context.speed = speed * std::exp(0.35 * spread * normal(rng));
  context.force = force * std::exp(0.35 * spread * normal(rng));
  const bool switch_device = uniform(rng, 0, 1) < std::min(1.0, 0.5 * spread);
  const int other = static_cast<int>(uniform(rng, 0, config.devices)) % config.devices;
  context.device = switch_device ? other : device;
  for (int c = 0; c < config.channels(); ++c) context.gain_jitter.push_back(std::exp(0.1 * spread * normal(rng)));
  return context;
}

// Height h, slope h' (per mm) and curvature h'' (per mm^2) of the profile along a scan at
// constant speed; components above 0.45 x the sample rate are left out, as a DAQ's
// anti-aliasing filter would.
struct ProfileTrace {
  std::vector<double> height, slope, curvature;
};

ProfileTrace trace_profile(const std::vector<SurfaceComponent>& components, std::mt19937_64& rng,
                           double speed, double sample_rate, std::int64_t length) {
  ProfileTrace trace{std::vector<double>(length, 0.0), std::vector<double>(length, 0.0),
                     std::vector<double>(length, 0.0)};
  for (const auto& component : components) {
    const double temporal_frequency = component.spatial_frequency * speed;
    const double phase = uniform(rng, 0, 2 * M_PI);
    if (temporal_frequency >= 0.45 * sample_rate) continue;
    const double omega = 2 * M_PI * component.spatial_frequency;
    const std::complex<double> step = std::polar(1.0, 2 * M_PI * temporal_frequency / sample_rate);
    std::complex<double> phasor = std::polar(1.0, phase);
    for (std::int64_t n = 0; n < length; ++n) {
      trace.height[n] += component.amplitude * phasor.imag();
      trace.slope[n] += component.amplitude * omega * phasor.real();
      trace.curvature[n] -= component.amplitude * omega * omega * phasor.imag();
      phasor *= step;
      if ((n & 1023) == 1023) phasor /= std::abs(phasor);  // keep the recurrence on the unit circle
    }
  }
  return trace;
}

// Fractal roughness: log-spaced components with power-law amplitudes, fresh phases per recording.
std::vector<SurfaceComponent> roughness_components(const Material& material, std::mt19937_64& rng,
                                                   double max_spatial_frequency) {
  const int count = 24;
  std::vector<SurfaceComponent> components;
  double total = 0;
  for (int k = 0; k < count; ++k) {
    const double frequency = 0.2 * std::pow(max_spatial_frequency / 0.2, (k + uniform(rng, 0, 1)) / count);
    const double amplitude = std::pow(frequency, -material.roughness_slope / 2);
    components.push_back({frequency, amplitude});
    total += amplitude * amplitude / 2;
  }
  const double scale = material.roughness_rms / std::sqrt(total);
  for (auto& component : components) component.amplitude *= scale;
  return components;
}

// A damped sensor resonance (two-pole band-pass added to the direct path).
void apply_resonance(std::vector<float>& channel, double resonance_hz, double sample_rate) {
  const double r = 0.97;
  const double theta = 2 * M_PI * resonance_hz / sample_rate;
  const double a1 = 2 * r * std::cos(theta), a2 = -r * r, gain = (1 - r) * 2;
  double y1 = 0, y2 = 0;
  for (auto& sample : channel) {
    const double y = gain * sample + a1 * y1 + a2 * y2;
    y2 = y1;
    y1 = y;
    sample = static_cast<float>(sample + y);
  }
}

Recording simulate_recording(const SimtexConfig& config, int class_index, int recording_number,
                             const Material& material, const std::vector<Device>& devices) {
  const Context context = context_of(config, class_index, recording_number);
  const Device& device = devices[context.device];
  auto rng = generator_for(config.seed, 6, class_index, recording_number);
  const std::int64_t length = static_cast<std::int64_t>(std::llround(config.recording_seconds * config.sample_rate));
  const double max_spatial = config.shape == SimtexShape::haptex ? 10.0 : 50.0;

  std::vector<SurfaceComponent> components = material.periodic;
  for (const auto& component : roughness_components(material, rng, max_spatial)) components.push_back(component);
  const ProfileTrace trace = trace_profile(components, rng, context.speed, config.sample_rate, length);

  Recording recording;
  recording.id = fmt::format("c{:03d}_r{:02d}", class_index, recording_number);
  recording.class_index = class_index;
  recording.channels = config.channels();
  recording.length = length;
  recording.signal.assign(recording.channels * length, 0.0f);
  recording.context = {{"scan_speed", context.speed}, {"normal_force", context.force},
                       {"device", static_cast<double>(context.device)}};

  auto channel = [&](int c) { return recording.signal.data() + c * length; };
  const double dt = 1.0 / config.sample_rate;
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::int64_t n = 0; n < length; ++n) {
    const double h = trace.height[n], slope = trace.slope[n], curvature = trace.curvature[n];
    // Stiffer contact at higher force: the profile couples more strongly into the forces.
    const double coupling = std::sqrt(context.force);
    const double normal_force = context.force * (1.0 + material.compliance * coupling * h);
    const double stick = material.stick_slip * std::tanh(3.0 * slope);
    const double friction_force = material.friction * normal_force * (1.0 + stick) + 0.02 * coupling * slope;
    if (config.shape == SimtexShape::haptex) {
      channel(0)[n] = static_cast<float>(friction_force);
      channel(1)[n] = static_cast<float>(normal_force);
      channel(2)[n] = static_cast<float>(friction_force / std::max(normal_force, 1e-3));
      channel(3)[n] = static_cast<float>(context.speed * n * dt + 1e-3 * h);
      channel(4)[n] = static_cast<float>(context.speed * (1.0 + 0.01 * slope));
    } else {
      const double v2 = context.speed * context.speed * 1e-3;  // acceleration scale of the profile
      channel(0)[n] = static_cast<float>(material.friction * coupling * context.speed * slope * 1e-2 + stick);
      channel(1)[n] = static_cast<float>(0.3 * material.friction * context.speed * slope * 1e-2);
      channel(2)[n] = static_cast<float>(v2 * curvature * coupling * 1e-2);
    }
  }
  for (int c = 0; c < recording.channels; ++c) {
    std::vector<float> samples(channel(c), channel(c) + length);
    if (config.shape == SimtexShape::lmt108 || c < 2) apply_resonance(samples, device.resonance_hz, config.sample_rate);
    const double gain = device.channel_gain[c] * context.gain_jitter[c];
    double rms = 0;
    for (float s : samples) rms += s * s;
    rms = std::sqrt(rms / length) + 1e-6;
    for (std::int64_t n = 0; n < length; ++n) {
      channel(c)[n] = static_cast<float>(gain * (samples[n] + device.noise_floor * rms * noise(rng)));
    }
  }
  return recording;
}

}  // namespace

std::vector<std::string> SimtexConfig::channel_names() const {
  if (shape == SimtexShape::haptex) {
    return {"friction_force", "normal_force", "friction_coefficient", "displacement", "velocity"};
  }
  return {"acceleration_x", "acceleration_y", "acceleration_z"};
}

std::string SimtexConfig::describe() const {
  return fmt::format("simtex shape={} classes={} groups={} recordings={} seconds={} sr={} seed={} "
                     "context_strength={} devices={} model=1",
                     shape == SimtexShape::haptex ? "haptex" : "lmt108", classes, groups,
                     recordings_per_class, recording_seconds, sample_rate, seed, context_strength, devices);
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
  std::vector<Material> materials;
  for (int y = 0; y < config.classes; ++y) {
    const int group = y * config.groups / config.classes;
    materials.push_back(material_of(config, y, group_traits(config, group)));
  }
  std::vector<Device> devices;
  for (int d = 0; d < config.devices; ++d) devices.push_back(device_of(config, d));

  const int total = config.classes * config.recordings_per_class;
  std::vector<Recording> recordings(total);
  const int workers = std::max(1, threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) {
    pool.emplace_back([&, w] {
      for (int index = w; index < total; index += workers) {
        const int y = index / config.recordings_per_class, r = index % config.recordings_per_class;
        recordings[index] = simulate_recording(config, y, r, materials[y], devices);
        recordings[index].group_index = y * config.groups / config.classes;
      }
    });
  }
  for (auto& thread : pool) thread.join();
  return recordings;
}

}  // namespace fscil
