#include "reports/figure_writer.h"

#include "core/atomic_file.h"
#include "reports/figure_csv.h"
#include "reports/pgfplots_figure.h"
#include "reports/svg_figure.h"

namespace fscil {

void write_figure(const std::filesystem::path& folder, const Figure& figure) {
  // All three rendered first, so a figure that cannot be rendered leaves no file behind.
  const std::string svg = render_svg(figure), tex = render_pgfplots(figure), csv = render_figure_csv(figure);
  const std::filesystem::path figures = folder / "figures";  // write_file_atomically creates it
  write_file_atomically(figures / (figure.name + ".svg"), svg);
  write_file_atomically(figures / (figure.name + ".tex"), tex);
  write_file_atomically(figures / (figure.name + ".csv"), csv);
}

}  // namespace fscil
