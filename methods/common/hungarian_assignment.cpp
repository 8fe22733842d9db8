#include "methods/common/hungarian_assignment.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fscil {

namespace {

void check_shape(const std::vector<std::vector<double>>& cost) {
  if (cost.empty() || cost.front().empty()) throw std::invalid_argument("assignment: empty cost matrix");
  const std::size_t columns = cost.front().size();
  for (const auto& row : cost) {
    if (row.size() != columns) throw std::invalid_argument("assignment: rows of different lengths");
    for (double value : row) {
      if (!std::isfinite(value)) throw std::invalid_argument("assignment: cost is not finite");
    }
  }
  if (cost.size() > columns) {
    throw std::invalid_argument("assignment: " + std::to_string(cost.size()) + " rows but only " +
                                std::to_string(columns) + " columns");
  }
}

}  // namespace

std::vector<std::size_t> min_cost_assignment(const std::vector<std::vector<double>>& cost) {
  check_shape(cost);
  const std::size_t rows = cost.size(), columns = cost.front().size();
  const double infinity = std::numeric_limits<double>::infinity();
  // 1-based with a virtual column 0: row_potential[i], column_potential[j] keep every reduced cost
  // cost[i][j] - row_potential[i] - column_potential[j] non-negative; row_of_column[j] is the
  // row matched to column j (0 = free).
  std::vector<double> row_potential(rows + 1, 0.0), column_potential(columns + 1, 0.0);
  std::vector<std::size_t> row_of_column(columns + 1, 0), previous_column(columns + 1, 0);
  for (std::size_t row = 1; row <= rows; ++row) {
    row_of_column[0] = row;
    std::size_t column = 0;
    std::vector<double> slack(columns + 1, infinity);
    std::vector<bool> visited(columns + 1, false);
    // Grow an alternating tree from the new row until it reaches a free column.
    do {
      visited[column] = true;
      const std::size_t tree_row = row_of_column[column];
      double delta = infinity;
      std::size_t next_column = 0;
      for (std::size_t j = 1; j <= columns; ++j) {
        if (visited[j]) continue;
        const double reduced = cost[tree_row - 1][j - 1] - row_potential[tree_row] - column_potential[j];
        if (reduced < slack[j]) {
          slack[j] = reduced;
          previous_column[j] = column;
        }
        if (slack[j] < delta) {
          delta = slack[j];
          next_column = j;
        }
      }
      for (std::size_t j = 0; j <= columns; ++j) {
        if (visited[j]) {
          row_potential[row_of_column[j]] += delta;
          column_potential[j] -= delta;
        } else {
          slack[j] -= delta;
        }
      }
      column = next_column;
    } while (row_of_column[column] != 0);
    // Flip the augmenting path back to the root.
    do {
      const std::size_t before = previous_column[column];
      row_of_column[column] = row_of_column[before];
      column = before;
    } while (column != 0);
  }
  std::vector<std::size_t> column_of_row(rows, 0);
  for (std::size_t j = 1; j <= columns; ++j) {
    if (row_of_column[j] != 0) column_of_row[row_of_column[j] - 1] = j - 1;
  }
  return column_of_row;
}

std::vector<std::size_t> max_score_assignment(const std::vector<std::vector<double>>& score) {
  std::vector<std::vector<double>> cost = score;
  for (auto& row : cost) {
    for (double& value : row) value = -value;
  }
  return min_cost_assignment(cost);
}

}  // namespace fscil
