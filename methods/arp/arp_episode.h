#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>
#include <vector>

#include "methods/method.h"

namespace fscil {

// The episode beside each batch of ARP's base training (chester-w-xie/APR Utils.py L39-L62,
// FSCIL_model_define_V1.py L213-L230 at 78426ecf): `way + tasks` base classes drawn without
// replacement, `shot` samples of each laid out class by class, and per task `way` of those classes
// drawn again, whose rows the task replaces by the supports' means. On a protocol with fewer base
// classes the episode takes them all, and a task at most that many (ours: small protocols).
struct ArpEpisode {
  torch::Tensor features;                  // classes x shot supports, class-major
  torch::Tensor classes;                   // the episode's base classes, int64
  std::vector<torch::Tensor> task_slots;   // per task: `way` positions into `classes`, int64
};

class ArpEpisodeSampler {
 public:
  ArpEpisodeSampler(const SessionData& base, std::int64_t base_classes, int way, int shot, int tasks);
  ArpEpisode draw(std::mt19937_64& generator) const;

 private:
  const SessionData& base_;
  std::int64_t base_classes_, episode_classes_;
  int way_, shot_, tasks_;
  std::vector<std::vector<std::int64_t>> members_;
};

// Per slot s of the episode: the mean of its `shot` consecutive rows of `support_embeddings`.
torch::Tensor support_means(const torch::Tensor& support_embeddings, std::int64_t shot);

}  // namespace fscil
