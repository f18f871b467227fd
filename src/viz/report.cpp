#include "viz/report.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>
#include <tuple>
#include <vector>

#include "eval/records.hpp"
#include "io/image_codec.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::string Format(const char* format, ...) {
  char buffer[256];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  return buffer;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A shared page must carry only the results, never the files of whoever makes it: the page reads a
// file of the folder only when it is a regular file reached without a symbolic link.
bool IsPlainFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(fs::symlink_status(path, ec));
}

// Throws InputError naming `path` when it exists but is a link or not a regular file; returns
// whether it exists.
bool RequirePlainFileIfPresent(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);
  if (!fs::exists(status)) return false;
  if (!fs::is_regular_file(status)) {
    throw MakeInputError(
        path.string(),
        std::string(fs::is_symlink(status) ? "is a symbolic link" : "is not a regular file") +
            "; the report reads only regular files inside the "
            "results folder");
  }
  return true;
}

// `root`/`relative` when every component of `relative` is a plain name (no "..", no absolute
// part) and every folder on the way is a real folder, not a link; "" otherwise.
std::string FolderInside(const fs::path& root, const std::string& relative) {
  const fs::path rel(relative);
  if (rel.empty() || rel.has_root_path()) return "";
  fs::path current = root;
  for (const fs::path& part : rel) {
    const std::string name = part.string();
    if (name.empty() || name == "." || name == "..") return "";
    current /= part;
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(current, ec))) return "";
  }
  return current.string();
}

// ---- tables ------------------------------------------------------------------------------------

struct Column {
  Column(std::string key_, std::string label_, bool numeric_, std::string td_class_ = "")
      : key(std::move(key_)),
        label(std::move(label_)),
        numeric(numeric_),
        td_class(std::move(td_class_)) {}
  std::string key;       // for report.html#sort=<key>
  std::string label;     // header text
  bool numeric = false;  // sorted as numbers, right-aligned
  std::string td_class;  // extra class of the column's cells (e.g. "wide" for long text)
};

struct Cell {
  std::string html;        // what is shown (already escaped)
  std::string sort_value;  // numeric columns: a number, or "" for "no value" (sorted last)
};

Cell Text(const std::string& text) { return {HtmlEscape(text), text}; }
Cell Html(const std::string& html, const std::string& sort_value) { return {html, sort_value}; }
Cell Number(double value, const char* format) {
  return {Format(format, value), Format("%.9g", value)};
}
Cell Count(long long n) { return {std::to_string(n), std::to_string(n)}; }
Cell Missing() { return {"&ndash;", ""}; }

// A table whose headers sort the rows when clicked (the script at the end of the page).
std::string SortableTable(const std::string& id, const std::vector<Column>& columns,
                          const std::vector<std::vector<Cell>>& rows) {
  std::ostringstream h;
  h << "<table class=\"sortable\"" << (id.empty() ? "" : " id=\"" + id + "\"") << "><thead><tr>";
  for (const Column& c : columns) {
    h << "<th data-key=\"" << HtmlEscape(c.key) << "\" data-type=\"" << (c.numeric ? "num" : "text")
      << "\" title=\"click to sort\">" << HtmlEscape(c.label) << "</th>";
  }
  h << "</tr></thead><tbody>\n";
  for (const auto& row : rows) {
    h << "<tr>";
    for (size_t k = 0; k < row.size(); ++k) {
      const bool numeric = k < columns.size() && columns[k].numeric;
      std::string cls = numeric ? "num" : "";
      if (k < columns.size() && !columns[k].td_class.empty()) {
        cls += (cls.empty() ? "" : " ") + columns[k].td_class;
      }
      h << "<td" << (cls.empty() ? "" : " class=\"" + cls + "\"") << " data-value=\""
        << HtmlEscape(row[k].sort_value) << "\">" << row[k].html << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</tbody></table>\n";
  return h.str();
}

std::string KeyValueTable(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::ostringstream h;
  h << "<table class=\"kv\"><tbody>\n";
  for (const auto& [key, html] : rows) {
    h << "<tr><th>" << HtmlEscape(key) << "</th><td>" << html << "</td></tr>\n";
  }
  h << "</tbody></table>\n";
  return h.str();
}

// Escapes `text` and turns `code` spans into <code>, as summary.md writes them.
std::string InlineMarkdown(const std::string& text) {
  std::string escaped = HtmlEscape(text), out;
  bool in_code = false;
  for (char c : escaped) {
    if (c == '`') {
      out += in_code ? "</code>" : "<code>";
      in_code = !in_code;
    } else {
      out += c;
    }
  }
  if (in_code) out += "</code>";
  return out;
}

std::vector<std::string> SplitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (size_t i = 1; i < line.size(); ++i) {  // line[0] is the leading '|'
    if (line[i] == '|') {
      const size_t b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

// The markdown of summary.md as HTML: headings, tables (GitHub pipe tables) and paragraphs.
std::string MarkdownToHtml(const std::string& markdown) {
  std::ostringstream h;
  std::istringstream in(markdown);
  std::string line;
  std::vector<std::vector<std::string>> table;
  auto flush_table = [&]() {
    if (table.empty()) return;
    h << "<table class=\"summary\"><thead><tr>";
    for (const std::string& c : table[0]) h << "<th>" << InlineMarkdown(c) << "</th>";
    h << "</tr></thead><tbody>\n";
    for (size_t r = 1; r < table.size(); ++r) {
      h << "<tr>";
      for (const std::string& c : table[r]) h << "<td>" << InlineMarkdown(c) << "</td>";
      h << "</tr>\n";
    }
    h << "</tbody></table>\n";
    table.clear();
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '|') {
      if (line.find_first_not_of("|-: ") == std::string::npos) continue;  // |---|---|
      table.push_back(SplitRow(line));
      continue;
    }
    flush_table();
    if (line.empty()) continue;
    if (line[0] == '#') {
      // A line of '#' alone (or with spaces) is an empty heading.
      const size_t level = std::min<size_t>(std::min(line.find_first_not_of('#'), line.size()), 3);
      const std::string tag = "h" + std::to_string(level + 2);  // under the page's own h1/h2
      const size_t text = std::min(line.find_first_not_of("# "), line.size());
      h << "<" << tag << ">" << InlineMarkdown(line.substr(text)) << "</" << tag << ">\n";
    } else {
      h << "<p>" << InlineMarkdown(line) << "</p>\n";
    }
  }
  flush_table();
  return h.str();
}

// ---- pictures ----------------------------------------------------------------------------------

struct Picture {
  std::string kind;     // "objects", "correspondences", "registered", "verification"
  int view = 0;         // source view
  int target_view = 0;  // target view (differs from `view` only for cross-view correspondences)
  std::string path;
};

// The pictures WriteRegistrationPictures writes, in view order and then in the order above.
std::vector<Picture> FindPictures(const std::string& dir) {
  std::vector<Picture> found;
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(fs::symlink_status(dir, ec))) return found;
  static const std::regex name_re(
      "(objects|correspondences|registered|verification|hypotheses|ambiguous|synthesized)-view([0-"
      "9]+)(?:-([0-9]+))?\\.("
      "png|jpg)");
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (!std::regex_match(name, m, name_re) || !IsPlainFile(entry.path())) continue;
    const int view = std::stoi(m[2]);
    found.push_back({m[1], view, m[3].matched ? std::stoi(m[3]) : view, entry.path().string()});
  }
  auto rank = [](const std::string& kind) {
    return kind == "objects"           ? 0
           : kind == "correspondences" ? 1
           : kind == "registered"      ? 2
           : kind == "verification"    ? 3
                                       : 4;
  };
  std::sort(found.begin(), found.end(), [&](const Picture& a, const Picture& b) {
    return std::make_tuple(a.view, rank(a.kind), a.target_view) <
           std::make_tuple(b.view, rank(b.kind), b.target_view);
  });
  return found;
}

std::string PictureCaption(const std::string& kind) {
  if (kind == "objects") return "matched objects (same colour = matched pair, grey = unmatched)";
  if (kind == "correspondences")
    return "point correspondences (RANSAC inliers green, outliers red)";
  if (kind == "verification") {
    return "geometric check in the target view (green: surfaces agree, red: source in the target "
           "camera's free space, yellow: hidden behind)";
  }
  if (kind == "ambiguous") {
    return "two poses fit these scans (ambiguous): the registered clouds under each, the reported "
           "one first (target blue, source orange)";
  }
  if (kind == "synthesized") {
    return "view synthesis: the source image beside the target rendered from the virtual camera "
           "whose matches registered it (inliers green, outliers red)";
  }
  if (kind == "hypotheses") {
    return "the candidate transforms the check judged: the chosen one first, then the runners-up "
           "by score (registered clouds, target blue, source orange)";
  }
  return "registered clouds in the target view (target blue, source orange)";
}

// Figures for `pictures`, grouped by view pair; counts the embedded images in `*embedded`.
std::string PicturesHtml(const std::vector<Picture>& pictures, const ReportConfig& config,
                         int* embedded) {
  std::ostringstream h;
  int current_view = -1;
  for (const Picture& p : pictures) {
    if (p.view != current_view) {
      if (current_view >= 0) h << "</div>\n";
      current_view = p.view;
      h << "<h4>view pair " << p.view << "</h4>\n<div class=\"pictures\">\n";
    }
    const std::string uri = ImageDataUri(p.path, config);
    const std::string caption = PictureCaption(p.kind);
    h << "<figure>";
    if (uri.empty()) {
      h << "<p class=\"bad\">" << HtmlEscape(fs::path(p.path).filename().string())
        << " could not be read as an image</p>";
    } else {
      h << "<img src=\"" << uri << "\" alt=\""
        << HtmlEscape(p.kind + " view " + std::to_string(p.view)) << "\">";
      ++*embedded;
    }
    h << "<figcaption>" << HtmlEscape(caption) << " &mdash; "
      << HtmlEscape(fs::path(p.path).filename().string()) << "</figcaption></figure>\n";
  }
  if (current_view >= 0) h << "</div>\n";
  return h.str();
}

// ---- page --------------------------------------------------------------------------------------

const char* kStyle = R"(
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif;
       color: #222; background: #fff; margin: 0 auto; padding: 1em 2em 4em; max-width: 1500px; }
h1 { font-size: 1.6em; margin-bottom: .2em; }
h2 { font-size: 1.3em; margin-top: 2em; border-bottom: 1px solid #ccc; padding-bottom: .2em; }
h3 { font-size: 1.1em; margin-top: 1.6em; }
h4 { font-size: 1em; margin: 1em 0 .4em; color: #555; }
.meta, .note { color: #555; }
.note { background: #f6f6f0; border-left: 4px solid #c8b560; padding: .5em .8em; }
code, pre { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: .9em; }
pre { background: #f5f5f5; padding: .8em; overflow-x: auto; }
table { border-collapse: collapse; margin: .6em 0 1.2em; }
th, td { border: 1px solid #d0d0d0; padding: .25em .6em; text-align: left; vertical-align: top; }
thead th { background: #eef1f5; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.kv th { background: #f5f5f5; font-weight: 600; }
table.sortable thead th { cursor: pointer; user-select: none; white-space: nowrap; }
table.sortable thead th:hover { background: #dde4ee; }
table.sortable thead th[aria-sort=ascending]::after { content: " \25B2"; }
table.sortable thead th[aria-sort=descending]::after { content: " \25BC"; }
table.sortable tbody tr:nth-child(even) { background: #fafafa; }
td.wide { min-width: 16em; max-width: 32em; }
td.nowrap { white-space: nowrap; }
.ok { color: #17702a; font-weight: 600; }
.bad { color: #b3261e; font-weight: 600; }
.pictures { display: flex; flex-wrap: wrap; gap: 1em; }
figure { margin: 0; max-width: 100%; }
figure img { max-width: 100%; height: auto; border: 1px solid #ccc; display: block; }
figcaption { font-size: .85em; color: #555; margin-top: .2em; }
.swatch { display: inline-block; width: .9em; height: .9em; vertical-align: middle;
          border: 1px solid #888; margin-right: .3em; }
)";

// Click a header to sort by it (again to reverse); numbers sort numerically and empty values go
// last either way; ties keep their current order. report.html#sort=<column key>[:desc] sorts the
// pairs table when the page opens.
const char* kScript = R"(
(function () {
  function value(cell, numeric) {
    var v = cell.getAttribute('data-value');
    if (v === null) v = cell.textContent;
    if (!numeric) return v.toLowerCase();
    var x = parseFloat(v);
    return isNaN(x) ? null : x;
  }
  function sortTable(table, col, descending) {
    var head = table.tHead.rows[0].cells;
    var numeric = head[col].getAttribute('data-type') === 'num';
    var body = table.tBodies[0];
    var rows = Array.prototype.slice.call(body.rows);
    var order = new Map();
    rows.forEach(function (r, i) { order.set(r, i); });
    rows.sort(function (a, b) {
      var x = value(a.cells[col], numeric), y = value(b.cells[col], numeric);
      if (x === null || y === null) {
        if (x === y) return order.get(a) - order.get(b);
        return x === null ? 1 : -1;
      }
      var c = x < y ? -1 : (x > y ? 1 : 0);
      if (descending) c = -c;
      return c !== 0 ? c : order.get(a) - order.get(b);
    });
    rows.forEach(function (r) { body.appendChild(r); });
    for (var k = 0; k < head.length; ++k) head[k].removeAttribute('aria-sort');
    head[col].setAttribute('aria-sort', descending ? 'descending' : 'ascending');
  }
  document.querySelectorAll('table.sortable').forEach(function (table) {
    var head = table.tHead.rows[0].cells;
    Array.prototype.forEach.call(head, function (th, col) {
      th.tabIndex = 0;
      var toggle = function () {
        sortTable(table, col, th.getAttribute('aria-sort') === 'ascending');
      };
      th.addEventListener('click', toggle);
      th.addEventListener('keydown', function (e) { if (e.key === 'Enter') toggle(); });
    });
  });
  var m = /^#sort=([A-Za-z0-9_-]+)(:desc)?$/.exec(window.location.hash);
  var pairs = document.getElementById('pairs');
  if (m && pairs) {
    var head = pairs.tHead.rows[0].cells;
    for (var c = 0; c < head.length; ++c) {
      if (head[c].getAttribute('data-key') === m[1]) sortTable(pairs, c, !!m[2]);
    }
  }
})();
)";

std::string PageStart(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         HtmlEscape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
         HtmlEscape(title) + "</h1>\n";
}

std::string PageEnd() {
  return std::string("<script>") + kScript + "</script>\n</body>\n</html>\n";
}

std::string Verdict(bool valid) {
  return valid ? "<span class=\"ok\">valid</span>" : "<span class=\"bad\">failed</span>";
}

std::string Swatch(int r, int g, int b) {
  return Format("<span class=\"swatch\" style=\"background: rgb(%d, %d, %d)\"></span>", r, g, b);
}

// The vertex count of a PLY header, or -1.
long long PlyVertexCount(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 40 && std::getline(in, line); ++i) {
    if (line.rfind("element vertex ", 0) == 0) return std::atoll(line.c_str() + 15);
    if (line.rfind("end_header", 0) == 0) break;
  }
  return -1;
}

std::string MatrixHtml(const json& T) {
  std::ostringstream h;
  h << "<table class=\"matrix\"><tbody>";
  if (T.is_array()) {
    for (const json& row : T) {
      h << "<tr>";
      if (row.is_array()) {
        for (const json& v : row) {
          h << "<td class=\"num\">" << (v.is_number() ? Format("%.6f", v.get<double>()) : "?")
            << "</td>";
        }
      }
      h << "</tr>";
    }
  }
  h << "</tbody></table>\n";
  return h.str();
}

double NumberOr(const json& j, const char* key, double fallback) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

std::string StringOr(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

// ---- register folder ---------------------------------------------------------------------------

std::string RegisterReport(const std::string& dir, const ReportConfig& config) {
  const std::string path = (fs::path(dir) / "result.json").string();
  RequirePlainFileIfPresent(path);
  const json doc =
      detail::ReadJsonFile(path, "result.json of a `zeroreg register --out-dir` folder");
  if (!doc.is_object() || !doc.contains("result") || !doc["result"].is_object()) {
    throw MakeInputError(path,
                         "has no \"result\" object; expected the result.json written by "
                         "`zeroreg register --out-dir`");
  }
  const json& r = doc["result"];
  const json counts = r.value("counts", json::object());
  const json gt = doc.value("ground_truth", json());
  const bool valid = r.value("valid", false);
  const std::string source = StringOr(doc, "source"), target = StringOr(doc, "target");

  const std::string title =
      config.title.empty() ? "zeroreg report: " + fs::path(dir).filename().string() : config.title;
  std::ostringstream h;
  h << PageStart(title);
  h << "<p class=\"meta\">A <code>zeroreg register</code> result: source <code>"
    << HtmlEscape(source) << "</code> registered onto target <code>" << HtmlEscape(target)
    << "</code>.</p>\n";

  // Summary.
  h << "<h2>Summary</h2>\n";
  std::vector<std::pair<std::string, std::string>> rows = {
      {"verdict", Verdict(valid)},
      {"reason", HtmlEscape(r.value("reason", ""))},
      {"path (correspondence source)", HtmlEscape(r.value("path", ""))}};
  if (gt.is_object()) {
    rows.push_back({"rotation error vs ground truth",
                    Format("%.3f deg", NumberOr(gt, "rotation_error_deg", 0))});
    rows.push_back({"translation error vs ground truth",
                    Format("%.2f cm", NumberOr(gt, "translation_error_cm", 0))});
    rows.push_back({"correspondences within 0.1 m under the ground truth",
                    Format("%.1f %%", 100 * NumberOr(gt, "correspondence_inlier_ratio", 0))});
  } else {
    rows.push_back({"ground truth", "not available (the scans have no poses and no --gt)"});
  }
  rows.push_back(
      {"keypoints source / target", Format("%.0f / %.0f", NumberOr(counts, "keypoints_source", 0),
                                           NumberOr(counts, "keypoints_target", 0))});
  rows.push_back({"correspondences", Format("%.0f", NumberOr(counts, "correspondences", 0))});
  rows.push_back({"RANSAC inliers", Format("%.0f (ratio %.3f)", NumberOr(counts, "inliers", 0),
                                           NumberOr(r, "inlier_ratio", 0))});
  rows.push_back({"inlier RMSE", Format("%.1f mm", 1000 * NumberOr(r, "inlier_rmse_m", 0))});
  rows.push_back(
      {"inlier spread (2nd axis)", Format("%.1f cm", 100 * NumberOr(r, "inlier_spread_m", 0))});
  rows.push_back({"RANSAC iterations", Format("%.0f", NumberOr(counts, "ransac_iterations", 0))});
  if (doc.contains("seed")) rows.push_back({"seed", HtmlEscape(detail::DumpJson(doc["seed"]))});
  h << KeyValueTable(rows);

  // The pair as a one-row table, shaped like an eval folder's pairs table.
  const json timings = r.value("timings_ms", json::object());
  std::vector<Column> columns = {{"source", "source", false},
                                 {"target", "target", false},
                                 {"verdict", "verdict", false},
                                 {"path", "path", false},
                                 {"rotation_error", "RE (deg)", true},
                                 {"translation_error", "TE (cm)", true},
                                 {"correspondences", "correspondences", true},
                                 {"inliers", "inliers", true},
                                 {"inlier_ratio", "inlier ratio", true},
                                 {"time", "time (s)", true}};
  std::vector<Cell> row = {Text(source), Text(target),
                           Html(Verdict(valid), valid ? "valid" : "failed"),
                           Text(r.value("path", ""))};
  if (gt.is_object()) {
    row.push_back(Number(NumberOr(gt, "rotation_error_deg", 0), "%.3f"));
    row.push_back(Number(NumberOr(gt, "translation_error_cm", 0), "%.2f"));
  } else {
    row.push_back(Missing());
    row.push_back(Missing());
  }
  row.push_back(Count(static_cast<long long>(NumberOr(counts, "correspondences", 0))));
  row.push_back(Count(static_cast<long long>(NumberOr(counts, "inliers", 0))));
  row.push_back(Number(NumberOr(r, "inlier_ratio", 0), "%.3f"));
  if (timings.contains("total") && timings["total"].is_number()) {
    row.push_back(Number(timings["total"].get<double>() / 1000, "%.2f"));
  } else {
    row.push_back(Missing());
  }
  h << "<h2>Pairs</h2>\n" << SortableTable("pairs", columns, {row});

  h << "<h3>Estimated T_target_source</h3>\n" << MatrixHtml(r.value("T_target_source", json()));
  if (gt.is_object() && gt.contains("T_target_source")) {
    h << "<h3>Ground-truth T_target_source</h3>\n" << MatrixHtml(gt["T_target_source"]);
  }

  // Every pose that fits an ambiguous pair.
  const json alternatives = r.value("alternatives", json::array());
  if (alternatives.is_array() && !alternatives.empty()) {
    h << "<h2>"
      << (r.value("ambiguous", false) ? "Ambiguous: these poses fit the scans"
                                      : "Other poses that fit, outside the motion prior")
      << "</h2>\n";
    std::vector<std::vector<Cell>> alternative_rows;
    for (const json& a : alternatives) {
      if (!a.is_object()) continue;
      alternative_rows.push_back(
          {Text(StringOr(a, "name")), Number(NumberOr(a, "score", 0), "%.3f"),
           Number(NumberOr(a, "overlap", 0), "%.3f"), Number(NumberOr(a, "violation", 0), "%.3f"),
           Number(NumberOr(a, "apart_m", 0), "%.3f"),
           Text(a.value("outside_prior", false) ? "yes" : "no")});
    }
    h << SortableTable("alternatives",
                       {{"name", "pose", false},
                        {"score", "score", true},
                        {"overlap", "overlap", true},
                        {"violation", "free-space violations", true},
                        {"apart", "apart (m RMS)", true},
                        {"prior", "outside the prior", false}},
                       alternative_rows);
  }

  // Objects (paper §3.2-3.3).
  if (r.contains("objects") && r["objects"].is_object()) {
    const json& objects = r["objects"];
    const json source_objects = objects.value("source", json::array());
    const json target_objects = objects.value("target", json::array());
    h << "<h2>Objects</h2>\n<p>" << source_objects.size() << " objects in the source, "
      << target_objects.size() << " in the target, "
      << objects.value("matches", json::array()).size()
      << " matched pairs (graph matching, Eq. 2).</p>\n";
    std::vector<std::vector<Cell>> match_rows;
    for (const json& m : objects.value("matches", json::array())) {
      match_rows.push_back({Text(StringOr(m, "source_label")), Text(StringOr(m, "target_label")),
                            Number(NumberOr(m, "node_similarity", 0), "%.3f"),
                            Count(static_cast<long long>(NumberOr(m, "correspondences", 0)))});
    }
    if (!match_rows.empty()) {
      h << SortableTable("matches",
                         {{"source_label", "source object", false},
                          {"target_label", "target object", false},
                          {"similarity", "node similarity C", true},
                          {"correspondences", "point correspondences", true}},
                         match_rows);
    }
  }

  // Pictures.
  const std::vector<Picture> pictures = FindPictures(FolderInside(dir, "pictures"));
  h << "<h2>Pictures</h2>\n";
  int embedded = 0;
  if (pictures.empty()) {
    h << "<p class=\"note\">No pictures in <code>pictures/</code> (written by <code>zeroreg "
         "register --out-dir</code> or <code>--viz</code>).</p>\n";
  } else {
    h << PicturesHtml(pictures, config, &embedded);
  }

  // Clouds.
  h << "<h2>Registered clouds (PLY)</h2>\n";
  std::vector<std::pair<std::string, std::string>> ply_rows;
  const std::vector<std::pair<std::string, std::string>> ply_files = {
      {"registered.ply", Swatch(30, 120, 200) + "target (blue) and " + Swatch(250, 140, 30) +
                             "source moved by T_target_source (orange), in the target frame"},
      {"source.ply", "source in its own frame, own colours"},
      {"target.ply", "target in its own frame, own colours"}};
  for (const auto& [name, what] : ply_files) {
    const std::string ply = (fs::path(dir) / name).string();
    if (!IsPlainFile(ply)) continue;
    ply_rows.push_back({name, what + Format(" &mdash; %lld points", PlyVertexCount(ply))});
  }
  if (ply_rows.empty()) {
    h << "<p class=\"note\">No PLY files in the folder (<code>zeroreg register --out-dir</code> "
         "writes them).</p>\n";
  } else {
    h << "<p>Open them in MeshLab, CloudCompare or Open3D, from the results folder.</p>\n"
      << KeyValueTable(ply_rows);
  }

  // Timings and config.
  if (timings.is_object() && !timings.empty()) {
    std::vector<std::vector<Cell>> timing_rows;
    for (const auto& [stage, ms] : timings.items()) {
      timing_rows.push_back({Text(stage), Number(ms.is_number() ? ms.get<double>() : 0, "%.0f")});
    }
    h << "<h2>Timings</h2>\n"
      << SortableTable("timings", {{"stage", "stage", false}, {"ms", "ms", true}}, timing_rows);
  }
  if (doc.contains("config")) {
    h << "<h2>Config</h2>\n<details><summary>effective pipeline config (JSON)</summary><pre>"
      << HtmlEscape(detail::DumpJson(doc["config"], 2)) << "</pre></details>\n";
  }
  h << PageEnd();
  return h.str();
}

// ---- eval folder -------------------------------------------------------------------------------

std::string EvalReport(const std::string& dir, const ReportConfig& config) {
  const fs::path root(dir);
  json summary = json::object();
  if (RequirePlainFileIfPresent(root / "summary.json"))
    summary =
        detail::ReadJsonFile((root / "summary.json").string(), "summary.json of a results folder");
  RequirePlainFileIfPresent(root / "pairs.jsonl");
  RequirePlainFileIfPresent(root / "summary.md");
  const std::vector<PairRecord> records = ReadPairsJsonl((root / "pairs.jsonl").string());
  const std::string protocol = StringOr(summary, "protocol");
  const std::string method = StringOr(summary, "method");

  const std::string title =
      config.title.empty() ? "zeroreg report: " + root.filename().string() : config.title;
  std::ostringstream h;
  h << PageStart(title);
  h << "<p class=\"meta\">A <code>zeroreg eval</code> results folder";
  if (!protocol.empty()) h << ": protocol <code>" << HtmlEscape(protocol) << "</code>";
  if (!method.empty()) h << ", method <code>" << HtmlEscape(method) << "</code>";
  if (summary.contains("shard")) h << ", shard " << HtmlEscape(StringOr(summary, "shard"));
  h << ", " << records.size() << " pairs in pairs.jsonl.</p>\n";

  h << "<h2>Summary</h2>\n";
  const std::string md = ReadBytes((root / "summary.md").string());
  if (!md.empty()) {
    h << MarkdownToHtml(md);
  } else if (summary.contains("benchmarks")) {
    h << "<p class=\"note\">No summary.md; the benchmarks of summary.json follow.</p>\n<pre>"
      << HtmlEscape(detail::DumpJson(summary["benchmarks"], 2)) << "</pre>\n";
  } else {
    h << "<p class=\"note\">No summary.md or summary.json in the folder (run <code>zeroreg "
         "eval</code> to completion, or <code>zeroreg eval merge</code>).</p>\n";
  }

  // Which pairs have pictures, and the pairs table.
  bool any_recall = false;
  for (const PairRecord& p : records) any_recall = any_recall || p.recall_error.has_value();
  std::vector<std::string> picture_dirs(records.size());
  int with_pictures = 0, skipped_pictures = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const PairRecord& p = records[i];
    // `benchmark` and `scene` come from pairs.jsonl: a "../" in them must not reach outside.
    const std::string folder =
        FolderInside(root, PairPictureFolder(p.benchmark, p.scene, p.target_id, p.source_id));
    if (FindPictures(folder).empty()) continue;
    if (config.max_pairs_with_pictures >= 0 && with_pictures >= config.max_pairs_with_pictures) {
      ++skipped_pictures;
      continue;
    }
    picture_dirs[i] = folder;
    ++with_pictures;
  }

  std::vector<Column> columns = {{"index", "#", true},
                                 {"benchmark", "benchmark / scene", false, "nowrap"},
                                 {"target", "target i", true},
                                 {"source", "source j", true},
                                 {"verdict", "verdict", false}};
  if (any_recall) {
    columns.push_back({"registered", "registered (E <= 0.04)", false});
    columns.push_back({"recall_error", "E (m^2)", true});
  }
  for (const Column& c : std::vector<Column>{{"rotation_error", "RE (deg)", true},
                                             {"translation_error", "TE (cm)", true},
                                             {"gt_inlier_ratio", "IR under GT (%)", true},
                                             {"correspondences", "correspondences", true},
                                             {"inliers", "inliers", true},
                                             {"time", "time (s)", true},
                                             {"reason", "reason / error", false, "wide"},
                                             {"pictures", "pictures", false}}) {
    columns.push_back(c);
  }
  std::vector<std::vector<Cell>> rows;
  for (size_t i = 0; i < records.size(); ++i) {
    const PairRecord& p = records[i];
    const bool failed_to_run = !p.error.empty();
    std::vector<Cell> row = {Count(static_cast<long long>(i)), Text(p.benchmark + " / " + p.scene),
                             Count(p.target_id), Count(p.source_id)};
    if (failed_to_run) {
      row.push_back(Html("<span class=\"bad\">error</span>", "error"));
    } else {
      row.push_back(Html(Verdict(p.valid), p.valid ? "valid" : "failed"));
    }
    if (any_recall && failed_to_run) {
      row.push_back(Missing());
      row.push_back(Missing());
    } else if (any_recall) {
      if (p.consecutive) {
        row.push_back(Text(std::string(p.registered ? "yes" : "no") + " (consecutive)"));
      } else {
        row.push_back(
            Html(p.registered ? "<span class=\"ok\">yes</span>" : "<span class=\"bad\">no</span>",
                 p.registered ? "yes" : "no"));
      }
      row.push_back(p.recall_error ? Number(*p.recall_error, "%.4f") : Missing());
    }
    if (failed_to_run) {
      for (int k = 0; k < 6; ++k) row.push_back(Missing());
    } else {
      row.push_back(Number(p.rotation_error_deg, "%.3f"));
      row.push_back(Number(p.translation_error_m * 100, "%.2f"));
      row.push_back(Number(p.inlier_ratio * 100, "%.1f"));
      row.push_back(Count(p.num_correspondences));
      row.push_back(Count(p.num_inliers));
      row.push_back(Number(p.time_ms / 1000, "%.2f"));
    }
    row.push_back(Text(failed_to_run ? p.error : p.reason));
    row.push_back(picture_dirs[i].empty()
                      ? Missing()
                      : Html("<a href=\"#pair-" + std::to_string(i) + "\">show</a>", "yes"));
    rows.push_back(row);
  }
  h << "<h2>Pairs</h2>\n<p>One row per pair of pairs.jsonl; click a column header to sort "
       "(again to reverse). RE / TE are against the ground truth, whatever the verdict.</p>\n"
    << SortableTable("pairs", columns, rows);

  h << "<h2>Pictures</h2>\n";
  int embedded = 0;
  if (with_pictures == 0 && skipped_pictures == 0) {
    h << "<p class=\"note\" id=\"no-pictures\">This results folder has no per-pair pictures "
         "(<code>&lt;results&gt;/pictures/&lt;benchmark&gt;/&lt;scene&gt;/&lt;i&gt;_&lt;j&gt;/"
         "</code>): <code>zeroreg eval</code> does not write them, so this page shows the "
         "tables only. To look at one pair, run <code>zeroreg register --out-dir</code> on it "
         "and make a report of that folder.</p>\n";
  } else {
    if (skipped_pictures > 0) {
      h << "<p class=\"note\">Pictures are shown for the first " << with_pictures << " pairs only; "
        << skipped_pictures << " more pairs have pictures in the folder.</p>\n";
    }
    for (size_t i = 0; i < records.size(); ++i) {
      if (picture_dirs[i].empty()) continue;
      const PairRecord& p = records[i];
      h << "<section id=\"pair-" << i << "\"><h3>#" << i << " " << HtmlEscape(p.key) << " &mdash; "
        << (p.error.empty() ? Verdict(p.valid) : "<span class=\"bad\">error</span>")
        << Format(", RE %.2f deg, TE %.1f cm", p.rotation_error_deg, p.translation_error_m * 100)
        << "</h3>\n"
        << PicturesHtml(FindPictures(picture_dirs[i]), config, &embedded) << "</section>\n";
    }
  }
  if (md.empty() && summary.contains("command")) {  // summary.md shows the command
    h << "<h2>Run</h2>\n<p>Command: <code>" << HtmlEscape(StringOr(summary, "command"))
      << "</code></p>\n";
  }
  if (summary.contains("settings")) {
    h << "<details><summary>settings (summary.json)</summary><pre>"
      << HtmlEscape(detail::DumpJson(summary["settings"], 2)) << "</pre></details>\n";
  }
  h << PageEnd();
  return h.str();
}

}  // namespace

std::string Base64Encode(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t n = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += kAlphabet[(n >> 6) & 63];
    out += kAlphabet[n & 63];
  }
  const size_t rest = bytes.size() - i;
  if (rest > 0) {
    uint32_t n = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) n |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += rest == 2 ? kAlphabet[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string ImageDataUri(const std::string& path, const ReportConfig& config) {
  const std::string bytes = ReadBytes(path);
  if (bytes.empty()) return "";
  cv::Mat image;
  try {
    image = detail::DecodeImage(std::vector<std::uint8_t>(bytes.begin(), bytes.end()),
                                detail::ImageMode::kColor);
  } catch (const std::exception&) {
    return "";  // not a picture the page can show
  }
  if (image.empty()) return "";
  const bool too_wide = config.max_image_width > 0 && image.cols > config.max_image_width;
  if (!too_wide && bytes.size() <= config.max_image_bytes) {
    const bool png = bytes.size() > 4 && bytes.compare(1, 3, "PNG") == 0;
    return std::string("data:image/") + (png ? "png" : "jpeg") + ";base64," + Base64Encode(bytes);
  }
  cv::Mat scaled = image;
  if (too_wide) {
    const double s = static_cast<double>(config.max_image_width) / image.cols;
    cv::resize(image, scaled, cv::Size(), s, s, cv::INTER_AREA);
  }
  std::vector<std::uint8_t> jpeg;
  try {
    jpeg = detail::EncodeJpeg(scaled, config.jpeg_quality);
  } catch (const std::exception&) {
    return "";
  }
  return "data:image/jpeg;base64," + Base64Encode(std::string(jpeg.begin(), jpeg.end()));
}

std::string PairPictureFolder(const std::string& benchmark, const std::string& scene, int target_id,
                              int source_id) {
  return "pictures/" + benchmark + "/" + scene + "/" + std::to_string(target_id) + "_" +
         std::to_string(source_id);
}

ResultsKind DetectResultsKind(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw MakeInputError(dir,
                         "is not a folder; expected a results folder of `zeroreg register "
                         "--out-dir` or `zeroreg eval`");
  }
  const fs::path root(dir);
  if (fs::exists(root / "result.json")) return ResultsKind::kRegister;
  if (fs::exists(root / "pairs.jsonl") || fs::exists(root / "summary.json")) {
    return ResultsKind::kEval;
  }
  throw MakeInputError(dir,
                       "holds neither result.json (a `zeroreg register --out-dir` folder) "
                       "nor pairs.jsonl / summary.json (a `zeroreg eval` folder)");
}

std::string BuildReportHtml(const std::string& dir, const ReportConfig& config) {
  const ResultsKind kind = DetectResultsKind(dir);
  try {
    return kind == ResultsKind::kRegister ? RegisterReport(dir, config) : EvalReport(dir, config);
  } catch (const json::exception& e) {
    // The pages read the files zeroreg wrote; a value of another type means the file was edited
    // or comes from another tool.
    throw MakeInputError(dir, std::string("a results file in this folder has a value of an "
                                          "unexpected type (edited by hand?): ") +
                                  e.what());
  }
}

void CheckReportOutput(const std::string& out_path) {
  std::error_code ec;
  const fs::file_status status = fs::status(out_path, ec);  // through links: what is written
  if (fs::is_directory(status)) {
    throw MakeInputError(out_path, "is a folder; expected the name of the HTML file to write");
  }
  if (!fs::is_regular_file(status)) return;  // new, or a device / FIFO written through
  // An existing file is replaced only when it is a page (an earlier report): --out naming
  // pairs.jsonl, summary.json or any other file would destroy it.
  std::ifstream in(out_path, std::ios::binary);
  std::string start(15, '\0');
  in.read(&start[0], static_cast<std::streamsize>(start.size()));
  start.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  if (fs::file_size(out_path, ec) > 0 && start != "<!DOCTYPE html>") {
    throw MakeInputError(out_path,
                         "exists and is not an HTML page (a results file?); the report replaces "
                         "only an earlier report: expected a new file name, e.g. report.html");
  }
}

void WriteReport(const std::string& dir, const std::string& out_path, const ReportConfig& config) {
  CheckReportOutput(out_path);  // before the page is built, which may take seconds
  const std::string html = BuildReportHtml(dir, config);
  // Through a temporary file and a rename: a full disk leaves the previous page whole.
  detail::WriteFileAtomically(out_path, html);
}

}  // namespace zeroreg
