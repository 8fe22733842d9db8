#include "methods/common/traced_cost.h"

#include <ATen/record_function.h>
#include <fmt/format.h>

#include <cstring>
#include <map>

namespace fscil {
namespace {

// The layers one traced forward pass has counted so far: the dispatcher's callbacks are plain
// function pointers, so they find it through this thread's pointer.
struct Trace {
  ModelCost cost;
  std::map<std::string, int> layers_of_kind;
  int open_counted = 0;  // counted operations running: what runs inside them is theirs
};
thread_local Trace* current_trace = nullptr;

bool is_any_of(const char* name, std::initializer_list<const char*> names) {
  for (const char* candidate : names) {
    if (std::strcmp(name, candidate) == 0) return true;
  }
  return false;
}

bool is_product(const char* name) {
  return is_any_of(name, {"aten::mm", "aten::addmm", "aten::addmm_", "aten::bmm", "aten::baddbmm", "aten::baddbmm_",
                          "aten::mv", "aten::addmv", "aten::addmv_", "aten::dot", "aten::vdot"});
}

bool is_norm(const char* name) {
  return is_any_of(name, {"aten::batch_norm", "aten::layer_norm", "aten::group_norm", "aten::instance_norm"});
}

bool is_window_pool(const char* name) {
  return is_any_of(name, {"aten::max_pool1d", "aten::max_pool2d", "aten::max_pool3d", "aten::avg_pool1d",
                          "aten::avg_pool2d", "aten::avg_pool3d", "aten::max_pool2d_with_indices",
                          "aten::max_pool3d_with_indices"});
}

bool is_adaptive_pool(const char* name) {
  return is_any_of(name, {"aten::adaptive_avg_pool1d", "aten::adaptive_avg_pool2d", "aten::adaptive_avg_pool3d",
                          "aten::adaptive_max_pool1d", "aten::adaptive_max_pool2d", "aten::adaptive_max_pool3d"});
}

bool is_counted(const char* name) {
  return std::strcmp(name, "aten::convolution") == 0 || std::strcmp(name, "aten::cdist") == 0 || is_product(name) ||
         is_norm(name) || is_window_pool(name) || is_adaptive_pool(name);
}

const at::Tensor* tensor_at(c10::ArrayRef<const c10::IValue> values, std::size_t index) {
  return index < values.size() && values[index].isTensor() ? &values[index].toTensor() : nullptr;
}

const at::Tensor* first_output(const std::vector<c10::IValue>& outputs) {
  if (outputs.empty()) return nullptr;
  if (outputs[0].isTensor()) return &outputs[0].toTensor();
  return nullptr;
}

// The MACs of one counted operation on one sample, and the kind model_cost.h files them under.
std::pair<std::string, std::int64_t> operation_macs(const at::RecordFunction& call, std::int64_t window) {
  const char* name = call.name();
  const auto inputs = call.inputs();
  const at::Tensor* output = first_output(call.outputs());
  if (output == nullptr) return {"", 0};
  if (std::strcmp(name, "aten::convolution") == 0) {
    // input, weight, bias, stride, padding, dilation, transposed, output_padding, groups
    const at::Tensor* input = tensor_at(inputs, 0);
    const at::Tensor* weight = tensor_at(inputs, 1);
    const at::Tensor* bias = tensor_at(inputs, 2);
    if (input == nullptr || weight == nullptr) return {"", 0};
    const std::int64_t per_element = weight->numel() / weight->size(0);  // in/groups x kernel, or out/groups x kernel
    const bool transposed = inputs.size() > 6 && inputs[6].isBool() && inputs[6].toBool();
    const std::int64_t bias_macs = bias != nullptr && bias->defined() ? output->numel() : 0;
    return {"conv", (transposed ? input->numel() : output->numel()) * per_element + bias_macs};
  }
  if (is_product(name) || std::strcmp(name, "aten::cdist") == 0) {
    const bool accumulates = std::strncmp(name, "aten::add", 9) == 0 || std::strncmp(name, "aten::baddbmm", 13) == 0;
    const at::Tensor* left = tensor_at(inputs, accumulates ? 1 : 0);
    if (left == nullptr || left->dim() == 0) return {"", 0};
    return {"linear", output->numel() * left->size(-1)};
  }
  if (is_norm(name)) {
    const at::Tensor* input = tensor_at(inputs, 0);
    return {std::strcmp(name, "aten::batch_norm") == 0 ? "batch_norm" : "norm", input != nullptr ? input->numel() : 0};
  }
  if (is_window_pool(name)) {
    return {"pool", output->numel() * window};
  }
  const at::Tensor* input = tensor_at(inputs, 0);
  return {"pool", input != nullptr ? input->numel() : 0};  // adaptive: every input element is read
}

// A call on_end counts; a pooling window's area, read when the call starts (an integer list input
// no longer holds its values when the call ends).
struct CountedCall : at::ObserverContext {
  std::int64_t window = 1;
};

std::int64_t window_area(const at::RecordFunction& call) {
  const auto inputs = call.inputs();
  if (inputs.size() < 2 || !inputs[1].isIntList()) return 0;
  const std::vector<std::int64_t> kernel = inputs[1].toIntVector();
  const int spatial = std::strstr(call.name(), "pool")[4] - '0';  // pool1d, pool2d, pool3d
  std::int64_t area = 1;
  for (int d = 0; d < spatial; ++d) area *= kernel.size() == 1 ? kernel[0] : kernel.at(d);
  return area;
}

std::unique_ptr<at::ObserverContext> on_start(const at::RecordFunction& call) {
  if (current_trace == nullptr || !is_counted(call.name())) return nullptr;
  ++current_trace->open_counted;
  auto counted = std::make_unique<CountedCall>();
  if (is_window_pool(call.name())) counted->window = window_area(call);
  return counted;
}

void on_end(const at::RecordFunction& call, at::ObserverContext* counted) {
  if (current_trace == nullptr || counted == nullptr) return;
  if (--current_trace->open_counted > 0) return;  // inside another counted operation
  const auto [kind, macs] = operation_macs(call, static_cast<CountedCall*>(counted)->window);
  if (macs == 0) return;
  current_trace->cost.add({fmt::format("{}.{}", kind, current_trace->layers_of_kind[kind]++), kind, macs});
}

}  // namespace

ModelCost traced_cost(const std::function<void()>& forward, const NamedModules& modules) {
  Trace trace;
  for (const auto& named : modules) {
    LayerCost layer{named.name, "parameters"};
    for (const auto& parameter : named.module->parameters()) layer.parameters += parameter.numel();
    if (named.trained_in_sessions) layer.trainable_parameters = layer.parameters;
    trace.cost.add(layer);
  }
  current_trace = &trace;
  const at::CallbackHandle handle = at::addThreadLocalCallback(
      at::RecordFunctionCallback(on_start, on_end).needsInputs(true).needsOutputs(true).scopes({at::RecordScope::FUNCTION}));
  try {
    torch::NoGradGuard no_grad;
    forward();
  } catch (...) {
    at::removeCallback(handle);
    current_trace = nullptr;
    throw;
  }
  at::removeCallback(handle);
  current_trace = nullptr;
  return trace.cost;
}

}  // namespace fscil
