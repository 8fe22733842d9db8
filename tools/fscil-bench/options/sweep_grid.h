#pragma once
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// One --grid of a sweep: a --set key (or shot, way, selection) and the values it takes.
struct GridAxis {
  std::string key;
  std::vector<std::string> values;
};

// The most cells one sweep takes: at a minute a cell (smoke scale) a week of work; more is a typo.
constexpr int kMaxGridCells = 10000;

// "key=v1,v2,..." per --grid; throws CliError naming the text on a missing '=', an empty or
// repeated value, a key given twice, characters other than letters, digits, '_', '.', '-', or
// more than kMaxGridCells cells in all.
std::vector<GridAxis> parse_grid(const std::vector<std::string>& texts);

// Every combination of one value per axis (the first axis varies slowest), its keys in the axes' order.
std::vector<GridCell> grid_cells(const std::vector<GridAxis>& axes);

}  // namespace fscil
