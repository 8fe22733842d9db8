#pragma once
#include <string>

#include "reports/figure.h"

namespace fscil {

// The figure as a tikzpicture holding one pgfplots axis, for \input into a paper that loads
// pgfplots: title (with the note under it), axis labels, one \addplot coordinates {...} per series
// with its legend entry, in the colours, marks and dash patterns of render_svg. Bars are ybar over
// the category indices labelled with the categories' names; a gap in a line is a `nan` coordinate
// (unbounded coords=jump), a missing bar or point is left out. Throws ReportError for a figure
// require_valid_figure refuses.
std::string render_pgfplots(const Figure& figure);

}  // namespace fscil
