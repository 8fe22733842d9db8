#include "tools/fscil-bench/options/sweep_grid.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace fscil {
namespace {

using Cell = GridCell;

TEST(SweepGrid, ParsesEachKeyWithItsValuesInTheOrderGiven) {
  const auto axes = parse_grid({"pic_weight=0,1,0.1,1e-4", "selection=last,test-oracle", "shot=5"});
  ASSERT_EQ(axes.size(), 3u);
  EXPECT_EQ(axes[0].key, "pic_weight");
  EXPECT_EQ(axes[0].values, (std::vector<std::string>{"0", "1", "0.1", "1e-4"}));
  EXPECT_EQ(axes[1].key, "selection");
  EXPECT_EQ(axes[1].values, (std::vector<std::string>{"last", "test-oracle"}));
  EXPECT_EQ(axes[2].values, (std::vector<std::string>{"5"}));
}

TEST(SweepGrid, RejectsGarbage) {
  const std::vector<std::vector<std::string>> bad = {
      {},               // no grid at all
      {"shot"},         // no '='
      {"shot="},        // no value
      {"=1,2"},         // no key
      {"shot=1,,2"},    // an empty value
      {"shot=1,"},      // a trailing comma is an empty value
      {",shot=1"},      // a key with a comma
      {"shot=1,2,1"},   // a value twice
      {"shot=1", "way=5", "shot=2"},  // a key twice
      {"pic weight=1"},               // characters no folder or CSV field may hold
      {"shot=1;2"},
      {"shot=1 2"},
      {"cell=../up"},
      {"shot=5+way=3"},
      {"lr=1e-4=x"},
      {"shot=\xc3\xa9"}};
  for (const auto& texts : bad) {
    std::string shown;
    for (const auto& text : texts) shown += "[" + text + "]";
    EXPECT_THROW(parse_grid(texts), CliError) << shown;
  }
}

TEST(SweepGrid, ErrorsNameTheGridTextAndTheCulprit) {
  const auto message = [](const std::vector<std::string>& texts) {
    try {
      parse_grid(texts);
    } catch (const CliError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({"shot"}), "--grid 'shot': expected key=value1,value2,...");
  EXPECT_EQ(message({"shot=1,2,1"}), "--grid 'shot=1,2,1': value 1 given twice");
  // Round seven: 16 and 16.0 named two cells of one run.
  EXPECT_EQ(message({"temperature=16,8,16.0"}), "--grid 'temperature=16,8,16.0': values 16 and 16.0 are one number; give it once");
  EXPECT_EQ(message({"context_strength=1,1e0"}), "--grid 'context_strength=1,1e0': values 1 and 1e0 are one number; give it once");
  EXPECT_EQ(message({"shot=1", "shot=2"}), "--grid shot: given twice; list all its values in one --grid");
  EXPECT_NE(message({"shot=1,,2"}).find("--grid 'shot=1,,2': value '' is empty"), std::string::npos);
  EXPECT_EQ(message({}), "sweep: expected at least one --grid key=value1,value2,...");
}

TEST(SweepGrid, CellsAreEveryCombinationWithTheFirstAxisSlowest) {
  const auto cells = grid_cells(parse_grid({"shot=1,5", "pic_weight=0,0.1,1"}));
  EXPECT_EQ(cells, (std::vector<Cell>{{{"shot", "1"}, {"pic_weight", "0"}},
                                      {{"shot", "1"}, {"pic_weight", "0.1"}},
                                      {{"shot", "1"}, {"pic_weight", "1"}},
                                      {{"shot", "5"}, {"pic_weight", "0"}},
                                      {{"shot", "5"}, {"pic_weight", "0.1"}},
                                      {{"shot", "5"}, {"pic_weight", "1"}}}));
  EXPECT_EQ(grid_cells(parse_grid({"selection=last,validation,test-oracle"})),
            (std::vector<Cell>{{{"selection", "last"}}, {{"selection", "validation"}}, {{"selection", "test-oracle"}}}));
  EXPECT_EQ(grid_cells(parse_grid({"a=1", "b=2", "c=3,4"})).size(), 2u);
}

TEST(SweepGrid, RefusesAGridOfMoreCellsThanASweepTakesBeforeMakingAnyCell) {
  const auto axis = [](const std::string& key, int values) {
    std::string text = key + "=0";
    for (int v = 1; v < values; ++v) text += "," + std::to_string(v);
    return text;
  };
  EXPECT_EQ(parse_grid({axis("a", 100), axis("b", 100)}).size(), 2u);  // 10 000 cells: the most
  try {
    parse_grid({axis("a", 100), axis("b", 100), axis("c", 2)});
    FAIL() << "20 000 cells accepted";
  } catch (const CliError& error) {
    EXPECT_STREQ(error.what(), "--grid: 20000 cells (100 x 100 x 2) are more than the 10000 a sweep takes; split it "
                               "into sweeps of fewer values");
  }
  // 4.1e9 cells, as once filled 19.7 GB: refused as fast as any other typo.
  EXPECT_THROW(parse_grid({axis("a", 300), axis("b", 300), axis("c", 300), axis("d", 152)}), CliError);
}

}  // namespace
}  // namespace fscil
