#include "reports/report_page.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "reports/figure_writer.h"
#include "core/error.h"
#include "core/text_file.h"
#include "tests/reports/markup_checks.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

Figure accuracy_figure(const std::string& title, const std::string& note = "") {
  Figure figure;
  figure.name = "accuracy";
  figure.title = title;
  figure.note = note;
  figure.series = {{"prototype", {0, 1, 2}, {90, 80, 70}}};
  return figure;
}

// A results folder as a run and a sweep leave it, with the files the page must leave out.
void write_results_folder(const fs::path& folder) {
  write_file_atomically(folder / "summary.csv", "method,dataset,AA\nprototype,simtex,70.12\n");
  write_file_atomically(folder / "results.tex", "% table\n");
  write_file_atomically(folder / "notes.md", "# notes\n");
  write_file_atomically(folder / "run.log", "not a table\n");
  write_file_atomically(folder / "results" / "prototype__simtex__seed1.json", "{}");
  write_file_atomically(folder / "results" / "prototype__simtex__seed2.json", "{}");
  write_file_atomically(folder / "results" / "stray.csv", "x\n");
  write_file_atomically(folder / "checkpoints" / "orco__simtex__seed1.ckpt", "partial");
  write_file_atomically(folder / "checkpoints" / "left_behind.csv", "x\n");
  write_file_atomically(folder / ".cache" / "hidden.csv", "x\n");
  write_file_atomically(folder / ".hidden.csv", "x\n");
  write_file_atomically(folder / "summary.csv.tmp-host-123", "half a file");
  write_figure(folder, accuracy_figure("Accuracy & forgetting"));
  write_file_atomically(folder / "shot-10" / "summary.csv", "method,AA\nprototype,74\n");
  write_file_atomically(folder / "shot-5" / "summary.csv", "method,AA\nprototype,72\n");
  write_file_atomically(folder / "shot-5" / "results" / "prototype__simtex__seed1.json", "{}");
  write_figure(folder / "shot-5", accuracy_figure("Accuracy, 5 shots", "selected on test (inflated)"));
}

// Issue 70: tables came alphabetically (costs, the 130-row sessions.csv, summary.csv last) and
// figures too (R first, accuracy per session last).
TEST(ReportPage, ShowsTheSummaryThenAccuracyPerSessionThenCostsThenTheRest) {
  const TemporaryDirectory temporary;
  const fs::path folder = temporary.path();
  for (const char* table : {"costs.csv", "sessions.csv", "summary.csv", "ablation.csv", "context_analysis.csv"}) {
    write_file_atomically(folder / table, "method,AA\nprototype,70\n");
  }
  for (const char* name : {"context_ratio_simtex", "efficiency_simtex_flops", "sessions_simtex_novel", "sessions_simtex_all",
                           "sessions_simtex_harmonic", "sessions_simtex_base"}) {
    Figure figure = accuracy_figure(name);
    figure.name = name;
    write_figure(folder, figure);
  }
  const std::string page = render_report_page(folder);
  std::vector<std::size_t> places;
  for (const char* shown : {"<h3><a href=\"summary.csv\">", "<h3><a href=\"ablation.csv\">", "alt=\"sessions_simtex_all\"",
                            "alt=\"sessions_simtex_base\"", "alt=\"sessions_simtex_novel\"",
                            "alt=\"sessions_simtex_harmonic\"", "<h3><a href=\"costs.csv\">",
                            "alt=\"efficiency_simtex_flops\"", "alt=\"context_ratio_simtex\"",
                            "<h3><a href=\"context_analysis.csv\">", "<h3><a href=\"sessions.csv\">"}) {
    places.push_back(page.find(shown));
    EXPECT_NE(places.back(), std::string::npos) << shown;
  }
  EXPECT_TRUE(std::is_sorted(places.begin(), places.end())) << page;
}

TEST(ReportPage, LinksEveryTableAndFigureAndNothingElse) {
  const TemporaryDirectory temporary;
  const fs::path folder = temporary.path() / "results-1";
  write_results_folder(folder);
  const std::string page = render_report_page(folder);
  SCOPED_TRACE(page);
  EXPECT_EQ(markup_problem(page, html_void_elements), "");
  EXPECT_EQ(occurrences(page, "<li><a href=\"summary.csv\">summary.csv</a></li>"), 1u);
  EXPECT_EQ(occurrences(page, "<h3><a href=\"summary.csv\">summary.csv</a></h3>"), 1u);  // shown inline
  for (const char* link : {"href=\"results.tex\"", "href=\"notes.md\"", "href=\"results/\"",
                           "href=\"shot-5/summary.csv\"", "href=\"shot-10/summary.csv\"", "href=\"shot-5/results/\"",
                           "href=\"figures/accuracy.tex\"", "href=\"figures/accuracy.csv\"",
                           "href=\"shot-5/figures/accuracy.tex\"", "href=\"shot-5/figures/accuracy.csv\"",
                           "<img src=\"figures/accuracy.svg\" alt=\"Accuracy &amp; forgetting\">",
                           "<img src=\"shot-5/figures/accuracy.svg\" alt=\"Accuracy, 5 shots\">"}) {
    EXPECT_EQ(occurrences(page, link), 1u) << link;
  }
  EXPECT_EQ(occurrences(page, "<img "), 2u);
  EXPECT_NE(page.find("2 run result files (JSON)"), std::string::npos);
  EXPECT_NE(page.find("1 run result file (JSON)"), std::string::npos);
  for (const char* left_out : {".json", "checkpoints", "left_behind", ".cache", "hidden", "tmp-host", "stray", "run.log",
                               "href=\"/", "file:", "http"}) {
    EXPECT_EQ(page.find(left_out), std::string::npos) << left_out;
  }
  // Folders in natural order: shot-5 before shot-10, after the top folder's own section.
  const std::size_t top = page.find("<h2>This folder</h2>"), five = page.find("<h2><code>shot-5/</code></h2>"),
                    ten = page.find("<h2><code>shot-10/</code></h2>");
  ASSERT_NE(top, std::string::npos);
  ASSERT_NE(five, std::string::npos);
  ASSERT_NE(ten, std::string::npos);
  EXPECT_LT(top, five);
  EXPECT_LT(five, ten);
  EXPECT_LT(page.find("href=\"shot-5/figures/accuracy.csv\""), ten);
  // The top folder's CSV is shown as a table, a subfolder's only linked.
  EXPECT_NE(page.find("<th>method</th><th>dataset</th><th>AA</th>"), std::string::npos);
  EXPECT_NE(page.find("<td>prototype</td><td>simtex</td><td class=\"number\">70.12</td>"), std::string::npos);
  EXPECT_EQ(page.find("<td class=\"number\">72</td>"), std::string::npos);
}

TEST(ReportPage, ShowsEachFiguresTitleAndNote) {
  const TemporaryDirectory temporary;
  write_results_folder(temporary.path());
  const std::string page = render_report_page(temporary.path());
  EXPECT_NE(page.find("<figcaption><strong>Accuracy, 5 shots</strong> <span class=\"note\">(selected on test "
                      "(inflated))</span>"),
            std::string::npos);
  EXPECT_NE(page.find("<figcaption><strong>Accuracy &amp; forgetting</strong><br>"), std::string::npos);
}

TEST(ReportPage, EscapesEveryCellAndName) {
  const TemporaryDirectory temporary;
  write_file_atomically(temporary.path() / "summary.csv",
                        "method,AA\n<script>alert(1)</script>,1\na&b \"q\" 'x',2\n");
  write_file_atomically(temporary.path() / "a b&c.csv", "x\n1\n");
  const std::string page = render_report_page(temporary.path());
  EXPECT_EQ(markup_problem(page, html_void_elements), "");
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_NE(page.find("<td>&lt;script&gt;alert(1)&lt;/script&gt;</td>"), std::string::npos);
  EXPECT_NE(page.find("<td>a&amp;b &quot;q&quot; &#39;x&#39;</td>"), std::string::npos);
  EXPECT_NE(page.find("<a href=\"a%20b%26c.csv\">a b&amp;c.csv</a>"), std::string::npos);
}

TEST(ReportPage, IsTheSameForTheSameFolder) {
  const TemporaryDirectory first, second;
  write_results_folder(first.path() / "results");
  // The same files written in another order.
  const fs::path other = second.path() / "results";
  write_file_atomically(other / "shot-5" / "summary.csv", "method,AA\nprototype,72\n");
  write_figure(other / "shot-5", accuracy_figure("Accuracy, 5 shots", "selected on test (inflated)"));
  write_results_folder(other);
  const std::string page = render_report_page(first.path() / "results");
  EXPECT_EQ(render_report_page(other), page);
  EXPECT_EQ(render_report_page(first.path() / "results"), page);
  EXPECT_NE(page.find("<title>fscil-bench report: results</title>"), std::string::npos);
  EXPECT_EQ(render_report_page(first.path() / "results/"), page);
}

TEST(ReportPage, WritesIndexHtml) {
  const TemporaryDirectory temporary;
  write_results_folder(temporary.path());
  write_report_page(temporary.path());
  const std::string written = read_text_file(temporary.path() / "index.html");
  EXPECT_EQ(written.rfind("<!DOCTYPE html>\n<html lang=\"en\">", 0), 0u);
  EXPECT_NE(written.find("<meta charset=\"utf-8\">"), std::string::npos);
  EXPECT_NE(written.find("<style>"), std::string::npos);
  EXPECT_EQ(render_report_page(temporary.path()), written);  // the page does not list itself
}

// A report renders its page before its tables and figures are written, so that all of them replace
// the old ones together: the page of the pending files must be the page of the folder once written.
TEST(ReportPage, OfPendingFilesIsThePageOfTheFolderOnceTheyAreWritten) {
  for (const bool folder_exists : {true, false}) {
    const TemporaryDirectory temporary;
    const fs::path folder = temporary.path() / "out";
    if (folder_exists) write_results_folder(folder);
    FileBatch files;
    files.add(folder / "summary.csv", "method,dataset,AA\nprototype,simtex,71.50\n");
    files.add(folder / "costs.csv", "method,flops\nprototype,12\n");
    Figure figure = accuracy_figure("Accuracy, new");
    figure.name = "sessions_simtex_all";
    add_figure(files, folder, figure);
    add_report_page(files, folder);
    const std::string pending_page = *files.find(folder / "index.html");
    EXPECT_NE(pending_page.find("71.50"), std::string::npos);
    EXPECT_NE(pending_page.find("alt=\"Accuracy, new\""), std::string::npos);
    files.replace_all();
    EXPECT_EQ(read_text_file(folder / "index.html"), pending_page) << (folder_exists ? "a folder" : "a new folder");
    EXPECT_EQ(render_report_page(folder), pending_page);
  }
}

TEST(ReportPage, SaysSoWhenTheFolderIsEmptyAndRefusesAMissingOne) {
  const TemporaryDirectory temporary;
  const std::string page = render_report_page(temporary.path());
  EXPECT_NE(page.find("No tables or figures in this folder yet."), std::string::npos);
  EXPECT_EQ(markup_problem(page, html_void_elements), "");
  EXPECT_THROW(render_report_page(temporary.path() / "missing"), ReportError);
}

}  // namespace
}  // namespace fscil
