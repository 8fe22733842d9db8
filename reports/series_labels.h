#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// What one series of a figure (a line, or a bar's category) shows: a method's row label and its
// sweep cell.
struct SeriesName {
  std::string method;
  GridCell cell;
};

struct SeriesLabels {
  std::vector<std::string> labels;  // one per name, in order
  std::string shared;               // what every series shares, for the figure's note; "" for nothing
};

// The one label rule of every figure: "method [key=value+key=value]" (label_with_cell), every key
// in the grid's order. Where a label is wider than `width` characters, what every series shares
// (the method, a key with one value) moves to `shared`, and if that is not enough each key is
// shortened to its shortest prefix (3 characters at least) no other key of the figure starts
// with, the abbreviations spelt out in `shared`. Labels stay distinct whatever they are shortened
// to; a label still too wide is kept whole.
SeriesLabels series_labels(const std::vector<SeriesName>& names, std::size_t width);

}  // namespace fscil
