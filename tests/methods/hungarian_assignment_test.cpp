// The Kuhn-Munkres assignment against brute force on every small shape up to 7 x 7.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>

#include "methods/common/hungarian_assignment.h"
#include "core/random_draws.h"

namespace fscil {
namespace {

using Matrix = std::vector<std::vector<double>>;

double total_cost(const Matrix& cost, const std::vector<std::size_t>& columns) {
  double sum = 0;
  for (std::size_t row = 0; row < cost.size(); ++row) sum += cost[row][columns[row]];
  return sum;
}

// The cheapest total over every injective row -> column map, by enumerating column orders.
double brute_force_minimum(const Matrix& cost) {
  std::vector<std::size_t> columns(cost.front().size());
  std::iota(columns.begin(), columns.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, total_cost(cost, columns));
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

Matrix random_matrix(std::size_t rows, std::size_t columns, std::mt19937_64& generator, bool integers) {
  Matrix cost(rows, std::vector<double>(columns));
  for (auto& row : cost) {
    for (double& value : row) {
      // Integers in [0, 3] give many ties.
      value = integers ? static_cast<double>(uniform_int(generator, 0, 3)) : uniform_real(generator, -5.0, 5.0);
    }
  }
  return cost;
}

void expect_distinct_columns(const std::vector<std::size_t>& columns, std::size_t column_count) {
  const std::set<std::size_t> unique(columns.begin(), columns.end());
  EXPECT_EQ(unique.size(), columns.size());
  for (std::size_t column : columns) EXPECT_LT(column, column_count);
}

TEST(HungarianAssignment, EqualsBruteForceOnEverySmallShapeSquareAndRectangular) {
  std::mt19937_64 generator(17);
  int checked = 0;
  for (std::size_t rows = 1; rows <= 7; ++rows) {
    for (std::size_t columns = rows; columns <= 7; ++columns) {
      for (int trial = 0; trial < 12; ++trial) {
        const Matrix cost = random_matrix(rows, columns, generator, trial % 3 == 0);
        const auto assignment = min_cost_assignment(cost);
        ASSERT_EQ(assignment.size(), rows);
        expect_distinct_columns(assignment, columns);
        EXPECT_NEAR(total_cost(cost, assignment), brute_force_minimum(cost), 1e-9)
            << rows << " x " << columns << " trial " << trial;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 28 * 12);
}

TEST(HungarianAssignment, RectangularPicksTheCheapColumnsAndMaximisingFlipsTheSign) {
  // Two rows, four columns: the cheap cells are (0, 3) and (1, 1).
  const Matrix cost = {{5, 4, 9, 1}, {7, 0, 8, 6}};
  EXPECT_EQ(min_cost_assignment(cost), (std::vector<std::size_t>{3, 1}));
  const Matrix score = {{0.1, 0.9, 0.2}, {0.8, 0.85, 0.0}};
  // Row 0 takes column 1 and row 1 column 0: 1.7, the largest sum.
  EXPECT_EQ(max_score_assignment(score), (std::vector<std::size_t>{1, 0}));
  const Matrix conflict = {{1.0, 0.9}, {1.0, 0.0}};  // both prefer column 0; the sum decides
  EXPECT_EQ(max_score_assignment(conflict), (std::vector<std::size_t>{1, 0}));
}

TEST(HungarianAssignment, RefusesMoreRowsThanColumnsRaggedAndNonFiniteInput) {
  EXPECT_THROW(min_cost_assignment({{1, 2}, {3, 4}, {5, 6}}), std::invalid_argument);
  EXPECT_THROW(min_cost_assignment({{1, 2}, {3}}), std::invalid_argument);
  EXPECT_THROW(min_cost_assignment({}), std::invalid_argument);
  EXPECT_THROW(min_cost_assignment({{1, std::numeric_limits<double>::quiet_NaN()}}), std::invalid_argument);
}

}  // namespace
}  // namespace fscil
