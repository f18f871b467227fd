#include "recordings/report.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

const char* VerdictColor(const std::string& verdict) {
  if (verdict == "accepted") return "#2a9d3a";
  if (verdict == "invalid") return "#cccccc";
  return "#d62828";  // valid but not accepted: unsupported, inconsistent, rival, ambiguous, ...
}

struct View2D {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_x = Eigen::Vector3d::UnitX(), axis_y = Eigen::Vector3d::UnitY();
  double min_x = 0, min_y = 0, scale = 1;
  Eigen::Vector2d operator()(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - mean;
    return {20 + (d.dot(axis_x) - min_x) * scale, 20 + (d.dot(axis_y) - min_y) * scale};
  }
};

// The plane of the two largest spreads of the positions (the floor plan of a walk).
View2D FitView(const std::vector<Eigen::Vector3d>& points, double size) {
  View2D v;
  if (points.empty()) return v;
  for (const auto& p : points) v.mean += p;
  v.mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : points) covariance += (p - v.mean) * (p - v.mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  v.axis_x = solver.eigenvectors().col(2);
  v.axis_y = solver.eigenvectors().col(1);
  double max_x = -1e300, max_y = -1e300;
  v.min_x = v.min_y = 1e300;
  for (const auto& p : points) {
    const Eigen::Vector3d d = p - v.mean;
    v.min_x = std::min(v.min_x, d.dot(v.axis_x));
    v.min_y = std::min(v.min_y, d.dot(v.axis_y));
    max_x = std::max(max_x, d.dot(v.axis_x));
    max_y = std::max(max_y, d.dot(v.axis_y));
  }
  v.scale = (size - 40) / std::max({max_x - v.min_x, max_y - v.min_y, 1e-3});
  return v;
}

std::string Svg(const RecordingsResult& result, const std::vector<Eigen::Vector3d>& positions,
                const View2D& view, const std::string& title) {
  std::string s = "<figure><svg width='520' height='520' style='border:1px solid #ddd'>";
  char buffer[256];
  for (const LoopCandidateResult& c : result.candidates) {
    const Eigen::Vector2d a = view(positions[c.u]), b = view(positions[c.v]);
    std::snprintf(buffer, sizeof(buffer),
                  "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='%s' stroke-width='%s'/>",
                  a.x(), a.y(), b.x(), b.y(), VerdictColor(c.verdict),
                  c.verdict == "invalid" ? "0.5" : "1.5");
    s += buffer;
  }
  for (std::size_t n = 0; n < positions.size(); ++n) {
    const Eigen::Vector2d p = view(positions[n]);
    std::snprintf(buffer, sizeof(buffer), "<circle cx='%.1f' cy='%.1f' r='3' fill='%s'/>", p.x(),
                  p.y(), result.keyframes[n].recording == 0 ? "#1e78c8" : "#fa8c1e");
    s += buffer;
  }
  return s + "</svg><figcaption>" + title + "</figcaption></figure>";
}

}  // namespace

void WriteRecordingsReport(const std::string& path, const RecordingsResult& result, bool merge,
                           const Transform& T_A_B_initial) {
  std::vector<Eigen::Vector3d> before, after;
  for (const RecordingKeyframe& k : result.keyframes) {
    const Transform T = k.recording == 1 ? T_A_B_initial * k.T_before : k.T_before;
    before.push_back(T.topRightCorner<3, 1>());
    after.push_back(k.T_after.topRightCorner<3, 1>());
  }
  std::vector<Eigen::Vector3d> all = after;
  all.insert(all.end(), before.begin(), before.end());
  const View2D view = FitView(all, 520);
  std::map<std::string, int> verdicts;
  for (const LoopCandidateResult& c : result.candidates) ++verdicts[c.verdict];
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot be written");
  out << "<!doctype html><html><head><meta charset='utf-8'><title>zeroreg "
      << (merge ? "merge" : "loops")
      << "</title><style>body{font-family:sans-serif;margin:2em}figure{display:inline-block;"
         "margin:0 1em}</style></head><body><h1>zeroreg "
      << (merge ? "merge" : "loops") << "</h1><p>" << (result.found ? "" : "<b>Not found:</b> ")
      << result.reason << "</p><p>Keyframes: <span style='color:#1e78c8'>&#9679; "
      << (merge ? "A" : "sequence") << "</span>"
      << (merge ? " <span style='color:#fa8c1e'>&#9679; B</span>" : "")
      << ". Candidate pairs: <span style='color:#2a9d3a'>accepted</span>, "
         "<span style='color:#d62828'>valid but not accepted</span>, "
         "<span style='color:#999'>not valid</span>.</p><p>";
  for (const auto& [verdict, count] : verdicts) out << verdict << ": " << count << " &nbsp; ";
  out << "</p>"
      << Svg(result, before, view,
             merge ? "before: given poses, B placed by the first accepted estimate"
                   : "before: the given odometry")
      << Svg(result, after, view, "after: the optimised pose graph (top view)")
      << "<table border='1' cellpadding='3' style='border-collapse:collapse;margin-top:1em'>"
         "<tr><th>stage</th><th>seconds</th><th>peak RSS MiB</th></tr>";
  char row[200];
  for (const StageReport& s : result.stages) {
    std::snprintf(row, sizeof(row), "<tr><td>%s</td><td>%.1f</td><td>%.0f</td></tr>",
                  s.stage.c_str(), s.seconds, s.peak_rss_mib);
    out << row;
  }
  out << "</table></body></html>\n";
}

}  // namespace zeroreg
