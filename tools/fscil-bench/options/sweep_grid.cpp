#include "tools/fscil-bench/options/sweep_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>

#include "reports/run_record.h"
#include "core/error.h"
#include "core/number_text.h"
#include "core/shown_text.h"

namespace fscil {

std::vector<GridAxis> parse_grid(const std::vector<std::string>& texts) {
  std::vector<GridAxis> axes;
  for (const auto& text : texts) {
    const auto equals = text.find('=');
    if (equals == std::string::npos) throw CliError(fmt::format("--grid '{}': expected key=value1,value2,...", text));
    GridAxis axis{text.substr(0, equals), {}};
    if (!is_grid_text(axis.key)) {
      throw CliError(fmt::format("--grid '{}': the key must be letters, digits, '_', '.' or '-'", text));
    }
    if (std::any_of(axes.begin(), axes.end(), [&](const GridAxis& other) { return other.key == axis.key; })) {
      throw CliError(fmt::format("--grid {}: given twice; list all its values in one --grid", axis.key));
    }
    const std::string list = text.substr(equals + 1);
    // Bounded before the values are read: 300 000 of them once took minutes to reach the refusal below.
    if (const auto values = static_cast<std::size_t>(std::count(list.begin(), list.end(), ',')) + 1;
        values > static_cast<std::size_t>(kMaxGridCells)) {
      throw CliError(fmt::format("--grid {}: {} values are more than the {} cells a sweep takes; split it into sweeps "
                                 "of fewer values", shown_text(axis.key), values, kMaxGridCells));
    }
    std::set<std::string> seen;
    std::map<double, std::string> seen_numbers;  // 16 and 16.0 are one value, so one run twice
    std::size_t start = 0;
    while (true) {
      const auto comma = list.find(',', start);
      const std::string value = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!is_grid_text(value)) {
        throw CliError(fmt::format("--grid '{}': value '{}' is empty or holds characters other than letters, "
                                   "digits, '_', '.' and '-'", text, value));
      }
      if (!seen.insert(value).second) {
        throw CliError(fmt::format("--grid '{}': value {} given twice", text, value));
      }
      if (const auto number = parse_finite_number(value)) {
        if (const auto [earlier, added] = seen_numbers.emplace(*number, value); !added) {
          throw CliError(fmt::format("--grid '{}': values {} and {} are one number; give it once", text,
                                     earlier->second, value));
        }
      }
      axis.values.push_back(value);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    axes.push_back(std::move(axis));
  }
  if (axes.empty()) throw CliError("sweep: expected at least one --grid key=value1,value2,...");
  // Counted before any cell is made: a grid of 4e9 cells once filled memory before it said anything.
  double cells = 1;
  std::string sizes;
  for (const auto& axis : axes) {
    cells *= static_cast<double>(axis.values.size());
    sizes += fmt::format("{}{}", sizes.empty() ? "" : " x ", axis.values.size());
  }
  if (cells > kMaxGridCells) {
    throw CliError(fmt::format("--grid: {} cells ({}) are more than the {} a sweep takes; split it into sweeps "
                               "of fewer values", cells, sizes, kMaxGridCells));
  }
  return axes;
}

std::vector<GridCell> grid_cells(const std::vector<GridAxis>& axes) {
  std::vector<GridCell> cells = {{}};
  for (const auto& axis : axes) {
    std::vector<GridCell> extended;
    for (const auto& cell : cells) {
      for (const auto& value : axis.values) {
        extended.push_back(cell);
        extended.back().emplace_back(axis.key, value);
      }
    }
    cells = std::move(extended);
  }
  return cells;
}

}  // namespace fscil
