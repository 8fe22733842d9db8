#pragma once
#include <array>
#include <cstddef>

namespace fscil {

// Okabe and Ito's colour-blind-safe palette without its yellow (too pale on white paper), then
// Tol's wine, olive, indigo and purple, Brewer's magenta and ochre and a grey: fourteen colours, as
// hexadecimal RGB, so the thirteen methods of --methods all each have their own, no two closer
// than 25 CIELAB units.
inline constexpr std::array<const char*, 14> figure_palette = {"0072B2", "D55E00", "009E73", "CC79A7", "E69F00",
                                                                "56B4E9", "000000", "882255", "999933", "332288",
                                                                "AA4499", "E7298A", "A6761D", "7F7F7F"};
inline constexpr int figure_dash_kinds = 5;    // solid, dashed, dotted, dash-dot, densely dashed
inline constexpr int figure_marker_kinds = 8;  // disc, square, triangle, diamond, inverted triangle, ring, hollow square, cross
inline constexpr int figure_hatch_kinds = 7;   // solid, /, \, horizontal, vertical, grid, dots

// How series `index` of a figure looks, the same in every renderer, so a method keeps its colour
// from the report page to the paper. Dash, marker and hatching cycle at other lengths than the
// colours, so series past the fourteenth still differ, and all of them differ in grey.
struct SeriesStyle {
  const char* colour;
  int dash;
  int marker;
  int hatch;
};

inline SeriesStyle series_style(std::size_t index) {
  return {figure_palette[index % figure_palette.size()], static_cast<int>(index % figure_dash_kinds),
          static_cast<int>(index % figure_marker_kinds), static_cast<int>(index % figure_hatch_kinds)};
}

}  // namespace fscil
