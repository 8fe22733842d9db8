#include "reports/figure_writer.h"

#include "reports/figure_csv.h"
#include "reports/pgfplots_figure.h"
#include "reports/svg_figure.h"

namespace fscil {

void add_figure(FileBatch& files, const std::filesystem::path& folder, const Figure& figure) {
  // All three rendered first, so a figure that cannot be rendered adds no file.
  std::string svg = render_svg(figure), tex = render_pgfplots(figure), csv = render_figure_csv(figure);
  const std::filesystem::path figures = folder / "figures";
  files.add(figures / (figure.name + ".svg"), std::move(svg));
  files.add(figures / (figure.name + ".tex"), std::move(tex));
  files.add(figures / (figure.name + ".csv"), std::move(csv));
}

void write_figure(const std::filesystem::path& folder, const Figure& figure) {
  FileBatch files;
  add_figure(files, folder, figure);
  files.replace_all();
}

}  // namespace fscil
