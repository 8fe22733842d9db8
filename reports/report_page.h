#pragma once
#include <filesystem>
#include <string>

#include "core/atomic_file.h"

namespace fscil {

// The report page of a results folder: one self-contained HTML5 page (inline CSS, no script, no
// network, relative links only, so it opens from disk) that links every table file (*.csv, *.tex,
// *.md) of the folder and its subfolders, shows the top folder's CSV tables inline, and shows every
// figure (figures/NAME.svg at any depth) with its title and note (read from the SVG) and links to
// its NAME.tex and NAME.csv. Grouped by folder, as a sweep writes each cell into a subfolder;
// sorted, so a folder gives the same page byte for byte. Run result files (results/*.json) are
// counted and their folder linked, not listed; checkpoints/ and hidden files are left out.
// Throws ReportError when `results_folder` is not a readable folder. With `pending`, the page of
// the folder as it will be once those files are written (a report rendering its page beside them).
std::string render_report_page(const std::filesystem::path& results_folder, const FileBatch* pending = nullptr);

// Adds `results_folder`/index.html, the page of the folder once `files` are written, to `files`.
void add_report_page(FileBatch& files, const std::filesystem::path& results_folder);

// Writes render_report_page(results_folder) as `results_folder`/index.html (write_file_atomically).
void write_report_page(const std::filesystem::path& results_folder);

}  // namespace fscil
