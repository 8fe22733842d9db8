#pragma once
#include <filesystem>
#include <string>

#include "reports/figure.h"

namespace fscil {

// The paper's embedding visualisation from a run's --save-embeddings file: of the last session
// saved, `per_side` base and `per_side` novel classes spread evenly over each range (the paper
// draws five of each at random), their test embeddings projected by PCA onto the first two
// principal directions and each normalised onto the unit circle; a scatter series per class.
// Throws DatasetError naming the file when it holds no saved session.
Figure embedding_figure(const std::filesystem::path& embeddings_file, const std::string& name,
                        const std::string& title, int per_side = 5);

}  // namespace fscil
