// Turns a material and an acquisition context into sensor signals (docs/datasets.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "datasets/simtex.h"
#include "datasets/simtex_random.h"

namespace fscil {

using namespace simtex_random;

namespace {

// Sums of sinusoids evaluated by phasor recurrence (one complex multiply per sample).
struct SinusoidSum {
  std::vector<double> value, derivative, second_derivative;  // per unit of the phase variable
  explicit SinusoidSum(std::int64_t length)
      : value(length, 0.0), derivative(length, 0.0), second_derivative(length, 0.0) {}

  // amplitude * sin(2 pi cycles_per_sample * n + phase); derivatives are taken with respect to
  // the variable whose frequency is `angular` (rad per unit), e.g. position for a profile.
  void add(double amplitude, double cycles_per_sample, double phase, double angular) {
    const std::complex<double> step = std::polar(1.0, 2 * M_PI * cycles_per_sample);
    std::complex<double> phasor = std::polar(1.0, phase);
    for (std::size_t n = 0; n < value.size(); ++n) {
      value[n] += amplitude * phasor.imag();
      derivative[n] += amplitude * angular * phasor.real();
      second_derivative[n] -= amplitude * angular * angular * phasor.imag();
      phasor *= step;
      if ((n & 1023) == 1023) phasor /= std::abs(phasor);  // keep the recurrence on the unit circle
    }
  }
};

// Anti-aliasing: a DAQ removes what lies above 0.45 of its sample rate.
constexpr double kPassband = 0.45;

// Fractal roughness: log-spaced components with power-law amplitudes scaled to the RMS.
std::vector<SurfaceComponent> roughness_components(const SimtexMaterial& material, std::mt19937_64& rng,
                                                   double max_spatial_frequency) {
  const int count = 24;
  std::vector<SurfaceComponent> components;
  double power = 0;
  for (int k = 0; k < count; ++k) {
    const double frequency = 0.2 * std::pow(max_spatial_frequency / 0.2, (k + uniform(rng, 0, 1)) / count);
    const double amplitude = std::pow(frequency, -material.roughness_slope / 2);
    components.push_back({frequency, amplitude, 0.0});
    power += amplitude * amplitude / 2;
  }
  const double scale = power > 0 ? material.roughness_rms / std::sqrt(power) : 0.0;
  for (auto& component : components) component.amplitude *= scale;
  return components;
}

// The profile traced along the scan: h (um), dh/dx (um/mm), d2h/dx2 (um/mm^2).
SinusoidSum trace_profile(const SimtexConfig& config, const SimtexMaterial& material, const SimtexContext& context,
                          std::mt19937_64& rng, std::int64_t length) {
  SinusoidSum trace(length);
  const double max_spatial = config.shape == SimtexShape::haptex ? 10.0 : 50.0;
  auto add_component = [&](const SurfaceComponent& component, double directional) {
    const double phase = uniform(rng, 0, 2 * M_PI);  // drawn first: a fresh spot whatever is dropped
    const double along_scan = component.spatial_frequency * std::max(0.02, directional);
    const double temporal = along_scan * context.scan_speed;
    if (temporal >= kPassband * config.sample_rate || component.amplitude == 0) return;
    trace.add(component.amplitude, temporal / config.sample_rate, phase, 2 * M_PI * along_scan);
  };
  // A grating seen at angle d to its wave vector has spatial frequency f |cos d| along the scan.
  for (const auto& component : material.periodic) {
    const double projection = std::abs(std::cos(context.scan_direction - component.orientation));
    add_component(component, 1 - material.anisotropy + material.anisotropy * projection);
  }
  for (const auto& component : roughness_components(material, rng, max_spatial)) add_component(component, 1.0);
  return trace;
}

// Stick-slip: a relaxation oscillation at v / stick_length, as its first three harmonics.
std::vector<double> stick_slip_wave(const SimtexConfig& config, const SimtexMaterial& material,
                                    const SimtexContext& context, std::mt19937_64& rng, std::int64_t length) {
  SinusoidSum wave(length);
  const double base = context.scan_speed / material.stick_length;
  const double phase = uniform(rng, 0, 2 * M_PI);
  for (int harmonic = 1; harmonic <= 3 && material.stick_slip > 0; ++harmonic) {
    if (harmonic * base >= kPassband * config.sample_rate) break;
    wave.add(1.0 / harmonic, harmonic * base / config.sample_rate, harmonic * phase, 0.0);
  }
  return wave.value;
}

// A damped sensor resonance: a two-pole band-pass added to the direct path.
void apply_resonance(std::vector<double>& channel, double resonance_hz, double pole, double sample_rate) {
  const double theta = 2 * M_PI * resonance_hz / sample_rate;
  const double a1 = 2 * pole * std::cos(theta), a2 = -pole * pole, gain = 2 * (1 - pole);
  double y1 = 0, y2 = 0;
  for (auto& sample : channel) {
    const double y = gain * sample + a1 * y1 + a2 * y2;
    y2 = y1;
    y1 = y;
    sample += y;
  }
}

}  // namespace

Recording simulate_recording(const SimtexConfig& config, const SimtexMaterial& material, const SimtexContext& context,
                             std::mt19937_64& rng) {
  const auto length = static_cast<std::int64_t>(std::llround(config.recording_seconds * config.sample_rate));
  const SinusoidSum trace = trace_profile(config, material, context, rng, length);
  const std::vector<double> stick = stick_slip_wave(config, material, context, rng, length);
  const double drift_phase = uniform(rng, 0, 2 * M_PI);

  const int channels = config.channels();
  std::vector<std::vector<double>> signal(channels, std::vector<double>(length));
  const double v = context.scan_speed;
  for (std::int64_t n = 0; n < length; ++n) {
    const double t = n / config.sample_rate;
    const double h = trace.value[n], slope = trace.derivative[n], curvature = trace.second_derivative[n];
    // The operator's hand drifts slowly; friction falls with load as in Hertzian contact.
    const double force = context.normal_force * (1 + context.drift * std::sin(2 * M_PI * t / 3.0 + drift_phase));
    const double friction = material.friction * std::pow(force, -0.15);
    const double root_force = std::sqrt(force);
    // Contact: small profile heights modulate the load linearly (amplitude ~ F^1.5), large ones saturate.
    const double normal_force = force * (1 + std::tanh(material.compliance * root_force * h));
    const double friction_force = friction * normal_force * (1 + material.stick_slip * stick[n]) + 0.02 * root_force * slope;
    if (config.shape == SimtexShape::haptex) {
      signal[0][n] = friction_force;
      signal[1][n] = normal_force;
      signal[2][n] = friction_force / std::max(normal_force, 1e-3);
      signal[3][n] = v * t + 1e-3 * h;
      signal[4][n] = v * (1 + 0.01 * slope);
    } else {
      signal[0][n] = 1e-2 * friction * root_force * v * slope + 0.05 * material.stick_slip * friction * force * stick[n];
      signal[1][n] = 0.3e-2 * friction * v * slope;
      signal[2][n] = 1e-5 * v * v * root_force * curvature;
    }
  }

  Recording recording;
  recording.channels = channels;
  recording.length = length;
  recording.signal.resize(channels * length);
  for (int c = 0; c < channels; ++c) {
    auto& samples = signal[c];
    const bool resonates = config.shape == SimtexShape::lmt108 || c < 2;  // the force sensor and accelerometers ring
    if (resonates && context.resonance_hz > 0) {
      apply_resonance(samples, context.resonance_hz, context.resonance_pole, config.sample_rate);
    }
    double power = 0;
    for (double s : samples) power += s * s;
    const double noise_scale = context.noise_floor * (std::sqrt(power / length) + 1e-6);
    const double gain = c < static_cast<int>(context.channel_gain.size()) ? context.channel_gain[c] : 1.0;
    for (std::int64_t n = 0; n < length; ++n) {
      const double noisy = samples[n] + (noise_scale > 0 ? noise_scale * normal(rng) : 0.0);
      recording.signal[c * length + n] = static_cast<float>(gain * noisy);
    }
  }
  recording.context = {{"scan_speed", context.scan_speed},
                       {"normal_force", context.normal_force},
                       {"scan_direction_deg", context.scan_direction * 180 / M_PI},
                       {"device", static_cast<double>(context.device)},
                       {"operator", static_cast<double>(context.operator_id)},
                       {"held_out", context.held_out ? 1.0 : 0.0}};
  return recording;
}

}  // namespace fscil
