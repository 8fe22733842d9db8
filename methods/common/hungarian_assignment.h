#pragma once
#include <cstddef>
#include <vector>

namespace fscil {

// Kuhn-Munkres with potentials, O(rows^2 * columns): the assignment of every row to its own
// column that minimises the summed cost. Needs rows <= columns; returns the column of each row.
// Throws std::invalid_argument on ragged, empty or too-tall matrices.
std::vector<std::size_t> min_cost_assignment(const std::vector<std::vector<double>>& cost);

// The same, maximising the summed score (OrCo assigns classes to the most similar targets).
std::vector<std::size_t> max_score_assignment(const std::vector<std::vector<double>>& score);

}  // namespace fscil
