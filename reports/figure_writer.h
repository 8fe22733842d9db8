#pragma once
#include <filesystem>

#include "core/atomic_file.h"
#include "reports/figure.h"

namespace fscil {

// Adds `folder`/figures/NAME.svg, NAME.tex (pgfplots) and NAME.csv (the data) to `files`. Throws
// ReportError for a figure require_valid_figure refuses, adding nothing.
void add_figure(FileBatch& files, const std::filesystem::path& folder, const Figure& figure);

// add_figure, written at once: the three files replace their old versions together or not at all
// (FileBatch), creating the folder. Throws FileError when one cannot be written.
void write_figure(const std::filesystem::path& folder, const Figure& figure);

}  // namespace fscil
