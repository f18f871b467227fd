// `zeroreg report RESULTS_DIR [--out report.html]`: one self-contained HTML page for a
// `register --out-dir` or `eval` results folder (docs/REPORT.md).
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "config_options.hpp"
#include "viz/report.hpp"

namespace zeroreg::cli {
namespace {

struct ReportOptions {
  std::string dir, out;
  ReportConfig config;
};

}  // namespace

Runner AddReportCommand(CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  app.add_option("results", o->dir,
                 "a `zeroreg register --out-dir` folder or a `zeroreg eval --out` folder")
      ->required();
  app.add_option("--out,-o", o->out, "the HTML file to write (default: RESULTS_DIR/report.html)");
  app.add_option("--title", o->config.title, "page title (default: the folder's name)");
  app.add_option("--max-width", o->config.max_image_width,
                 "downscale pictures wider than this many pixels (default 1280)")
      ->check(AtLeast(1, /*integer=*/true));
  app.add_option("--jpeg-quality", o->config.jpeg_quality,
                 "JPEG quality of re-encoded pictures, 1-100 (default 85)")
      ->check(InRange(1, 100, /*integer=*/true));
  app.add_option("--max-pairs-with-pictures", o->config.max_pairs_with_pictures,
                 "eval folders: embed pictures of at most this many pairs (default 200, -1 = all)");

  return [o]() {
    const std::string out =
        o->out.empty() ? (std::filesystem::path(o->dir) / "report.html").string() : o->out;
    WriteReport(o->dir, out, o->config);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(out, ec)) {
      // Written into a device or a pipe (--out /dev/stdout): the page alone goes there.
      std::fprintf(stderr, "report written to %s\n", out.c_str());
      return kExitOk;
    }
    const auto bytes = std::filesystem::file_size(out, ec);
    std::printf("report written to %s (%.1f MB)\n", out.c_str(), ec ? 0.0 : bytes / 1e6);
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
