#include "methods/pan/pan_settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/parameter_set.h"

namespace fscil {

PanSettings PanSettings::from(const ParameterSet& params) {
  PanSettings s;
  s.standard = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));
  s.pit_epochs = params.count("pan_pit_epochs", s.pit_epochs, ValidRange::at_least(0));
  s.pit_episodes = params.count("pan_pit_episodes", s.pit_episodes, ValidRange::at_least(1));
  s.encoder_lr = params.real("pan_encoder_lr", s.encoder_lr, ValidRange::at_least(0));
  s.attention_lr = params.real("pan_attention_lr", s.attention_lr, ValidRange::at_least(0));
  s.session_steps = params.count("pan_session_steps", s.session_steps, ValidRange::at_least(0));
  s.session_lr = params.real("pan_session_lr", s.session_lr, ValidRange::at_least(0));
  s.temporary_base = params.integer("pan_temporary_base", s.temporary_base, ValidRange::at_least(0));
  return s;
}

std::int64_t temporary_base_classes(std::int64_t base_classes, std::int64_t requested) {
  if (requested != 0) {
    if (requested >= base_classes) {
      throw MethodError(fmt::format("pan_temporary_base is {}: the protocol has {} base classes, and at least one "
                                    "must stay a temporary novel class",
                                    requested, base_classes));
    }
    return requested;
  }
  const auto share = static_cast<std::int64_t>(std::llround(static_cast<double>(base_classes) * 35.0 / 60.0));
  return std::clamp<std::int64_t>(share, 1, base_classes - 1);
}

}  // namespace fscil
