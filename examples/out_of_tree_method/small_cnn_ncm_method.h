#pragma once
#include <methods/module_method.h>

#include <memory>

// A small CNN trained with cross-entropy on the base classes, then frozen; every class is the
// mean of its training embeddings and a sample goes to the nearest mean (cosine). A ModuleMethod:
// its state is its modules, so it writes build() and the four protocol functions, nothing else.
// The base session's linear head is not one of them: only training uses it.
class SmallCnnNcmMethod : public fscil::ModuleMethod {
 public:
  explicit SmallCnnNcmMethod(const fscil::ParameterSet& params);
  void train_base(const fscil::SessionData& base, fscil::RunContext& context) override;
  void learn_session(const fscil::SessionData& support, fscil::RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;

 protected:
  fscil::NamedModules build(const fscil::RunContext& context) override;

 private:
  void add_class_means(const fscil::SessionData& data);

  std::int64_t epochs_;
  double learning_rate_;
  std::int64_t width_;
  torch::nn::Sequential encoder_{nullptr};
  // One row per class of the protocol, and how many are filled: buffers, so they are state.
  struct ClassMeansImpl : torch::nn::Module {
    ClassMeansImpl(std::int64_t classes, std::int64_t dim)
        : rows(register_buffer("rows", torch::zeros({classes, dim}))),
          seen(register_buffer("seen", torch::zeros({1}, torch::kLong))) {}
    torch::Tensor rows, seen;
  };
  TORCH_MODULE(ClassMeans);
  ClassMeans means_{nullptr};
};

std::unique_ptr<fscil::Method> make_small_cnn_ncm_method(const fscil::ParameterSet& params);
