#include "viz/pictures.hpp"

#include "verify/verify.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <set>

#include "estimate/lift.hpp"
#include "io/image_codec.hpp"
#include "synthesis/render.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Distinct, saturated colours (BGR) for matched pairs; cycled when there are more pairs.
const cv::Scalar kPalette[] = {{75, 25, 230},  {75, 180, 60},  {25, 225, 255},  {200, 130, 0},
                               {48, 130, 245}, {180, 30, 145}, {240, 240, 70},  {230, 50, 240},
                               {60, 245, 210}, {128, 128, 0},  {255, 190, 220}, {40, 110, 170}};
const cv::Scalar kGrey(150, 150, 150);

cv::Mat SideBySide(const View& a, const View& b) {
  cv::Mat canvas(std::max(a.color.rows, b.color.rows), a.color.cols + b.color.cols, CV_8UC3,
                 cv::Scalar(0, 0, 0));
  a.color.copyTo(canvas(cv::Rect(0, 0, a.color.cols, a.color.rows)));
  b.color.copyTo(canvas(cv::Rect(a.color.cols, 0, b.color.cols, b.color.rows)));
  return canvas;
}

void DrawObject(cv::Mat& canvas, const ObjectSummary& object, int view, int x_offset,
                const cv::Scalar& colour) {
  for (const ObjectView& ov : object.views) {
    if (ov.view != view) continue;
    const cv::Point offset(x_offset, 0);
    if (!ov.outline.empty()) {
      std::vector<cv::Point> shifted;
      for (const cv::Point& p : ov.outline) shifted.push_back(p + offset);
      cv::polylines(canvas, std::vector<std::vector<cv::Point>>{shifted}, true, colour, 2);
    }
    const cv::Rect box(cv::Point(static_cast<int>(ov.box.x) + x_offset, static_cast<int>(ov.box.y)),
                       cv::Size(static_cast<int>(ov.box.width), static_cast<int>(ov.box.height)));
    cv::rectangle(canvas, box, colour, 1);
    char text[128];
    std::snprintf(text, sizeof(text), "%s %.2f", object.label.c_str(), ov.score);
    const cv::Point at(box.x + 2, std::max(box.y - 4, 12));
    cv::putText(canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3);
    cv::putText(canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1);
  }
}

void Caption(cv::Mat& canvas, const std::string& text) {
  cv::putText(canvas, text, cv::Point(8, canvas.rows - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 3);
  cv::putText(canvas, text, cv::Point(8, canvas.rows - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(255, 255, 255), 1);
}

}  // namespace

cv::Mat DrawObjectMatches(const Scan& source, const Scan& target, const RegistrationResult& result,
                          int view) {
  const View& a = source.views[view];
  cv::Mat canvas = SideBySide(a, target.views[view]);
  std::vector<int> colour_s(result.source_objects.size(), -1),
      colour_t(result.target_objects.size(), -1);
  for (size_t k = 0; k < result.object_matches.size(); ++k) {
    colour_s[result.object_matches[k].source] = static_cast<int>(k);
    colour_t[result.object_matches[k].target] = static_cast<int>(k);
  }
  const int palette = static_cast<int>(std::size(kPalette));
  for (size_t i = 0; i < result.source_objects.size(); ++i) {
    DrawObject(canvas, result.source_objects[i], view, 0,
               colour_s[i] < 0 ? kGrey : kPalette[colour_s[i] % palette]);
  }
  for (size_t i = 0; i < result.target_objects.size(); ++i) {
    DrawObject(canvas, result.target_objects[i], view, a.color.cols,
               colour_t[i] < 0 ? kGrey : kPalette[colour_t[i] % palette]);
  }
  char text[160];
  std::snprintf(
      text, sizeof(text), "source | target   %zu / %zu objects, %zu matched (grey: unmatched)",
      result.source_objects.size(), result.target_objects.size(), result.object_matches.size());
  Caption(canvas, text);
  return canvas;
}

namespace {

// The correspondences between source view `source_view` and target view `target_view` (-1: the
// rendered target) as lines from the left image to the right one, `offset` apart: outliers red
// first, inliers green on top; counts them.
void DrawMatchLines(const RegistrationResult& result, int source_view, int target_view,
                    const cv::Point2f& offset, cv::Mat* canvas, int* inliers, int* outliers) {
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t i = 0; i < result.correspondences.size(); ++i) {
      const Correspondence& c = result.correspondences[i];
      if (c.view != source_view || c.target_view != target_view) continue;
      const bool inlier = i < result.is_inlier.size() && result.is_inlier[i];
      if (inlier != (pass == 1)) continue;
      ++*(inlier ? inliers : outliers);
      const cv::Point2f p(c.source_pixel.x(), c.source_pixel.y());
      const cv::Point2f q = cv::Point2f(c.target_pixel.x(), c.target_pixel.y()) + offset;
      const cv::Scalar colour = inlier ? cv::Scalar(60, 200, 60) : cv::Scalar(40, 40, 230);
      cv::line(*canvas, p, q, colour, 1, cv::LINE_AA);
      cv::circle(*canvas, p, 2, colour, -1);
      cv::circle(*canvas, q, 2, colour, -1);
    }
  }
}

}  // namespace

cv::Mat DrawCorrespondences(const Scan& source, const Scan& target,
                            const RegistrationResult& result, int source_view, int target_view) {
  const View& a = source.views[source_view];
  cv::Mat canvas = SideBySide(a, target.views[target_view]);
  const cv::Point2f offset(static_cast<float>(a.color.cols), 0.f);
  int inliers = 0, outliers = 0;
  DrawMatchLines(result, source_view, target_view, offset, &canvas, &inliers, &outliers);
  char text[160];
  std::snprintf(text, sizeof(text), "%d RANSAC inliers (green), %d outliers (red); path %s",
                inliers, outliers, PathName(result.path).c_str());
  Caption(canvas, text);
  return canvas;
}

cv::Mat DrawSynthesizedView(const Scan& source, const Scan& target,
                            const RegistrationResult& result) {
  if (!result.rendered_view) return cv::Mat();
  const RenderedCamera& camera = *result.rendered_view;
  const View& a = source.views[static_cast<size_t>(camera.source_view)];
  View rendered;
  rendered.color = RenderScan(target, camera.T_target_camera, camera.intrinsics).color;
  cv::Mat canvas = SideBySide(a, rendered);
  const cv::Point2f offset(static_cast<float>(a.color.cols), 0.f);
  int inliers = 0, outliers = 0;
  DrawMatchLines(result, camera.source_view, /*target_view=*/-1, offset, &canvas, &inliers,
                 &outliers);
  char text[240];
  std::snprintf(text, sizeof(text),
                "source view %d | target rendered from %s: %d inliers (green), %d outliers (red); "
                "%s",
                camera.source_view, camera.from.c_str(), inliers, outliers,
                result.valid ? "valid" : "not valid");
  Caption(canvas, text);
  return canvas;
}

cv::Mat DrawRegisteredClouds(const Scan& source, const Scan& target,
                             const Transform& T_target_source, int view) {
  const View& tv = target.views[view];
  const Intrinsics& K = tv.intrinsics;
  cv::Mat canvas(tv.color.rows, tv.color.cols, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat zbuffer(tv.color.rows, tv.color.cols, CV_32F, cv::Scalar(1e9f));
  const Transform T_camera_target = tv.T_scan_camera.inverse();
  auto splat = [&](const std::vector<Eigen::Vector3d>& points, const Transform& T,
                   const cv::Vec3b& colour) {
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d c = (T * p.homogeneous()).head<3>();
      if (c.z() <= 0.05) continue;
      const int x = static_cast<int>(std::lround(K.fx * c.x() / c.z() + K.cx));
      const int y = static_cast<int>(std::lround(K.fy * c.y() / c.z() + K.cy));
      for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u < 0 || v < 0 || u >= canvas.cols || v >= canvas.rows) continue;
          // Points within 1 cm of the nearest surface both show, so that overlap interleaves.
          if (c.z() < zbuffer.at<float>(v, u) + 0.01f) {
            zbuffer.at<float>(v, u) = std::min(zbuffer.at<float>(v, u), static_cast<float>(c.z()));
            canvas.at<cv::Vec3b>(v, u) = colour;
          }
        }
      }
    }
  };
  const std::vector<Eigen::Vector3d> target_points = ScanPoints(target, PixelGrid{3}),
                                     source_points = ScanPoints(source, PixelGrid{3});
  // Interleave draw order by splitting each cloud in halves, so neither colour always wins.
  const size_t hs = source_points.size() / 2, ht = target_points.size() / 2;
  const std::vector<Eigen::Vector3d> s1(source_points.begin(), source_points.begin() + hs),
      s2(source_points.begin() + hs, source_points.end()),
      t1(target_points.begin(), target_points.begin() + ht),
      t2(target_points.begin() + ht, target_points.end());
  const cv::Vec3b blue(200, 120, 30), orange(30, 140, 250);
  splat(t1, T_camera_target, blue);
  splat(s1, T_camera_target * T_target_source, orange);
  splat(t2, T_camera_target, blue);
  splat(s2, T_camera_target * T_target_source, orange);
  Caption(canvas,
          "registered: target blue, source orange (in target view " + std::to_string(view) + ")");
  return canvas;
}

cv::Mat DrawVerification(const Scan& source, const Scan& target, const RegistrationResult& result,
                         const VerifyConfig& config, const DepthModel& depth, int view) {
  const View& tv = target.views[view];
  cv::Mat grey, canvas;
  cv::cvtColor(tv.color, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(grey / 2 + 64, canvas, cv::COLOR_GRAY2BGR);  // dimmed, so the dots stand out
  const cv::Scalar colours[] = {cv::Scalar(60, 200, 60), cv::Scalar(40, 40, 230),
                                cv::Scalar(40, 210, 230)};  // agree, violate, occluded (BGR)
  for (const VerificationSample& s :
       VerificationSamples(source, target, result.T_target_source, config, depth, view)) {
    cv::circle(canvas,
               cv::Point(static_cast<int>(std::lround(s.x)), static_cast<int>(std::lround(s.y))), 1,
               colours[s.kind], cv::FILLED);
  }
  char text[200];
  const VerificationResult& v = result.verification;
  std::snprintf(text, sizeof(text),
                "check %s: overlap %.0f%%, free-space violations %.1f%% (green/red/yellow)",
                v.ran ? (v.passed ? "passed" : "FAILED") : "off", 100 * v.overlap,
                100 * v.violation);
  Caption(canvas, text);
  return canvas;
}

namespace {

// Tiles two per row, an odd last row padded with white; empty without tiles.
cv::Mat TwoPerRow(const std::vector<cv::Mat>& tiles) {
  if (tiles.empty()) return {};
  const int columns = tiles.size() > 1 ? 2 : 1;
  std::vector<cv::Mat> rows;
  for (size_t k = 0; k < tiles.size(); k += columns) {
    std::vector<cv::Mat> row(
        tiles.begin() + static_cast<long>(k),
        tiles.begin() + static_cast<long>(std::min(tiles.size(), k + columns)));
    while (static_cast<int>(row.size()) < columns) {
      row.emplace_back(tiles[0].size(), tiles[0].type(), cv::Scalar(255, 255, 255));
    }
    cv::Mat joined;
    cv::hconcat(row, joined);
    rows.push_back(joined);
  }
  cv::Mat canvas;
  cv::vconcat(rows, canvas);
  return canvas;
}

}  // namespace

cv::Mat DrawHypotheses(const Scan& source, const Scan& target, const RegistrationResult& result,
                       int view, int max_candidates) {
  // The chosen candidate first, then the others by verification score (best first).
  std::vector<const CandidateSummary*> order;
  for (const CandidateSummary& c : result.candidates) order.push_back(&c);
  std::stable_sort(order.begin(), order.end(),
                   [](const CandidateSummary* a, const CandidateSummary* b) {
                     if (a->chosen != b->chosen) return a->chosen;
                     return a->score > b->score;
                   });
  if (static_cast<int>(order.size()) > max_candidates)
    order.resize(static_cast<size_t>(max_candidates));
  std::vector<cv::Mat> tiles;
  for (const CandidateSummary* c : order) {
    cv::Mat tile = DrawRegisteredClouds(source, target, c->T_target_source, view);
    // Cover the registered-clouds caption with this candidate's verdict.
    cv::rectangle(tile, cv::Point(0, tile.rows - 28), cv::Point(tile.cols, tile.rows),
                  c->chosen ? cv::Scalar(60, 140, 60) : cv::Scalar(90, 90, 90), cv::FILLED);
    char text[200];
    std::snprintf(text, sizeof(text), "%s%s: score %.3f, check %s%s", c->chosen ? "CHOSEN " : "",
                  c->name.c_str(), c->score, c->passed ? "passed" : "refused",
                  c->outside_prior ? ", outside the prior" : "");
    Caption(tile, text);
    tiles.push_back(tile);
  }
  return TwoPerRow(tiles);
}

cv::Mat DrawAlternatives(const Scan& source, const Scan& target, const RegistrationResult& result,
                         int view) {
  std::vector<cv::Mat> tiles;
  for (size_t k = 0; k < result.alternatives.size(); ++k) {
    const Alternative& a = result.alternatives[k];
    cv::Mat tile = DrawRegisteredClouds(source, target, a.T_target_source, view);
    cv::rectangle(tile, cv::Point(0, tile.rows - 28), cv::Point(tile.cols, tile.rows),
                  a.outside_prior ? cv::Scalar(90, 90, 90) : cv::Scalar(40, 110, 200), cv::FILLED);
    char text[200];
    std::snprintf(text, sizeof(text), "%s%s: score %.3f, %.2f m apart%s", k == 0 ? "REPORTED " : "",
                  a.name.c_str(), a.score, a.apart_m, a.outside_prior ? ", outside the prior" : "");
    Caption(tile, text);
    tiles.push_back(tile);
  }
  return TwoPerRow(tiles);
}

bool IsRegistrationPictureName(const std::string& file_name) {
  static const std::regex name_re(
      "(objects|correspondences|registered|verification|hypotheses|ambiguous|synthesized)-view[0-9]"
      "+"
      "(-[0-9]+)?\\.(png|"
      "jpg)");
  return std::regex_match(file_name, name_re);
}

std::vector<std::string> WriteRegistrationPictures(const std::string& dir, const Scan& source,
                                                   const Scan& target,
                                                   const RegistrationResult& result,
                                                   const VerifyConfig& verify,
                                                   const DepthModel& depth) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw MakeInputError(dir, "cannot create the picture folder (" + ec.message() + ")");
  // A run with fewer views, or without a choice of candidates, writes fewer pictures: those of an
  // earlier run would otherwise be shown (by `zeroreg report`) as this result's.
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    std::error_code type_error;
    if (entry.is_directory(type_error) && !entry.is_symlink(type_error)) continue;
    if (!IsRegistrationPictureName(entry.path().filename().string())) continue;
    std::error_code remove_error;
    std::filesystem::remove(entry.path(), remove_error);
    if (remove_error) {
      throw MakeInputError(entry.path().string(), "cannot remove the picture of an earlier run (" +
                                                      remove_error.message() + ")");
    }
  }
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const cv::Mat& image) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    if (!detail::WriteImageFile(path, image))
      throw MakeInputError(path, "cannot write the picture");
    written.push_back(path);
  };
  const size_t views = std::min(source.views.size(), target.views.size());
  for (size_t v = 0; v < views; ++v) {
    const std::string suffix = "-view" + std::to_string(v) + ".png";
    const int view = static_cast<int>(v);
    if (!result.source_objects.empty() || !result.target_objects.empty()) {
      write("objects" + suffix, DrawObjectMatches(source, target, result, view));
    }
    write("correspondences" + suffix, DrawCorrespondences(source, target, result, view, view));
    write("registered" + suffix,
          DrawRegisteredClouds(source, target, result.T_target_source, view));
  }
  for (size_t v = 0; v < target.views.size(); ++v) {
    write("verification-view" + std::to_string(v) + ".png",
          DrawVerification(source, target, result, verify, depth, static_cast<int>(v)));
  }
  if (result.rendered_view && result.rendered_view->source_view >= 0 &&
      result.rendered_view->source_view < static_cast<int>(source.views.size())) {
    write("synthesized-view" + std::to_string(result.rendered_view->source_view) + ".png",
          DrawSynthesizedView(source, target, result));
  }
  // The winning hypothesis and its runners-up, when there was a choice.
  if (result.candidates.size() > 1) {
    for (size_t v = 0; v < target.views.size(); ++v) {
      write("hypotheses-view" + std::to_string(v) + ".png",
            DrawHypotheses(source, target, result, static_cast<int>(v), /*max_candidates=*/6));
    }
  }
  // The poses that fit an ambiguous pair (or that a motion prior ruled out), side by side.
  if (!result.alternatives.empty()) {
    for (size_t v = 0; v < target.views.size(); ++v) {
      write("ambiguous-view" + std::to_string(v) + ".png",
            DrawAlternatives(source, target, result, static_cast<int>(v)));
    }
  }
  // Pairs of different views (the whole-image fallback may match every source view with every
  // target view): a correspondence picture for each pair that has correspondences.
  std::set<std::pair<int, int>> cross_pairs;
  for (const Correspondence& c : result.correspondences) {
    if (c.view != c.target_view) cross_pairs.emplace(c.view, c.target_view);
  }
  for (const auto& [vs, vt] : cross_pairs) {
    // Target view -1: pixels of a rendering (synthesized-view<i>.png shows them).
    if (vs >= static_cast<int>(source.views.size()) || vt < 0 ||
        vt >= static_cast<int>(target.views.size())) {
      continue;
    }
    write("correspondences-view" + std::to_string(vs) + "-" + std::to_string(vt) + ".png",
          DrawCorrespondences(source, target, result, vs, vt));
  }
  return written;
}

}  // namespace zeroreg
