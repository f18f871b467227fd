#include "verify/verify.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

#include "estimate/lift.hpp"

namespace zeroreg {
namespace {

// Tallies of one direction (points of scan A rendered into the views of scan B).
struct RenderTally {
  int points = 0;      // sampled depth pixels of A (each counted once, in its best view of B)
  int agree = 0;       // coincide with a surface of B
  int violate = 0;     // lie in B's free space
  int occluded = 0;    // behind B's surface
  double score = 0.0;  // sum over agreeing points of 1 - (r / tau)^2 minus one per violation
  double sum_sq_residual = 0.0;  // over agreeing points, m^2
};

// Tallies of both directions and what they say (the fields of VerificationResult).
struct GeometricAgreement {
  double overlap = 0.0, overlap_max = 0.0, violation = 0.0, residual_rms_m = 0.0, score = 0.0;
};

// Camera point of pixel (x, y) at depth z.
Eigen::Vector3d CameraPoint(const Intrinsics& K, double x, double y, double z) {
  return {(x - K.cx) * z / K.fx, (y - K.cy) * z / K.fy, z};
}

double Tolerance(const VerifyConfig& c, const DepthModel& depth, double d) {
  // d * d for the structured-light exponent 2: the hot path, and the sum rounds as it always did.
  if (depth.noise_exponent == 2.0) {
    return c.registration_tolerance_m + c.depth_noise_sigmas * depth.noise_at_1m_m * d * d;
  }
  return c.registration_tolerance_m +
         c.depth_noise_sigmas * depth.noise_at_1m_m * std::pow(d, depth.noise_exponent);
}

enum class Evidence { kNone, kOccluded, kViolate, kAgree };

// Where point p (camera frame of `view`) lands in the view's depth image, and what it says.
Evidence Classify(const View& view, const Eigen::Vector3d& p, const VerifyConfig& c,
                  const DepthModel& depth_model, double* residual, double* tolerance,
                  cv::Point* pixel = nullptr) {
  if (p.z() <= depth_model.min_m) return Evidence::kNone;
  const Intrinsics& K = view.intrinsics;
  const int u = static_cast<int>(std::lround(K.fx * p.x() / p.z() + K.cx));
  const int v = static_cast<int>(std::lround(K.fy * p.y() / p.z() + K.cy));
  const cv::Mat& depth = view.depth;
  if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return Evidence::kNone;
  if (pixel != nullptr) *pixel = {u, v};
  const double centre = depth.at<float>(v, u);
  const int r = std::max(0, c.neighbourhood_px);
  double best_tolerance = 0, best_ratio = 1e30, nearest_front = 1e30;
  bool all_valid = true;
  for (int y = std::max(0, v - r); y <= std::min(depth.rows - 1, v + r); ++y) {
    const float* row = depth.ptr<float>(y);
    for (int x = std::max(0, u - r); x <= std::min(depth.cols - 1, u + r); ++x) {
      const double d = row[x];
      if (!(d >= depth_model.min_m && d <= depth_model.max_m)) {
        all_valid = false;
        continue;
      }
      const double tau = Tolerance(c, depth_model, d);
      const double e = std::abs(p.z() - d);
      if (e / tau < best_ratio) {
        best_ratio = e / tau;
        best_tolerance = tau;
      }
      nearest_front = std::min(nearest_front, d - tau);
    }
  }
  const bool centre_valid = centre >= depth_model.min_m && centre <= depth_model.max_m;
  if (best_ratio <= 1.0) {
    // The residual that scores the agreement is the one at the landing pixel itself (capped at
    // the tolerance): the neighbourhood decides agreement, but would hide a misalignment of a
    // pixel or two from the score that ranks candidates.
    *tolerance = best_tolerance;
    *residual = centre_valid ? std::min(std::abs(p.z() - centre), best_tolerance) : best_tolerance;
    return Evidence::kAgree;
  }
  if (!centre_valid) return Evidence::kNone;
  // In front of every reading around the landing pixel: space the camera saw through.
  if (all_valid && p.z() < nearest_front) return Evidence::kViolate;
  return Evidence::kOccluded;
}

// Grey level (0-255) of a colour pixel, the mean of its three channels (the same in RGB and BGR);
// -1 when the view has no colour of the depth's size.
float GrayAt(const View& view, int x, int y) {
  const cv::Mat& color = view.color;
  if (color.type() != CV_8UC3 || color.size() != view.depth.size()) return -1.0f;
  const cv::Vec3b& c = color.at<cv::Vec3b>(y, x);
  return (static_cast<float>(c[0]) + static_cast<float>(c[1]) + static_cast<float>(c[2])) / 3.0f;
}

// Points of scan A (already in B's scan frame) rendered into B's views; a point counts once,
// with the strongest evidence any view of B gives (agreement over violation over occlusion).
// `gray_pairs`: for each agreeing point with colour in both scans, (A's grey, B's grey where it
// lands).
RenderTally Render(const std::vector<SurfacePoint>& points_in_b, const Scan& b,
                   const VerifyConfig& c, const DepthModel& depth_model,
                   std::vector<Evidence>* evidence = nullptr,
                   std::vector<std::pair<float, float>>* gray_pairs = nullptr) {
  RenderTally tally;
  if (evidence) evidence->clear();
  tally.points = static_cast<int>(points_in_b.size());
  std::vector<Transform> T_camera_scan;
  for (const View& view : b.views) T_camera_scan.push_back(view.T_scan_camera.inverse());
  for (const SurfacePoint& s : points_in_b) {
    Evidence strongest = Evidence::kNone;
    double residual = 0, tolerance = 1;
    size_t landed_view = 0;
    cv::Point landed;
    for (size_t k = 0; k < b.views.size() && strongest != Evidence::kAgree; ++k) {
      const Eigen::Vector3d p = (T_camera_scan[k] * s.point.homogeneous()).head<3>();
      double r = 0, tau = 1;
      cv::Point pixel;
      const Evidence e = Classify(b.views[k], p, c, depth_model, &r, &tau, &pixel);
      if (static_cast<int>(e) > static_cast<int>(strongest)) {
        strongest = e;
        residual = r;
        tolerance = tau;
        landed_view = k;
        landed = pixel;
      }
    }
    if (evidence) evidence->push_back(strongest);
    switch (strongest) {
      case Evidence::kAgree:
        if (gray_pairs != nullptr && s.gray >= 0.0f) {
          const float there = GrayAt(b.views[landed_view], landed.x, landed.y);
          if (there >= 0.0f) gray_pairs->emplace_back(s.gray, there);
        }
        ++tally.agree;
        tally.score += 1.0 - (residual / tolerance) * (residual / tolerance);
        tally.sum_sq_residual += residual * residual;
        break;
      case Evidence::kViolate:
        ++tally.violate;
        tally.score -= 1.0;
        break;
      case Evidence::kOccluded:
        ++tally.occluded;
        break;
      case Evidence::kNone:
        break;
    }
  }
  return tally;
}

std::vector<SurfacePoint> Moved(const std::vector<SurfacePoint>& points, const Transform& T) {
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T.topRightCorner<3, 1>();
  std::vector<SurfacePoint> out;
  out.reserve(points.size());
  for (const SurfacePoint& s : points) out.push_back({R * s.point + t, R * s.normal, s.gray});
  return out;
}

GeometricAgreement Summarise(const RenderTally& st, const RenderTally& ts) {
  GeometricAgreement g;
  const auto fraction = [](int part, int whole) {
    return whole > 0 ? static_cast<double>(part) / whole : 0.0;
  };
  const double a = fraction(st.agree, st.points), b = fraction(ts.agree, ts.points);
  g.overlap = std::min(a, b);
  g.overlap_max = std::max(a, b);
  const int agree = st.agree + ts.agree, violate = st.violate + ts.violate;
  g.violation = fraction(violate, agree + violate);
  g.residual_rms_m = agree > 0 ? std::sqrt((st.sum_sq_residual + ts.sum_sq_residual) / agree) : 0;
  const int points = st.points + ts.points;
  g.score = points > 0 ? (st.score + ts.score) / points : 0.0;
  return g;
}

// The rigid motion (in the target frame) that the agreeing source surfaces constrain least: the
// eigenvector of the smallest eigenvalue of sum J J^T, J = [(q - c) x n / rho; n], over agreeing
// points q with normals n (c their centroid, rho their RMS distance from it, so rotation and
// translation are both in metres of surface motion). Returned as a transform that moves the
// surfaces by about `distance` metres.
Transform WeakestMotion(const std::vector<SurfacePoint>& agreeing, double distance) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const SurfacePoint& s : agreeing) c += s.point;
  c /= static_cast<double>(agreeing.size());
  double rho_sq = 0;
  for (const SurfacePoint& s : agreeing) rho_sq += (s.point - c).squaredNorm();
  const double rho = std::sqrt(std::max(rho_sq / agreeing.size(), 1e-6));
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  for (const SurfacePoint& s : agreeing) {
    Eigen::Matrix<double, 6, 1> J;
    J << (s.point - c).cross(s.normal) / rho, s.normal;
    H += J * J.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(H);
  const Eigen::Matrix<double, 6, 1> weakest = eigen.eigenvectors().col(0);  // ascending order
  const Eigen::Vector3d omega = weakest.head<3>() * distance / rho;
  const Eigen::Vector3d translation = weakest.tail<3>() * distance;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (omega.norm() > 0) R = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  Transform T = Transform::Identity();  // rotate about the centroid, then translate
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = c - R * c + translation;
  return T;
}

// Average ranks (1-based) of `values`, ties sharing the mean of their ranks.
std::vector<double> Ranks(const std::vector<float>& values) {
  std::vector<size_t> order(values.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) ++j;
    const double mean_rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (size_t k = i; k <= j; ++k) ranks[order[k]] = mean_rank;
    i = j + 1;
  }
  return ranks;
}

// Spearman's rank correlation of the pairs; NaN below 30 pairs or without spread.
double RankCorrelation(const std::vector<std::pair<float, float>>& pairs) {
  constexpr size_t kMinPairs = 30;
  if (pairs.size() < kMinPairs) return std::numeric_limits<double>::quiet_NaN();
  std::vector<float> a, b;
  for (const auto& [x, y] : pairs) {
    a.push_back(x);
    b.push_back(y);
  }
  const std::vector<double> ra = Ranks(a), rb = Ranks(b);
  const double n = static_cast<double>(pairs.size()), mean = (n + 1.0) / 2.0;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    sab += (ra[i] - mean) * (rb[i] - mean);
    saa += (ra[i] - mean) * (ra[i] - mean);
    sbb += (rb[i] - mean) * (rb[i] - mean);
  }
  if (!(saa > 0 && sbb > 0)) return std::numeric_limits<double>::quiet_NaN();
  return sab / std::sqrt(saa * sbb);
}

}  // namespace

// The normal comes from the 4-neighbours 2 px away (the same neighbours that decide the edge test).
std::vector<SurfacePoint> SampleSurface(const Scan& scan, const VerifyConfig& config,
                                        const DepthModel& depth_model) {
  std::vector<SurfacePoint> out;
  constexpr int kStep = 2;
  for (const View& view : scan.views) {
    const cv::Mat& depth = view.depth;
    const int stride = PixelGrid{config.pixel_stride}.StrideFor(depth.cols);
    const Intrinsics& K = view.intrinsics;
    const Eigen::Matrix3d R = view.T_scan_camera.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = view.T_scan_camera.topRightCorner<3, 1>();
    for (int y = kStep; y + kStep < depth.rows; y += stride) {
      for (int x = kStep; x + kStep < depth.cols; x += stride) {
        const double z = depth.at<float>(y, x);
        if (!(z >= depth_model.min_m && z <= depth_model.max_m)) continue;
        const double left = depth.at<float>(y, x - kStep), right = depth.at<float>(y, x + kStep);
        const double up = depth.at<float>(y - kStep, x), down = depth.at<float>(y + kStep, x);
        const double limit = depth_model.edge_relative * z;
        bool edge = false;
        for (double n : {left, right, up, down}) edge |= !(n > 0) || std::abs(n - z) > limit;
        if (edge) continue;
        const Eigen::Vector3d dx =
            CameraPoint(K, x + kStep, y, right) - CameraPoint(K, x - kStep, y, left);
        const Eigen::Vector3d dy =
            CameraPoint(K, x, y + kStep, down) - CameraPoint(K, x, y - kStep, up);
        Eigen::Vector3d normal = dx.cross(dy);
        const double norm = normal.norm();
        normal = norm > 0 ? Eigen::Vector3d(R * normal / norm) : Eigen::Vector3d::Zero();
        out.push_back({R * CameraPoint(K, x, y, z) + t, normal, GrayAt(view, x, y)});
      }
    }
  }
  return out;
}

VerificationResult VerifyRegistration(const Scan& source, const Scan& target,
                                      const Transform& T_target_source, const VerifyConfig& config,
                                      const DepthModel& depth) {
  return VerifyRegistration(source, SampleSurface(source, config, depth), target,
                            SampleSurface(target, config, depth), T_target_source, config, depth);
}

VerificationResult VerifyRegistration(const Scan& source,
                                      const std::vector<SurfacePoint>& source_points,
                                      const Scan& target,
                                      const std::vector<SurfacePoint>& target_points,
                                      const Transform& T_target_source, const VerifyConfig& config,
                                      const DepthModel& depth) {
  VerificationResult v;
  v.ran = true;
  v.source_samples = static_cast<int>(source_points.size());
  v.target_samples = static_cast<int>(target_points.size());
  char why[400];
  if (static_cast<int>(std::min(source_points.size(), target_points.size())) < config.min_points) {
    std::snprintf(why, sizeof(why),
                  "too little depth to verify: %zu source and %zu target surface samples (need %d "
                  "each)",
                  source_points.size(), target_points.size(), config.min_points);
    v.reason = why;
    return v;
  }
  // Source samples into the target's views (their evidence is kept for the probe below), target
  // samples into the source's views.
  const std::vector<SurfacePoint> moved_source = Moved(source_points, T_target_source);
  std::vector<Evidence> at_estimate;
  std::vector<std::pair<float, float>> gray_pairs;  // (source grey, target grey)
  const RenderTally st = Render(moved_source, target, config, depth, &at_estimate, &gray_pairs);
  std::vector<std::pair<float, float>> gray_pairs_back;  // (target grey, source grey)
  const RenderTally ts = Render(Moved(target_points, T_target_source.inverse()), source, config,
                                depth, nullptr, &gray_pairs_back);
  for (const auto& [t, s] : gray_pairs_back) gray_pairs.emplace_back(s, t);
  v.brightness_rank_correlation = RankCorrelation(gray_pairs);
  const GeometricAgreement g = Summarise(st, ts);
  v.overlap = g.overlap;
  v.overlap_max = g.overlap_max;
  v.violation = g.violation;
  v.residual_rms_m = g.residual_rms_m;
  v.score = g.score;

  // Degeneracy probe along the least constrained motion, in both senses: the fraction of the
  // source samples agreeing at the estimate that the moved estimate puts off the target's surface
  // (in front of or behind it). A plane or a corridor slides: its samples stay on the surface.
  std::vector<SurfacePoint> agreeing;
  for (size_t k = 0; k < moved_source.size(); ++k) {
    if (at_estimate[k] == Evidence::kAgree && !moved_source[k].normal.isZero()) {
      agreeing.push_back(moved_source[k]);
    }
  }
  v.probe_contradicted = 1.0;
  if (agreeing.size() >= 6) {
    const Transform delta = WeakestMotion(agreeing, config.probe_translation_m);
    for (const Transform& step : {delta, Transform(delta.inverse())}) {
      std::vector<Evidence> probed;
      Render(Moved(agreeing, step), target, config, depth, &probed);
      const auto contradicted = std::count_if(probed.begin(), probed.end(), [](Evidence e) {
        return e == Evidence::kViolate || e == Evidence::kOccluded;
      });
      v.probe_contradicted =
          std::min(v.probe_contradicted, static_cast<double>(contradicted) / agreeing.size());
    }
  }
  v.degenerate = v.probe_contradicted < config.min_probe_contradicted;

  if (g.overlap < config.min_overlap) {
    std::snprintf(why, sizeof(why),
                  "the scans do not agree: only %.1f%% of one scan's surface coincides with the "
                  "other's under this transform (need %.0f%%; %.1f%% the other way)",
                  100 * g.overlap, 100 * config.min_overlap, 100 * g.overlap_max);
  } else if (g.violation > config.max_violation) {
    std::snprintf(why, sizeof(why),
                  "the scans contradict each other: %.1f%% of the compared surface lies in space "
                  "the other camera saw through (allowed %.0f%%; overlap %.1f%%)",
                  100 * g.violation, 100 * config.max_violation, 100 * g.overlap);
  } else {
    v.passed = true;
    std::snprintf(why, sizeof(why),
                  "the scans agree: overlap %.1f%%, free-space violations %.1f%%, depth residual "
                  "%.1f cm RMS, %.0f%% of it contradicted %.0f cm off",
                  100 * g.overlap, 100 * g.violation, 100 * g.residual_rms_m,
                  100 * v.probe_contradicted, 100 * config.probe_translation_m);
  }
  v.reason = why;
  if (v.degenerate) {
    // Flagged, not failed: the geometry leaves this motion open, the correspondences (texture)
    // may still fix it; the count test and the reason say so.
    std::snprintf(why, sizeof(why),
                  "; DEGENERATE geometry: moved %.0f cm along its least constrained direction, "
                  "only %.1f%% of the agreeing surface leaves the other scan's surface (a plane or "
                  "a corridor slides; %.0f%% expected), so only the correspondences fix that "
                  "motion",
                  100 * config.probe_translation_m, 100 * v.probe_contradicted,
                  100 * config.min_probe_contradicted);
    v.reason += why;
  }
  return v;
}

std::vector<VerificationSample> VerificationSamples(const Scan& source, const Scan& target,
                                                    const Transform& T_target_source,
                                                    const VerifyConfig& config,
                                                    const DepthModel& depth, int view) {
  std::vector<VerificationSample> out;
  if (view < 0 || view >= static_cast<int>(target.views.size())) return out;
  const View& tv = target.views[view];
  const Transform T = tv.T_scan_camera.inverse() * T_target_source;
  for (const SurfacePoint& s : SampleSurface(source, config, depth)) {
    const Eigen::Vector3d p = (T * s.point.homogeneous()).head<3>();
    double r = 0, tau = 1;
    const Evidence e = Classify(tv, p, config, depth, &r, &tau);
    if (e == Evidence::kNone) continue;
    VerificationSample sample;
    sample.x = static_cast<float>(tv.intrinsics.fx * p.x() / p.z() + tv.intrinsics.cx);
    sample.y = static_cast<float>(tv.intrinsics.fy * p.y() / p.z() + tv.intrinsics.cy);
    sample.kind = e == Evidence::kAgree     ? VerificationSample::kAgree
                  : e == Evidence::kViolate ? VerificationSample::kViolate
                                            : VerificationSample::kOccluded;
    out.push_back(sample);
  }
  return out;
}

}  // namespace zeroreg
