#include "reports/report_page.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>

#include "core/atomic_file.h"
#include "reports/csv_fields.h"
#include "core/error.h"
#include "core/text_file.h"
#include "reports/xml_text.h"
#include "core/number_text.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

// Rows of a CSV shown inline; the linked file has them all.
constexpr std::size_t max_inline_rows = 1000;

const char* const page_style = R"(body{font-family:"DejaVu Sans","Liberation Sans",Arial,Helvetica,sans-serif;
color:#1a1a1a;line-height:1.45;max-width:100rem;margin:1.5rem auto;padding:0 1rem}
h1{font-size:1.5rem}h2{font-size:1.2rem;border-bottom:1px solid #bbb;padding-bottom:.2rem;margin-top:2.2rem}
h3{font-size:1rem;margin-top:1.4rem}ul.files{columns:18rem;padding-left:1.2rem}
div.table{overflow-x:auto;margin:.4rem 0 1.2rem}table{border-collapse:collapse;font-size:.8rem}
th,td{border:1px solid #ccc;padding:.15rem .45rem;text-align:left;white-space:nowrap}
th{background:#f0f0f0}td.number{text-align:right;font-variant-numeric:tabular-nums}
div.figures{display:flex;flex-wrap:wrap;gap:0 2rem}figure{margin:.5rem 0 1.5rem;max-width:642px}
figure img{max-width:100%;height:auto;border:1px solid #ddd}
figcaption{font-size:.9rem;margin-top:.3rem}.note{color:#b00000;font-style:italic}
p.rows{font-size:.85rem;color:#555})";

struct FolderContents {
  std::vector<fs::path> tables;   // relative to the results folder
  std::vector<fs::path> figures;  // their .svg files, relative to the results folder
  bool has_results = false;
  std::size_t run_files = 0;
};

// Where a table or figure stands on the page, in the order a reader wants them: the summary and the
// reproduction's own tables, then accuracy per session, then the costs, then the rest, with the
// long tidy tables last.
int reading_rank(const fs::path& file) {
  const std::string stem = file.stem().string();
  if (file.extension() != ".svg") {
    if (stem == "summary") return 0;
    if (stem == "costs") return 20;
    if (stem == "sessions" || stem == "context_analysis") return 40;
    return 1;
  }
  if (stem.rfind("sessions_", 0) == 0) {
    int suffix = 0;
    for (const char* metric : {"_all", "_base", "_novel", "_harmonic"}) {
      const std::string ending = metric;
      if (stem.size() >= ending.size() && stem.compare(stem.size() - ending.size(), ending.size(), ending) == 0) {
        return 10 + suffix;
      }
      ++suffix;
    }
    return 14;
  }
  if (stem.rfind("efficiency_", 0) == 0) return 21;
  return 30;
}

// "shot-5" before "shot-10": runs of digits compare as numbers, the rest byte by byte.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  const auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      std::size_t i_end = i, j_end = j;
      while (i_end < a.size() && digit(a[i_end])) ++i_end;
      while (j_end < b.size() && digit(b[j_end])) ++j_end;
      const std::string x = a.substr(i, i_end - i), y = b.substr(j, j_end - j);
      const std::string x_trimmed = x.substr(std::min(x.find_first_not_of('0'), x.size() - 1));
      const std::string y_trimmed = y.substr(std::min(y.find_first_not_of('0'), y.size() - 1));
      if (x_trimmed.size() != y_trimmed.size()) return x_trimmed.size() < y_trimmed.size();
      if (x_trimmed != y_trimmed) return x_trimmed < y_trimmed;
      if (x != y) return x < y;
      i = i_end;
      j = j_end;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

struct NaturalOrder {
  bool operator()(const std::string& a, const std::string& b) const { return natural_less(a, b); }
};

using Folders = std::map<std::string, FolderContents, NaturalOrder>;  // key: folder relative to the top, "" for it

bool is_table_file(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".csv" || extension == ".tex" || extension == ".md";
}

std::size_t json_files_in(const fs::path& folder) {
  std::size_t count = 0;
  std::error_code error;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    if (it->path().extension() == ".json" && it->is_regular_file(error)) ++count;
  }
  return count;
}

// The folder as it will be once `pending` (files about to be written, or none) replaces its files.
struct PageSource {
  fs::path root;
  const FileBatch* pending = nullptr;

  const std::string* pending_text(const fs::path& relative) const {
    return pending == nullptr ? nullptr : pending->find(root / relative);
  }
  std::string text(const fs::path& relative) const {
    if (const std::string* text = pending_text(relative)) return *text;
    return read_text_file(root / relative);
  }
  bool has_file(const fs::path& relative) const {
    std::error_code error;
    return pending_text(relative) != nullptr || fs::is_regular_file(root / relative, error);
  }
};

// Files the page shows: a figure's .svg under figures/, or a table file.
void add_shown_file(Folders& folders, const fs::path& relative) {
  const fs::path parent = relative.parent_path();
  if (parent.filename() == "figures") {
    if (relative.extension() == ".svg") folders[parent.parent_path().generic_string()].figures.push_back(relative);
  } else if (is_table_file(relative)) {
    folders[parent.generic_string()].tables.push_back(relative);
  }
}

// A folder the page leaves out: a run's own (results/ is counted, not listed; checkpoints/) or hidden.
bool is_left_out_folder(const std::string& name) {
  return name == "checkpoints" || name == "results" || name.front() == '.';
}

// A pending file the listing below would show: inside the root, in no folder the page leaves out.
bool is_listed(const fs::path& relative) {
  if (relative.empty() || relative.is_absolute()) return false;
  for (const fs::path& part : relative) {
    const std::string name = part.string();
    if (name.empty() || name == ".." || is_left_out_folder(name)) return false;
  }
  return true;
}

void add_files_on_disk(Folders& folders, const fs::path& root) {
  std::error_code error;
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, error), end;
  for (; !error && it != end; it.increment(error)) {
    const fs::path relative = it->path().lexically_relative(root);
    const std::string name = relative.filename().string();
    const fs::path parent = relative.parent_path();
    std::error_code kind_error;
    const bool directory = it->is_directory(kind_error);
    if (directory && is_left_out_folder(name)) {
      it.disable_recursion_pending();
      if (name == "results") {
        FolderContents& contents = folders[parent.generic_string()];
        contents.has_results = true;
        contents.run_files = json_files_in(it->path());
      }
      continue;
    }
    if (directory || name.front() == '.' || !it->is_regular_file(kind_error)) continue;
    add_shown_file(folders, relative);
  }
  if (error) throw ReportError(fmt::format("{}: cannot list ({})", root.string(), error.message()));
}

Folders folder_contents(const PageSource& source) {
  const fs::path& root = source.root;
  std::error_code exists_error;
  const bool to_be_created = source.pending != nullptr && !fs::exists(fs::symlink_status(root, exists_error));
  if (const std::string why = why_not_a_folder(root); !why.empty() && !to_be_created) {
    throw ReportError(fmt::format("{}: {} (expected a results folder)", root.string(), why));
  }
  Folders folders;
  if (!to_be_created) add_files_on_disk(folders, root);
  if (source.pending != nullptr) {
    const fs::path normal_root = root.lexically_normal();
    for (const auto& [path, content] : source.pending->files()) {  // by normal path
      const fs::path relative = path.lexically_relative(normal_root);
      std::error_code on_disk_error;
      if (is_listed(relative) && !fs::exists(path, on_disk_error)) add_shown_file(folders, relative);
    }
  }
  const auto in_reading_order = [](const fs::path& a, const fs::path& b) {
    if (reading_rank(a) != reading_rank(b)) return reading_rank(a) < reading_rank(b);
    return natural_less(a.generic_string(), b.generic_string());
  };
  for (auto& [folder, contents] : folders) {
    std::sort(contents.tables.begin(), contents.tables.end(), in_reading_order);
    std::sort(contents.figures.begin(), contents.figures.end(), in_reading_order);
  }
  return folders;
}

// A relative path as a URL: every byte but letters, digits, '-', '.', '_', '~' and '/' percent-encoded.
std::string href(const fs::path& relative, bool folder = false) {
  std::string out;
  for (const char c : relative.generic_string()) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += c;
    } else {
      out += fmt::format("%{:02X}", byte);
    }
  }
  return folder ? out + "/" : out;
}

std::string link(const fs::path& relative, const std::string& text, bool folder = false) {
  return fmt::format("<a href=\"{}\">{}</a>", href(relative, folder), xml_text(text));
}

// The text of the first <NAME> element of an SVG render_svg wrote, its entities decoded; empty
// when there is none.
std::string svg_element_text(const std::string& svg, const std::string& name) {
  const std::string open = "<" + name + ">", close = "</" + name + ">";
  const std::size_t begin = svg.find(open);
  if (begin == std::string::npos) return "";
  const std::size_t end = svg.find(close, begin);
  if (end == std::string::npos) return "";
  const std::string text = svg.substr(begin + open.size(), end - begin - open.size());
  static const std::vector<std::pair<std::string, std::string>> entities = {
      {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&#39;", "'"}, {"&amp;", "&"}};
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const auto entity = std::find_if(entities.begin(), entities.end(),
                                     [&](const auto& pair) { return text.compare(i, pair.first.size(), pair.first) == 0; });
    if (entity != entities.end()) {
      out += entity->second;
      i += entity->first.size();
    } else {
      out += text[i++];
    }
  }
  return out;
}

bool is_number(const std::string& text) { return parse_finite_number(text).has_value(); }

std::string inline_table(const PageSource& source, const fs::path& relative) {
  std::vector<std::string> lines = csv_lines(source.text(relative));
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  std::string out = fmt::format("<h3>{}</h3>\n", link(relative, relative.generic_string()));
  if (lines.empty()) return out + "<p class=\"rows\">(empty)</p>\n";
  out += "<div class=\"table\"><table>\n<thead><tr>";
  for (const auto& field : csv_fields(lines.front())) out += fmt::format("<th>{}</th>", xml_text(field));
  out += "</tr></thead>\n<tbody>\n";
  const std::size_t rows = std::min(lines.size() - 1, max_inline_rows);
  for (std::size_t row = 1; row <= rows; ++row) {
    out += "<tr>";
    for (const auto& field : csv_fields(lines[row])) {
      out += fmt::format("<td{}>{}</td>", is_number(field) ? " class=\"number\"" : "", xml_text(field));
    }
    out += "</tr>\n";
  }
  out += "</tbody>\n</table></div>\n";
  if (rows < lines.size() - 1) {
    out += fmt::format("<p class=\"rows\">The first {} of {} rows; the file has them all.</p>\n", rows, lines.size() - 1);
  }
  return out;
}

std::string figure_entry(const PageSource& source, const fs::path& svg) {
  const std::string text = source.text(svg);
  const std::string stem = svg.stem().string();
  std::string title = svg_element_text(text, "title");
  if (title.empty()) title = stem;
  const std::string note = svg_element_text(text, "desc");
  std::string out = fmt::format("<figure id=\"{}\">\n<img src=\"{}\" alt=\"{}\">\n<figcaption><strong>{}</strong>",
                                xml_text("figure-" + svg.generic_string()), href(svg), xml_text(title), xml_text(title));
  if (!note.empty()) out += fmt::format(" <span class=\"note\">({})</span>", xml_text(note));
  out += fmt::format("<br><code>{}</code>", xml_text(svg.generic_string()));
  for (const auto& [extension, what] : {std::pair<const char*, const char*>{".tex", "pgfplots (.tex)"}, {".csv", "data (.csv)"}}) {
    const fs::path sibling = fs::path(svg).replace_extension(extension);
    if (source.has_file(sibling)) out += " &middot; " + link(sibling, what);
  }
  return out + "</figcaption>\n</figure>\n";
}

std::string folder_section(const PageSource& source, const std::string& folder, const FolderContents& contents,
                           std::size_t index) {
  std::string out = fmt::format("<section id=\"folder-{}\">\n<h2>{}</h2>\n", index,
                                folder.empty() ? std::string("This folder") : fmt::format("<code>{}/</code>", xml_text(folder)));
  if (!contents.tables.empty()) {
    out += "<h3>Tables</h3>\n<ul class=\"files\">\n";
    for (const auto& table : contents.tables) {
      out += fmt::format("<li>{}</li>\n", link(table, table.lexically_relative(folder).generic_string()));
    }
    out += "</ul>\n";
  }
  if (contents.has_results) {
    const fs::path results = fs::path(folder) / "results";
    out += fmt::format("<p>{}: {} run result file{} (JSON), from which every table is rebuilt.</p>\n",
                       link(results.lexically_normal(), "results/", true), contents.run_files,
                       contents.run_files == 1 ? "" : "s");
  }
  // The folder's own tables inline (a sweep cell's are linked above), with the figures between them
  // in reading order; neighbouring figures share one row.
  std::vector<fs::path> shown;
  if (folder.empty()) {
    for (const auto& table : contents.tables) {
      if (table.extension() == ".csv") shown.push_back(table);
    }
  }
  shown.insert(shown.end(), contents.figures.begin(), contents.figures.end());
  std::stable_sort(shown.begin(), shown.end(),
                   [](const fs::path& a, const fs::path& b) { return reading_rank(a) < reading_rank(b); });
  bool in_figures = false;
  for (const auto& item : shown) {
    const bool figure = item.extension() == ".svg";
    if (figure && !in_figures) out += "<div class=\"figures\">\n";
    if (!figure && in_figures) out += "</div>\n";
    in_figures = figure;
    out += figure ? figure_entry(source, item) : inline_table(source, item);
  }
  if (in_figures) out += "</div>\n";
  return out + "</section>\n";
}

std::string folder_title(const fs::path& root) {
  fs::path path = fs::absolute(root).lexically_normal();  // "." names the current folder
  if (!path.has_filename()) path = path.parent_path();
  return path.filename().string();
}

}  // namespace

std::string render_report_page(const fs::path& results_folder, const FileBatch* pending) {
  // "runs/paper/" names the folder "runs/paper" does; without the empty last element paths relate.
  const fs::path root = results_folder.has_filename() ? results_folder : results_folder.parent_path();
  const PageSource source{root, pending};
  const Folders folders = folder_contents(source);
  const std::string title = fmt::format("fscil-bench report: {}", folder_title(root));
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                    "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += fmt::format("<title>{0}</title>\n<style>\n{1}\n</style>\n</head>\n<body>\n<h1>{0}</h1>\n", xml_text(title),
                     page_style);
  out += "<p>Tables and figures of this results folder. Each figure's data is in its .csv, its LaTeX (pgfplots) "
         "in its .tex.</p>\n";
  std::vector<std::pair<std::string, const FolderContents*>> shown;
  for (const auto& [folder, contents] : folders) {
    if (!contents.tables.empty() || !contents.figures.empty() || contents.has_results) shown.emplace_back(folder, &contents);
  }
  if (shown.empty()) out += "<p>No tables or figures in this folder yet.</p>\n";
  if (shown.size() > 1) {
    out += "<nav><ul>\n";
    for (std::size_t i = 0; i < shown.size(); ++i) {
      const std::string name = shown[i].first.empty() ? std::string("This folder") : shown[i].first + "/";
      out += fmt::format("<li><a href=\"#folder-{}\">{}</a></li>\n", i, xml_text(name));
    }
    out += "</ul></nav>\n";
  }
  for (std::size_t i = 0; i < shown.size(); ++i) {
    out += folder_section(source, shown[i].first, *shown[i].second, i);
  }
  return out + "</body>\n</html>\n";
}

void add_report_page(FileBatch& files, const fs::path& results_folder) {
  std::string page = render_report_page(results_folder, &files);
  files.add(results_folder / "index.html", std::move(page));
}

void write_report_page(const fs::path& results_folder) {
  write_file_atomically(results_folder / "index.html", render_report_page(results_folder));
}

}  // namespace fscil
