#include "reports/embedding_figure.h"

#include <fmt/format.h>
#include <torch/torch.h>

#include <algorithm>

#include "core/error.h"
#include "datasets/hdf5_file.h"

namespace fscil {

namespace {

// `count` classes spread evenly over [first, end).
std::vector<std::int32_t> spread(std::int32_t first, std::int32_t end, int count) {
  std::vector<std::int32_t> classes;
  const std::int32_t range = end - first;
  for (int k = 0; k < std::min<std::int32_t>(count, range); ++k) {
    classes.push_back(first + static_cast<std::int32_t>(static_cast<std::int64_t>(k) * range / std::min(count, range)));
  }
  return classes;
}

}  // namespace

Figure embedding_figure(const std::filesystem::path& embeddings_file, const std::string& name, const std::string& title,
                        int per_side) {
  const std::vector<std::int32_t> sessions = read_hdf5_integers(embeddings_file, "sessions");
  if (sessions.empty()) throw DatasetError(fmt::format("{}: holds no saved session embeddings", embeddings_file.string()));
  const std::int32_t session = sessions.back();
  const FloatArray embeddings = read_hdf5_floats(embeddings_file, fmt::format("session_{}_embeddings", session), 2);
  const std::vector<std::int32_t> labels = read_hdf5_integers(embeddings_file, fmt::format("session_{}_labels", session));
  const std::vector<std::int32_t> base = read_hdf5_integers(embeddings_file, "base_classes");
  if (base.size() != 1 || labels.size() != static_cast<std::size_t>(embeddings.shape[0])) {
    throw DatasetError(fmt::format("{}: labels and embeddings of session {} do not match", embeddings_file.string(),
                                   session));
  }
  const std::int32_t seen = *std::max_element(labels.begin(), labels.end()) + 1;
  std::vector<std::int32_t> classes = spread(0, base[0], per_side);
  for (std::int32_t c : spread(base[0], seen, per_side)) classes.push_back(c);

  std::vector<std::int64_t> rows;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (std::find(classes.begin(), classes.end(), labels[i]) != classes.end()) rows.push_back(static_cast<std::int64_t>(i));
  }
  const torch::Tensor all = torch::from_blob(const_cast<float*>(embeddings.values.data()),
                                             {embeddings.shape[0], embeddings.shape[1]}, torch::kFloat)
                                .to(torch::kDouble);
  torch::Tensor points = all.index_select(0, torch::tensor(rows));
  points = points - points.mean(0);
  const torch::Tensor directions = std::get<2>(torch::linalg::svd(points, false, c10::nullopt)).narrow(0, 0, 2);
  const torch::Tensor plane = torch::nn::functional::normalize(points.matmul(directions.t()),
                                                               torch::nn::functional::NormalizeFuncOptions().dim(1));
  Figure figure;
  figure.name = name;
  figure.title = title;
  figure.kind = FigureKind::scatter;
  figure.x_label = "first principal direction";
  figure.y_label = "second principal direction";
  figure.equal_axes = true;
  figure.draw_unit_circle = true;
  for (std::int32_t c : classes) {
    FigureSeries series{fmt::format("class {} ({})", c, c < base[0] ? "base" : "novel"), {}, {}};
    for (std::size_t r = 0; r < rows.size(); ++r) {
      if (labels[static_cast<std::size_t>(rows[r])] != c) continue;
      series.x.push_back(plane[static_cast<std::int64_t>(r)][0].item<double>());
      series.y.push_back(plane[static_cast<std::int64_t>(r)][1].item<double>());
    }
    figure.series.push_back(std::move(series));
  }
  return figure;
}

}  // namespace fscil
