#pragma once
#include <string>

#include "reports/figure.h"

namespace fscil {

// The figure's data as tidy CSV, `series,x,y`, one line per point in series order: x as the
// category's name when x is categorical, numbers with 8 significant digits (every decimal a table
// shows), a gap's y empty. A field holding a comma, quote or line break is quoted (RFC 4180), as
// labels are free text. Throws ReportError for a figure require_valid_figure refuses.
std::string render_figure_csv(const Figure& figure);

}  // namespace fscil
