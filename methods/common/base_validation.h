#pragma once
#include <fmt/format.h>

#include "methods/method.h"

namespace fscil {

// The trained base's top-1 accuracy on base validation, as the `base_validation` diagnostic and a
// progress note; nothing when the run has no validation split.
inline void record_base_validation(Method& method, RunContext& context) {
  if (context.validation == nullptr) return;
  const double accuracy = method.accuracy_on(*context.validation);
  context.diagnostics["base_validation"] = accuracy;
  if (context.progress != nullptr) context.progress->note(fmt::format("base validation accuracy {:.2f}%", accuracy));
}

}  // namespace fscil
