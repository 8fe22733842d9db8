#pragma once
#include <filesystem>

#include "reports/figure.h"

namespace fscil {

// Writes `folder`/figures/NAME.svg, NAME.tex (pgfplots) and NAME.csv (the data), creating the
// folder; each file whole or not at all (write_file_atomically). Throws ReportError for a figure
// require_valid_figure refuses, before any file is written, and FileError when one cannot be.
void write_figure(const std::filesystem::path& folder, const Figure& figure);

}  // namespace fscil
