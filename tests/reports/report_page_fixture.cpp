// Writes a small results folder with figures of each kind, a sweep cell in a subfolder and its
// report page, for the browser test (tests/reports/report_page_browser_test.sh) and for looking
// at by hand: fscil_report_page_fixture DIR, then open DIR/index.html.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <string>

#include "core/atomic_file.h"
#include "reports/figure_writer.h"
#include "reports/report_page.h"

namespace {

using fscil::Figure;
using fscil::FigureKind;
using fscil::FigureSeries;

constexpr double gap = std::numeric_limits<double>::quiet_NaN();

Figure accuracy_per_session(double shift) {
  Figure figure;
  figure.name = "accuracy_per_session";
  figure.title = "Accuracy per session, simtex";
  figure.x_label = "session";
  figure.y_label = "accuracy (%)";
  figure.kind = FigureKind::lines;
  const std::vector<double> sessions = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  figure.series = {{"prototype", sessions, {91.2, 84.5, 79.9, 75.3, 71.8, 68.2, 65.4, 62.9, 60.1}},
                   {"cop-fscil", sessions, {92.0, 86.1, 82.4, gap, 76.0, 73.3, 70.9, 68.8, 66.5}},
                   {"pits-sc & <orco>", sessions, {90.4, 83.0, 78.2, 74.0, 70.1, 66.7, 63.5, 60.8, 58.0}}};
  for (auto& series : figure.series) {
    for (double& y : series.y) y += shift;
  }
  return figure;
}

Figure cost_per_method() {
  Figure figure;
  figure.name = "cost_per_method";
  figure.title = "Training time per method";
  figure.y_label = "seconds";
  figure.kind = FigureKind::bars;
  figure.x_categories = {"prototype", "pits-sc", "cop-fscil/cpi", "cop-fscil", "orco"};
  figure.series = {{"base session", {0, 1, 2, 3, 4}, {41.5, 48.2, 52.0, 55.7, 80.3}},
                   {"per incremental session", {0, 1, 2, 3, 4}, {0.4, 3.1, 3.3, gap, 9.8}}};
  return figure;
}

Figure prototypes_on_unit_circle() {
  Figure figure;
  figure.name = "prototypes_on_unit_circle";
  figure.title = "Class prototypes, first two directions";
  figure.x_label = "u1";
  figure.y_label = "u2";
  figure.kind = FigureKind::scatter;
  figure.equal_axes = true;
  figure.draw_unit_circle = true;
  figure.note = "selected on test (inflated)";
  FigureSeries base{"base classes", {}, {}}, novel{"novel classes", {}, {}};
  for (int c = 0; c < 12; ++c) {
    const double angle = 2 * std::acos(-1.0) * c / 12;
    auto& series = c < 8 ? base : novel;
    series.x.push_back(0.92 * std::cos(angle));
    series.y.push_back(0.92 * std::sin(angle));
  }
  figure.series = {base, novel};
  return figure;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path folder = argv[1];
    fscil::write_file_atomically(folder / "summary.csv",
                                 "method,dataset,split,seeds,AA,PD,ADR\nprototype,simtex,test,1,70.12,31.10,3.89\n"
                                 "<b>cop-fscil</b> & \"x\",simtex,test,1,75.53,25.50,3.19\n");
    fscil::write_file_atomically(folder / "results.tex", "% table\n");
    // As wide as the main job's sessions.csv: whole on a 1400 px page, cut in a narrower one.
    std::string sessions = "method,dataset,split,selection,precision,seed,session,seen_classes,accuracy,base,novel,"
                           "current,harmonic,train_seconds,test_seconds,R\n";
    for (int session = 0; session < 9; ++session) {
      sessions += fmt::format("cop-fscil/cpi+pcqa,sf-instruments,validation,last,fp32,1,{},{},81.25,83.50,"
                              "{},77.10,80.17,123.45,4.56,0.3125\n", session, 60 + 5 * session, 70.0 + session);
    }
    fscil::write_file_atomically(folder / "sessions.csv", sessions);
    fscil::write_file_atomically(folder / "results" / "prototype__simtex__seed1.json", "{}\n");
    fscil::write_file_atomically(folder / "checkpoints" / "orco__simtex__seed1.ckpt", "partial\n");
    fscil::write_figure(folder, accuracy_per_session(0));
    fscil::write_figure(folder, cost_per_method());
    fscil::write_figure(folder, prototypes_on_unit_circle());
    const std::filesystem::path cell = folder / "shot-5";
    fscil::write_file_atomically(cell / "summary.csv", "method,dataset,AA\nprototype,simtex,72.40\n");
    fscil::write_figure(cell, accuracy_per_session(2.5));
    fscil::write_report_page(folder);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
  return 0;
}
