// A method whose state is its modules gets save_state, restore_state and inference_cost for free.
#include "methods/module_method.h"

#include <gtest/gtest.h>

#include "methods/method_registry.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

// Flattened features through one linear layer; a class is the mean of its embeddings.
class LinearMeans : public ModuleMethod {
 public:
  void train_base(const SessionData& base, RunContext& context) override {
    build_modules(context);
    add_means(base);
  }
  void learn_session(const SessionData& support, RunContext& context) override { add_means(support); }
  torch::Tensor embed(const torch::Tensor& features) override {
    torch::NoGradGuard no_grad;
    return layer_(features.flatten(1));
  }
  torch::Tensor classify(const torch::Tensor& embeddings) override {
    torch::NoGradGuard no_grad;
    return torch::mm(embeddings, means_->weight.narrow(0, 0, means_->seen.item<std::int64_t>()).t());
  }

 protected:
  NamedModules build(const RunContext& context) override {
    layer_ = torch::nn::Linear(context.input.feature_map().elements(), 8);
    means_ = Means(context.total_classes, 8);
    return {{"layer", layer_.ptr()}, {"means", means_.ptr(), /*trained_in_sessions=*/true}};
  }

 private:
  void add_means(const SessionData& data) {
    torch::NoGradGuard no_grad;
    const torch::Tensor embeddings = embed(data.features.all());
    for (std::int64_t label : data.new_classes) means_->weight[label] = embeddings.index({data.labels == label}).mean(0);
    means_->seen.fill_(data.new_classes.back() + 1);
  }
  struct MeansImpl : torch::nn::Module {
    MeansImpl(std::int64_t classes, std::int64_t dim)
        : weight(register_parameter("weight", torch::zeros({classes, dim}))),
          seen(register_buffer("seen", torch::zeros({1}, torch::kLong))) {}
    torch::Tensor weight, seen;
  };
  TORCH_MODULE(Means);
  torch::nn::Linear layer_{nullptr};
  Means means_{nullptr};
};

TEST(ModuleMethod, StateIsTheModulesAndARestoredMethodGivesTheSameLogits) {
  torch::manual_seed(3);
  RunContext context = tiny_context(3);
  LinearMeans trained;
  trained.train_base(tiny_base(), context);
  const MethodState state = trained.save_state();
  std::set<std::string> keys;
  for (const auto& entry : state) keys.insert(entry.first);
  EXPECT_EQ(keys, (std::set<std::string>{"layer.weight", "layer.bias", "means.weight", "means.seen"}));

  LinearMeans restored;
  restored.restore_state(state, context);
  const torch::Tensor before = torch::randn({5, 2, 4, 4});
  EXPECT_TRUE(torch::equal(trained.logits(before), restored.logits(before)));
  const SessionData support = tiny_support(6);
  trained.learn_session(support, context);
  restored.learn_session(support, context);
  const torch::Tensor probe = torch::randn({5, 2, 4, 4});
  EXPECT_TRUE(torch::equal(trained.logits(probe), restored.logits(probe)));
}

TEST(ModuleMethod, RefusesAStateThatDoesNotFitAndSavingBeforeTraining) {
  RunContext context = tiny_context(1);
  LinearMeans untrained;
  EXPECT_THROW(untrained.save_state(), MethodError);
  LinearMeans trained;
  trained.train_base(tiny_base(), context);
  for (const char* stray : {"head.weight", "layer.old_weight"}) {
    MethodState extra = trained.save_state();
    extra[stray] = torch::zeros({2});
    EXPECT_THROW(LinearMeans().restore_state(extra, context), MethodError) << stray;
  }
  MethodState missing = trained.save_state();
  missing.erase("means.seen");
  EXPECT_THROW(LinearMeans().restore_state(missing, context), MethodError);
  MethodState reshaped = trained.save_state();
  reshaped["layer.weight"] = torch::zeros({8, 3});
  EXPECT_THROW(LinearMeans().restore_state(reshaped, context), MethodError);
}

TEST(ModuleMethod, InferenceCostIsTracedFromLogitsOnOneSample) {
  RunContext context = tiny_context(1);
  LinearMeans method;
  method.train_base(tiny_base(), context);
  const ModelCost cost = method.inference_cost(context.input);
  EXPECT_EQ(cost.macs_of("linear"), 32 * 8 + 8 * 6);  // the layer, then 6 base class means
  EXPECT_EQ(cost.parameters(), 32 * 8 + 8 + 10 * 8);
  EXPECT_EQ(cost.trainable_parameters(), 10 * 8);  // the means, which sessions write
}

// build() results that would save or count a tensor twice, or none.
class BadModules : public LinearMeans {
 public:
  explicit BadModules(int fault) : fault_(fault) {}

 protected:
  NamedModules build(const RunContext& context) override {
    NamedModules modules = LinearMeans::build(context);
    if (fault_ == 0) return {};
    if (fault_ == 1) modules.push_back({"layer", modules[0].module});
    if (fault_ == 2) modules.push_back({"again", modules[0].module});
    if (fault_ == 3) modules.push_back({"", modules[0].module});
    return modules;
  }

 private:
  int fault_;
};

TEST(ModuleMethod, RefusesNoModulesDuplicateNamesAndSharedModules) {
  RunContext context = tiny_context(1);
  for (int fault = 0; fault < 4; ++fault) {
    BadModules method(fault);
    EXPECT_THROW(method.train_base(tiny_base(), context), MethodError) << fault;
    EXPECT_THROW(method.save_state(), MethodError) << fault;  // nothing half-built was kept
  }
}

// Registers into this process's registry for good: ctest runs each test in a process of its own.
TEST(MethodRegistry, ARegisteredMethodJoinsAllAndIsCreatedByName) {
  register_method({"linear-means", "test", [](const ParameterSet&) { return std::make_unique<LinearMeans>(); }});
  const auto all = resolve_method_names("all");
  EXPECT_EQ(all.back(), "linear-means");
  EXPECT_EQ(all.front(), "prototype");
  EXPECT_NE(dynamic_cast<LinearMeans*>(create_method("linear-means", ParameterSet()).get()), nullptr);
  EXPECT_EQ(resolve_method_names("prototype,linear-means").size(), 2u);
}

TEST(MethodRegistry, RefusesTakenReservedAndMalformedNames) {
  const auto make = [](const ParameterSet&) { return std::make_unique<LinearMeans>(); };
  const std::size_t registered = method_registry().size();
  for (const char* name : {"prototype", "all", "ablation", "", "Linear", "two words", "a,b"}) {
    EXPECT_THROW(register_method({name, "test", make}), MethodError) << name;
  }
  EXPECT_THROW(register_method({"no-create", "test", nullptr}), MethodError);
  MethodEntry two_lines{"two-line-note", "test", make};
  two_lines.table_note = "our reading\nof something";
  EXPECT_THROW(register_method(two_lines), MethodError);
  EXPECT_EQ(method_registry().size(), registered);
}

}  // namespace
}  // namespace fscil
