#include "methods/common/resnet18.h"

#include <ATen/autocast_mode.h>
#include <fmt/format.h>

#include "methods/common/module_cost.h"
#include "methods/common/running_statistics_guard.h"
#include "methods/common/unrolled_convolution.h"
#include "methods/method.h"

namespace fscil {

namespace nn = torch::nn;

namespace {

constexpr int kStages = 4;
constexpr int kSegments = 1 + kStages;  // the stem with its pool, then the stages
nn::Conv2d conv(std::int64_t in, std::int64_t out, std::int64_t kernel, std::int64_t stride, std::int64_t padding) {
  return nn::Conv2d(nn::Conv2dOptions(in, out, kernel).stride(stride).padding(padding).bias(false));
}

// LibTorch's CPU autocast to bfloat16 while it lives, when `on` and autocast is not on already
// (--precision bf16). Autocast keeps bf16 copies of the weights while it is on, stale once an
// optimiser steps, so the guard that turned it on drops them when it ends.
class Bf16Autocast {
 public:
  explicit Bf16Autocast(bool on) : owner_(on && !at::autocast::is_cpu_enabled()) {
    if (!owner_) return;
    previous_type_ = at::autocast::get_autocast_cpu_dtype();
    at::autocast::set_autocast_cpu_dtype(at::kBFloat16);
    at::autocast::set_cpu_enabled(true);
  }
  ~Bf16Autocast() {
    if (!owner_) return;
    at::autocast::set_cpu_enabled(false);
    at::autocast::set_autocast_cpu_dtype(previous_type_);
    at::autocast::clear_cache();
  }
  Bf16Autocast(const Bf16Autocast&) = delete;
  Bf16Autocast& operator=(const Bf16Autocast&) = delete;

 private:
  bool owner_;
  at::ScalarType previous_type_ = at::kBFloat16;
};

// A batch norm at inference is y = x * scale + shift per channel, with these two vectors.
std::pair<torch::Tensor, torch::Tensor> inference_affine(const nn::BatchNorm2d& norm) {
  const torch::Tensor scale = norm->weight / torch::sqrt(norm->running_var + norm->options.eps());
  return {scale, norm->bias - norm->running_mean * scale};
}

// conv's convolution of x in training, unrolled into one matrix product on the tiny maps where
// that is faster. Only in training, where the step's time goes (docs/architecture.md, "The
// training step"); inference stays on oneDNN.
torch::Tensor convolve_in_training(nn::Conv2d& conv, const torch::Tensor& x) {
  const auto& options = conv->options;
  const auto kernel = *options.kernel_size(), stride = *options.stride(), dilation = *options.dilation();
  const auto padding = *c10::get<torch::ExpandingArray<2>>(options.padding());
  const bool same_in_both_axes = kernel[0] == kernel[1] && stride[0] == stride[1] && padding[0] == padding[1];
  const bool plain = !options.bias() && dilation[0] == 1 && dilation[1] == 1 && options.groups() == 1 &&
                     c10::get_if<torch::enumtype::kZeros>(&options.padding_mode()) != nullptr;
  if (same_in_both_axes && plain && unrolling_pays(x.size(2), x.size(3), kernel[0], stride[0], padding[0])) {
    return unrolled_conv2d(x, conv->weight, stride[0], padding[0]);
  }
  return conv->forward(x);
}

// The stem, its norm and the max pool run on channels-last maps (oneDNN's stem kernels and ATen's
// pooling are faster there: docs/profiling.md, "The training step"); the stages get contiguous
// maps back.
torch::Tensor channels_last(const torch::Tensor& map) { return map.contiguous(at::MemoryFormat::ChannelsLast); }

// The pooled map made contiguous for the stages, whose gradient goes back channels-last. With the
// contiguous gradient that .contiguous() hands back, ATen's max-pool backward would copy the whole
// channels-last stem map to a contiguous one and its gradient back (two 67 MB copies a step on
// NS-100's shape: docs/profiling.md); the pooled map's gradient is 4 times smaller.
class ContiguousWithChannelsLastGradient : public torch::autograd::Function<ContiguousWithChannelsLastGradient> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext*, const torch::Tensor& map) { return map.contiguous(); }
  static torch::autograd::variable_list backward(torch::autograd::AutogradContext*,
                                                 torch::autograd::variable_list gradients) {
    return {channels_last(gradients[0])};
  }
};

torch::Tensor pool_stem_map(const torch::Tensor& map) {
  return ContiguousWithChannelsLastGradient::apply(torch::max_pool2d(map, 3, 2, 1));
}

// conv then norm at inference, as one convolution: the norm's scale folds into the weights and its
// shift becomes the bias.
torch::Tensor folded_conv_norm(const nn::Conv2d& conv, const nn::BatchNorm2d& norm, const torch::Tensor& x) {
  const auto [scale, shift] = inference_affine(norm);
  const auto& options = conv->options;
  return torch::conv2d(x, conv->weight * scale.view({-1, 1, 1, 1}), shift, *options.stride(),
                       *c10::get<torch::ExpandingArray<2>>(options.padding()), *options.dilation(), options.groups());
}

// A segment of the encoder (the stem with its pool, or a ResNet stage) whose activations are not
// kept: forward runs it without a graph (autograd functions do) and saves only its input; backward
// runs it again with a graph, under a guard that leaves the running statistics as the first
// forward set them, and differentiates that.
// Inputs: the segment's input, the encoder, the segment index, the segment's trained parameters (so
// autograd hands their gradients back). The encoder must outlive the graph, as a module does
// whose forward built it; the parameters that train, and train mode, must not change between
// forward and backward (checked).
class RecomputedSegment : public torch::autograd::Function<RecomputedSegment> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& input,
                               ResNet18EncoderImpl* encoder, std::int64_t segment, at::TensorList parameters) {
    ctx->save_for_backward({input});
    ctx->saved_data["encoder"] = reinterpret_cast<std::int64_t>(encoder);
    ctx->saved_data["segment"] = segment;
    ctx->saved_data["parameters"] = static_cast<std::int64_t>(parameters.size());
    return encoder->run_segment(static_cast<int>(segment), input);
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list output_gradients) {
    TORCH_CHECK(!torch::GradMode::is_enabled(), "recomputed ResNet segments do not support a second derivative");
    auto* encoder = reinterpret_cast<ResNet18EncoderImpl*>(ctx->saved_data["encoder"].toInt());
    const int segment = static_cast<int>(ctx->saved_data["segment"].toInt());
    const torch::Tensor saved = ctx->get_saved_variables()[0];
    const torch::Tensor input = saved.detach().requires_grad_(saved.requires_grad());
    std::vector<torch::Tensor> wrt = encoder->segment_parameters(segment);
    TORCH_CHECK(encoder->is_training() && static_cast<std::int64_t>(wrt.size()) == ctx->saved_data["parameters"].toInt(),
                "a recomputed ResNet segment changed between forward and backward (train mode or trained parameters)");
    torch::Tensor output;
    {
      torch::AutoGradMode with_graph(true);
      RunningStatisticsGuard first_forward_statistics(*encoder);
      output = encoder->run_segment(segment, input);
    }
    if (input.requires_grad()) wrt.insert(wrt.begin(), input);
    std::vector<torch::Tensor> gradients =
        torch::autograd::grad({output}, wrt, {output_gradients[0]}, /*retain_graph=*/false,
                              /*create_graph=*/false, /*allow_unused=*/true);
    torch::autograd::variable_list result;
    result.push_back(input.requires_grad() ? gradients.front() : torch::Tensor());
    result.push_back(torch::Tensor());  // the encoder
    result.push_back(torch::Tensor());  // the segment index
    result.insert(result.end(), gradients.begin() + (input.requires_grad() ? 1 : 0), gradients.end());
    return result;
  }
};

}  // namespace

BasicBlockImpl::BasicBlockImpl(std::int64_t in_planes, std::int64_t planes, std::int64_t stride,
                               bool fold_norms_at_inference)
    : conv1(register_module("conv1", conv(in_planes, planes, 3, stride, 1))),
      conv2(register_module("conv2", conv(planes, planes, 3, 1, 1))),
      bn1(register_module("bn1", nn::BatchNorm2d(planes))),
      bn2(register_module("bn2", nn::BatchNorm2d(planes))),
      fold_norms_at_inference_(fold_norms_at_inference) {
  if (stride != 1 || in_planes != planes) {
    shortcut_conv_ = conv(in_planes, planes, 1, stride, 0);
    shortcut_norm_ = nn::BatchNorm2d(planes);
    downsample = register_module("downsample", nn::Sequential(shortcut_conv_, shortcut_norm_));
  }
}

torch::Tensor BasicBlockImpl::forward(const torch::Tensor& x) {
  if (!is_training() && fold_norms_at_inference_) {
    torch::Tensor out = folded_conv_norm(conv1, bn1, x).relu_();
    out = folded_conv_norm(conv2, bn2, out);
    if (downsample) {
      out += folded_conv_norm(shortcut_conv_, shortcut_norm_, x);
    } else {
      out += x;
    }
    return out.relu_();
  }
  // Training (convolutions may unroll), or inference without folding (always oneDNN).
  const auto convolved = [&](nn::Conv2d& conv, const torch::Tensor& input) {
    return is_training() ? convolve_in_training(conv, input) : conv->forward(input);
  };
  torch::Tensor out = bn1(convolved(conv1, x)).relu_();
  out = bn2(convolved(conv2, out));
  out += downsample ? shortcut_norm_(convolved(shortcut_conv_, x)) : x;
  return out.relu_();
}

MapShape BasicBlockImpl::count_cost(ModelCost& cost, const std::string& name, const MapShape& input) const {
  MapShape out = count_conv2d(cost, name + ".conv1", *conv1, input);
  count_batch_norm(cost, name + ".bn1", *bn1, out);
  out = count_conv2d(cost, name + ".conv2", *conv2, out);
  count_batch_norm(cost, name + ".bn2", *bn2, out);
  if (downsample) {
    const MapShape shortcut = count_conv2d(cost, name + ".downsample.0", *shortcut_conv_, input);
    count_batch_norm(cost, name + ".downsample.1", *shortcut_norm_, shortcut);
  }
  return out;
}

ResNet18EncoderImpl::ResNet18EncoderImpl(const ResNet18Options& options)
    : input_norm(register_module("bn0", nn::BatchNorm2d(options.mel_bins))),
      stem(register_module("conv1", conv(options.in_channels, options.widths[0], 7, 2, 3))),
      stem_norm(register_module("bn1", nn::BatchNorm2d(options.widths[0]))),
      stages(register_module("stages", nn::Sequential())),
      widths_(options.widths),
      embedding_size_(options.widths[3]),
      fold_norms_at_inference_(options.fold_norms_at_inference),
      recompute_activations_(options.recompute_activations),
      memory_budget_(options.memory_budget),
      precision_(options.precision) {
  std::int64_t in_planes = options.widths[0];
  for (int stage = 0; stage < kStages; ++stage) {
    const std::int64_t stride = stage == 0 ? 1 : 2;
    stages->push_back(BasicBlock(in_planes, options.widths[stage], stride, fold_norms_at_inference_));
    stages->push_back(BasicBlock(options.widths[stage], options.widths[stage], 1, fold_norms_at_inference_));
    in_planes = options.widths[stage];
  }
  for (auto& module : modules(/*include_self=*/false)) {
    if (auto* convolution = module->as<nn::Conv2d>()) {
      nn::init::kaiming_normal_(convolution->weight, 0.0, torch::kFanOut, torch::kReLU);
    } else if (auto* norm = module->as<nn::BatchNorm2d>()) {
      nn::init::ones_(norm->weight);
      nn::init::zeros_(norm->bias);
    }
  }
}

torch::Tensor ResNet18EncoderImpl::forward(const torch::Tensor& x, const InputNormHook& after_input_norm) {
  return torch::adaptive_avg_pool2d(forward_map(x, after_input_norm), {1, 1}).flatten(1);
}

std::pair<torch::Tensor, torch::Tensor> ResNet18EncoderImpl::forward_with_first_stage(const torch::Tensor& x) {
  torch::Tensor first_stage_map;
  const torch::Tensor embedding = torch::adaptive_avg_pool2d(forward_map(x, {}, &first_stage_map), {1, 1}).flatten(1);
  return {embedding, torch::adaptive_avg_pool2d(first_stage_map, {1, 1}).flatten(1)};
}

torch::Tensor ResNet18EncoderImpl::forward_map(const torch::Tensor& x, const InputNormHook& after_input_norm,
                                               torch::Tensor* first_stage_map) {
  if (!is_training() && fold_norms_at_inference_) {
    // bn0 at inference: a scale and shift per Mel bin, broadcast over the contiguous input.
    const auto [scale, shift] = inference_affine(input_norm);
    torch::Tensor normalised = torch::addcmul(shift.view({1, 1, -1, 1}), x, scale.view({1, 1, -1, 1}));
    if (after_input_norm) normalised = after_input_norm(normalised);
    const Bf16Autocast autocast(precision_ == Precision::bf16);
    torch::Tensor map = pool_stem_map(folded_conv_norm(stem, stem_norm, channels_last(normalised)).relu_());
    // Block by block, as the Sequential runs them, to keep the first stage's output.
    for (std::size_t block = 0; block < stages->size(); ++block) {
      map = stages->ptr(block)->as<BasicBlock>()->forward(map);
      if (block == 1 && first_stage_map != nullptr) *first_stage_map = map.to(torch::kFloat);
    }
    return map.to(torch::kFloat);
  }
  // bn0 normalises each Mel bin, so the bins become the channel axis for it.
  torch::Tensor out = input_norm(x.transpose(1, 2)).transpose(1, 2);
  if (after_input_norm) out = after_input_norm(out);
  const bool recompute = is_training() && torch::GradMode::is_enabled() &&
                         (recompute_activations_ || (memory_budget_ && memory_budget_->would_exceed(training_pass_bytes(out))));
  for (int segment = 0; segment < kSegments; ++segment) {
    const std::vector<torch::Tensor> parameters = recompute ? segment_parameters(segment) : std::vector<torch::Tensor>{};
    out = !recompute || (parameters.empty() && !out.requires_grad())
              ? run_segment(segment, out)
              : RecomputedSegment::apply(out, this, static_cast<std::int64_t>(segment), at::TensorList(parameters));
    if (segment == 1 && first_stage_map != nullptr) *first_stage_map = out.to(torch::kFloat);
  }
  return out.to(torch::kFloat);
}

torch::Tensor ResNet18EncoderImpl::run_segment(int segment, const torch::Tensor& x) {
  // Here, so that a segment recomputed in backward runs in the precision its forward ran in.
  const Bf16Autocast autocast(precision_ == Precision::bf16);
  if (segment == 0) return pool_stem_map(stem_norm(stem(channels_last(x))).relu_());
  const torch::Tensor out = stages->ptr(2 * segment - 2)->as<BasicBlock>()->forward(x);
  return stages->ptr(2 * segment - 1)->as<BasicBlock>()->forward(out);
}

std::vector<torch::Tensor> ResNet18EncoderImpl::segment_parameters(int segment) const {
  std::vector<torch::Tensor> modules_parameters;
  if (segment == 0) {
    modules_parameters = stem->parameters();
    for (const auto& parameter : stem_norm->parameters()) modules_parameters.push_back(parameter);
  } else {
    for (int block = 2 * segment - 2; block < 2 * segment; ++block) {
      for (const auto& parameter : stages->ptr(block)->parameters()) modules_parameters.push_back(parameter);
    }
  }
  std::vector<torch::Tensor> trained;
  for (const auto& parameter : modules_parameters) {
    if (parameter.requires_grad()) trained.push_back(parameter);
  }
  return trained;
}

std::int64_t ResNet18EncoderImpl::training_pass_bytes(const torch::Tensor& normalised) const {
  // The shapes as count_cost() walks them: the stem (7x7, stride 2, padding 3), its max pool and
  // each stage's first convolution (3x3, stride 2, padding 1).
  const MapShape input{normalised.size(1), normalised.size(2), normalised.size(3)};
  const MapShape stem_map = window_output(input, widths_[0], 7, 7, 2, 3);
  MapShape map = window_output(stem_map, widths_[0], 3, 3, 2, 1);
  // The stem keeps its channels-last copy of the input (its weight gradient reads it), its
  // convolution's output (the norm reads it) and its norm's output after ReLU (ReLU and the pool
  // read it), the pool's indices (int64: two floats each) and its contiguous output.
  std::int64_t elements = input.elements() + 2 * stem_map.elements() + 3 * map.elements();
  for (int stage = 0; stage < kStages; ++stage) {
    const std::int64_t in_planes = map.channels;
    map = stage > 0 ? window_output(map, widths_[stage], 3, 3, 2, 1) : MapShape{widths_[stage], map.height, map.width};
    // Each block keeps its two convolutions' outputs (its norms read them) and its two norms'
    // outputs (ReLU and the next convolution read them; the residual sum and the last ReLU work
    // in place); a block that changes the map keeps its shortcut convolution's output too (the
    // shortcut norm's output is summed in and freed).
    const bool shortcut = stage > 0 || in_planes != widths_[stage];
    elements += (8 + (shortcut ? 1 : 0)) * map.elements();
  }
  // Backward's gradients of the stem map at its norm's output and at its convolution's output.
  elements += 2 * stem_map.elements();
  return elements * normalised.size(0) * static_cast<std::int64_t>(normalised.element_size());
}

void ResNet18EncoderImpl::count_cost(ModelCost& cost, const std::string& name, const MapShape& input) const {
  count_batch_norm(cost, name + ".bn0", *input_norm, input);
  MapShape out = count_conv2d(cost, name + ".conv1", *stem, input);
  count_batch_norm(cost, name + ".bn1", *stem_norm, out);
  const MapShape pooled = window_output(out, out.channels, 3, 3, 2, 1);  // the max_pool2d of pool_stem_map()
  cost.add({name + ".maxpool", "pool", max_pool_macs(pooled, 3)});
  out = pooled;
  for (std::size_t block = 0; block < stages->size(); ++block) {
    out = stages->ptr(block)->as<BasicBlock>()->count_cost(cost, fmt::format("{}.stages.{}", name, block), out);
  }
  cost.add({name + ".avgpool", "pool", global_average_pool_macs(out)});
}

ResNet18Options encoder_options(const RunContext& context) {
  ResNet18Options options{context.input.channels, context.input.mel_bins};
  options.recompute_activations = context.recompute_activations;
  options.memory_budget = context.memory_budget;
  options.precision = context.precision;
  return options;
}

}  // namespace fscil
