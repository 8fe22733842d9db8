#include "methods/common/traced_cost.h"

#include <torch/csrc/autograd/profiler_legacy.h>

#include <fmt/format.h>

#include <map>
#include <numeric>

namespace fscil {
namespace {

namespace profiler = torch::autograd::profiler;

std::int64_t elements(const std::vector<std::int64_t>& shape) {
  return std::accumulate(shape.begin(), shape.end(), std::int64_t{1}, std::multiplies<>());
}

// The MACs of one recorded operation and the kind model_cost.h files them under; 0 for the rest.
std::pair<std::string, std::int64_t> operation_macs(profiler::LegacyEvent& event) {  // flops() is not const
  const std::string name = event.name();
  const auto& shapes = event.shapes();
  if (name == "aten::conv2d" && shapes.size() >= 3 && shapes[1].size() == 4) {
    const std::int64_t multiplies = static_cast<std::int64_t>(event.flops() / 2);
    const auto& weight = shapes[1];  // out x in/groups x kh x kw
    const std::int64_t per_output = weight[1] * weight[2] * weight[3];
    const bool bias = !shapes[2].empty();
    return {"conv", multiplies + (bias && per_output > 0 ? multiplies / per_output : 0)};
  }
  if (name == "aten::addmm" || name == "aten::mm" || name == "aten::bmm" || name == "aten::baddbmm") {
    return {"linear", static_cast<std::int64_t>(event.flops() / 2)};
  }
  if (name == "aten::batch_norm" && !shapes.empty()) return {"batch_norm", elements(shapes[0])};
  if (name == "aten::adaptive_avg_pool2d" && !shapes.empty()) return {"pool", elements(shapes[0])};
  return {"", 0};
}

}  // namespace

ModelCost traced_cost(const std::function<void()>& forward, const NamedModules& modules) {
  ModelCost cost;
  for (const auto& [name, module] : modules) {
    LayerCost layer{name, "parameters"};
    for (const auto& parameter : module->parameters()) {
      layer.parameters += parameter.numel();
      if (parameter.requires_grad()) layer.trainable_parameters += parameter.numel();
    }
    cost.add(layer);
  }
  const profiler::ProfilerConfig config(profiler::ProfilerState::CPU, /*report_input_shapes=*/true,
                                        /*profile_memory=*/false, /*with_stack=*/false, /*with_flops=*/true);
  profiler::enableProfilerLegacy(config);
  try {
    torch::NoGradGuard no_grad;
    forward();
  } catch (...) {
    profiler::disableProfilerLegacy();
    throw;
  }
  std::map<std::string, int> counted;
  profiler::thread_event_lists recorded = profiler::disableProfilerLegacy();
  for (auto& thread_events : recorded) {
    for (auto& event : thread_events) {
      if (event.kindStr() != "push") continue;
      const auto [kind, macs] = operation_macs(event);
      if (macs == 0) continue;
      cost.add({fmt::format("{}.{}", kind, counted[kind]++), kind, macs});
    }
  }
  return cost;
}

}  // namespace fscil
