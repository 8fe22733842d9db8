#pragma once
#include <string>

#include "reports/figure.h"

namespace fscil {

// The figure as a self-contained SVG 1.1 document, 640 pixels wide and 400 high (higher when a long
// legend needs it): title, note, axes with ticks at nice numbers, legend, and per series a colour
// of a palette that prints, with its own dash pattern and marker (lines, scatter) or hatching (bars)
// so series stay apart in grey. The note is drawn under the title and is the SVG's <desc>, the
// title its <title>. No script, font or file outside it. Throws ReportError for a figure
// require_valid_figure refuses.
std::string render_svg(const Figure& figure);

}  // namespace fscil
