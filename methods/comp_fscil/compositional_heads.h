#pragma once
#include <torch/torch.h>

namespace fscil {

// Comp-FSCIL's two heads and its primitive reuse (Zoilsen/Comp-FSCIL models/base/Network.py and
// helper.py at 95a44177). A "primitive" is the D-long column at one position of the encoder's
// last map; a sample or a class prototype is the set of its columns.

// x^p where x > 0, x elsewhere (Network.py L93-L98, L112-L117), with gradient 0 at x = 0 as the
// release's relu-then-pow gives.
torch::Tensor signed_power(const torch::Tensor& x, double p);

// Linear CKA between each sample's primitives and each prototype's (Network.py L351-L374):
// ||A^T P||_F^2 / (||A^T A||_F ||P^T P||_F), each column centred over the D channels first.
// maps: N x D x n (or N x D x h x w), prototypes: K x D x m (or K x D x h' x w') -> N x K in [0, 1].
// The release has no epsilon; a denominator below 1e-12 is held there (ours) so a constant map
// scores 0 rather than NaN.
torch::Tensor cka_similarity(const torch::Tensor& maps, const torch::Tensor& prototypes);

// The vector head on pooled embeddings (N x D) and rows (K x D), both centred over their D
// values (Network.py L139-L154): in training -T ||x - w||^2, at test T cos(x, w).
torch::Tensor vector_distance_logits(const torch::Tensor& pooled, const torch::Tensor& rows, double temperature);
torch::Tensor vector_cosine_logits(const torch::Tensor& pooled, const torch::Tensor& rows, double temperature);

// Primitive reuse (helper.py L38-L88): every base prototype's primitives are replaced by a
// softmax(tau x -squared distance) mix of the other base classes' primitives (its own class masked
// by -9999 before the scaling; the weights detached, the primitives not), and each sample is
// scored by CKA against these rebuilt prototypes, with +1e-6 in the denominator. maps: N x D x n,
// unpowered; prototypes: B x D x m. Returns N x B CKA values (the caller scales them).
torch::Tensor reuse_similarity(const torch::Tensor& maps, const torch::Tensor& prototypes, double tau);

}  // namespace fscil
