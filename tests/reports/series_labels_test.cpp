#include "reports/series_labels.h"

#include <gtest/gtest.h>

#include <set>

#include "reports/figure.h"

namespace fscil {
namespace {

TEST(SeriesLabels, EveryKeyInTheGridsOrderWhileTheLabelsFit) {
  const SeriesLabels labels = series_labels({{"pits-sc", {{"shot", "1"}, {"epochs_new", "5"}}}, {"orco", {}}}, 40);
  EXPECT_EQ(labels.labels, (std::vector<std::string>{"pits-sc [shot=1+epochs_new=5]", "orco"}));
  EXPECT_EQ(labels.shared, "");
}

// The sweep of the issue: `--grid shot=1,5 --grid epochs_new=5,20 --methods pits-sc`, whose legend
// read "pits-sc [epochs_new=5+shot=…" twice.
TEST(SeriesLabels, WhatEverySeriesSharesMovesToTheNoteAndTheRestStaysWhole) {
  std::vector<SeriesName> cells;
  for (const char* shot : {"1", "5"}) {
    for (const char* epochs : {"5", "20"}) cells.push_back({"pits-sc", {{"shot", shot}, {"epochs_new", epochs}}});
  }
  const SeriesLabels labels = series_labels(cells, figure_legend_width);
  EXPECT_EQ(labels.labels, (std::vector<std::string>{"shot=1+epochs_new=5", "shot=1+epochs_new=20",
                                                      "shot=5+epochs_new=5", "shot=5+epochs_new=20"}));
  EXPECT_EQ(labels.shared, "pits-sc");

  cells.push_back({"pits-sc", {{"shot", "5"}, {"epochs_new", "50"}}});
  for (auto& cell : cells) cell.cell.emplace_back("way", "5");  // one value: says nothing about which is which
  const SeriesLabels with_way = series_labels(cells, figure_legend_width);
  EXPECT_EQ(with_way.labels.back(), "shot=5+epochs_new=50");
  EXPECT_EQ(with_way.shared, "pits-sc; way=5");
}

TEST(SeriesLabels, KeysTooLongAreShortenedToDistinctPrefixesSpeltOutInTheNote) {
  const std::vector<SeriesName> cells = {{"cop-fscil", {{"pspc_probes", "5"}, {"pspc_mean", "views"}}},
                                         {"cop-fscil", {{"pspc_probes", "50"}, {"pspc_mean", "original"}}},
                                         {"pits-sc", {{"pspc_probes", "5"}, {"pspc_mean", "views"}}}};
  const SeriesLabels labels = series_labels(cells, 24);
  EXPECT_EQ(labels.labels, (std::vector<std::string>{"cop-fscil [pspc_p=5+pspc_m=views]",
                                                      "cop-fscil [pspc_p=50+pspc_m=original]",
                                                      "pits-sc [pspc_p=5+pspc_m=views]"}))
      << "a label still too wide is kept whole, never cut";
  EXPECT_EQ(labels.shared, "pspc_p = pspc_probes; pspc_m = pspc_mean");
  EXPECT_EQ(std::set<std::string>(labels.labels.begin(), labels.labels.end()).size(), cells.size());
}

TEST(SeriesLabels, AKeyThatStartsAnotherIsKeptWhole) {
  const SeriesLabels labels =
      series_labels({{"a-method", {{"lr", "0.1"}, {"lr_new", "0.01"}}}, {"b-method", {{"lr", "1"}, {"lr_new", "0.1"}}}}, 12);
  EXPECT_EQ(labels.labels, (std::vector<std::string>{"a-method [lr=0.1+lr_=0.01]", "b-method [lr=1+lr_=0.1]"}));
  EXPECT_EQ(labels.shared, "lr_ = lr_new");
}

TEST(SeriesLabels, OneSeriesOrIdenticalSeriesKeepTheirWholeLabels) {
  const SeriesName long_name{"cop-fscil/cpi+pspc", {{"pspc_probes", "5"}}};
  EXPECT_EQ(series_labels({long_name}, 10).labels, (std::vector<std::string>{"cop-fscil/cpi+pspc [pspc_probes=5]"}));
  EXPECT_EQ(series_labels({long_name, long_name}, 10).labels.front(), "cop-fscil/cpi+pspc [pspc_probes=5]");
}

}  // namespace
}  // namespace fscil
