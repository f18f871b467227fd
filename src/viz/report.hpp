// `zeroreg report`: one self-contained HTML page for a results folder (docs/REPORT.md).
//
// Two kinds of folder are recognised:
//   register  `zeroreg register --out-dir DIR`: DIR/result.json, DIR/pictures/*-view<i>.png and
//             DIR/{registered,source,target}.ply;
//   eval      `zeroreg eval ... --out DIR`: DIR/summary.json, DIR/summary.md, DIR/pairs.jsonl and,
//             when present, per-pair pictures in DIR/<PairPictureFolder(...)>.
// The page needs no network: CSS and the sorting script are inline and every picture is embedded
// as a base64 data URI (re-encoded as JPEG and downscaled when large, to keep the page small).
#pragma once

#include <string>

namespace zeroreg {

struct ReportConfig {
  // Pictures wider than this are downscaled (pixels) before embedding.
  int max_image_width = 1280;
  // A picture file larger than this (bytes), or one that had to be downscaled, is re-encoded as
  // JPEG at `jpeg_quality` (0-100); smaller ones are embedded as they are.
  size_t max_image_bytes = 200 * 1024;
  int jpeg_quality = 85;
  // Eval folders: embed pictures for at most this many pairs (in pairs.jsonl order; the page says
  // how many were left out). 0 = none, negative = all.
  int max_pairs_with_pictures = 200;
  std::string title;  // empty: "zeroreg report: <folder name>"
};

enum class ResultsKind { kRegister, kEval };

// Throws InputError naming `dir` when it is neither kind of folder.
ResultsKind DetectResultsKind(const std::string& dir);

// Where an eval run keeps the pictures of pair (target i, source j) of a benchmark/scene,
// relative to its results folder: "pictures/<benchmark>/<scene>/<i>_<j>". The files inside are
// named as WriteRegistrationPictures names them.
std::string PairPictureFolder(const std::string& benchmark, const std::string& scene, int target_id,
                              int source_id);

// The HTML page for `dir`. Throws InputError when a file of the folder is missing or malformed.
std::string BuildReportHtml(const std::string& dir, const ReportConfig& config = ReportConfig());

// Throws InputError naming `out_path` unless the page may be written there: a new file, an earlier
// page (a file starting with <!DOCTYPE html>), or a device / FIFO; never a folder or a results
// file.
void CheckReportOutput(const std::string& out_path);

// Builds the page and writes it to `out_path` through a temporary file and a rename (InputError,
// with the system's reason, if it cannot be written; the previous page then stays whole). Only
// regular files inside `dir`, reached without symbolic links, are read into the page.
void WriteReport(const std::string& dir, const std::string& out_path,
                 const ReportConfig& config = ReportConfig());

// Helpers, exposed for the tests.
std::string Base64Encode(const std::string& bytes);
std::string HtmlEscape(const std::string& text);
// A picture file as "data:image/...;base64,...", downscaled / re-encoded per `config`. Returns ""
// when the file cannot be read as an image.
std::string ImageDataUri(const std::string& path, const ReportConfig& config);

}  // namespace zeroreg
