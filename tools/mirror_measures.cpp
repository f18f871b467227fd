// zeroreg-mirror-measures: what tells a mirrored scan's fit from a right result, measured on
// registration results under their own transforms. Not installed; a measurement, not a test
// (docs/CONFIG.md, verify.mirror_min_matches).
//
//   zeroreg-mirror-measures RECORDS.jsonl... [--data DIR] [--radius M]...
//
// Each record (a line of an eval pairs.jsonl, or of scripts/bench-mirrored.py's) names a scene,
// a source and a target frame and its transform T_est; "mirrored": true flips the source frame
// left-right as bench-mirrored.py does. The features are the pipeline's default ones (the
// extractor and lifting Pipeline::Prepare uses). Prints one JSON line per record: its key,
// valid, rotation / translation error where the record has them, the distinctive matches of the
// source's images with the target's as given and flipped left-right (what the pipeline's mirror
// test decides on, src/pipeline/handedness.hpp), the camera turn under T_est, and per radius the
// keypoint agreement (co-visible, agreeing, chance; the same for the keypoints seen alike from
// both cameras). Exits 2 on a bad argument or file.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "estimate/lift.hpp"
#include "features/feature_extractor.hpp"
#include "pipeline/handedness.hpp"
#include "pipeline/image_correspondences.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace {

using namespace zeroreg;

// What the pipeline's mirror test (src/pipeline/handedness.hpp) was chosen against: the keypoint
// agreement under a result's transform. Of the source keypoints that land on a target view's
// measured surface (co-visible, within the check's depth tolerance), how many have their
// descriptor's nearest neighbour among that view's keypoints within a radius of where the
// transform puts them. It did not separate mirror fits from right results (right results across
// a wide change of view agree as little), so it decides nothing in the pipeline.
struct KeypointAgreement {
  // Source keypoints that land on a target view's measured surface under the transform (within
  // the check's depth tolerance), at most kAgreementKeypoints per source view.
  int covisible = 0;
  // Of those, the ones whose descriptor's nearest neighbour (cosine) among that target view's
  // keypoints lies within `settings.radius_m` of where the transform puts them.
  int agreeing = 0;
  // What `agreeing` would be by chance: the sum over the co-visible keypoints of the share of the
  // target view's keypoints within `settings.radius_m` of where each lands.
  double chance = 0.0;
  // The same counts over the co-visible keypoints whose surface point the two cameras see alike:
  // the rays from the two cameras to it within `near_view_deg` of each other and its distances
  // from them within a factor of `near_view_scale` (the descriptors are made for that; across a
  // wider change of view they fail on right poses too).
  int covisible_near = 0;
  int agreeing_near = 0;
  double chance_near = 0.0;
};

struct AgreementSettings {
  double radius_m = 0.1;
  double near_view_deg = 15.0;
  double near_view_scale = 1.25;
};

// The strongest keypoints of a view that the agreement uses (the extractors sort by score).
constexpr int kAgreementKeypoints = 1024;

// Whether a point at camera depth z that lands at pixel (u, v) of `view` lies on its measured
// surface: some depth reading within verify.neighbourhood_px agrees within the check's tolerance.
bool OnSurface(const View& view, double u, double v, double z, const VerifyConfig& verify,
               const DepthModel& depth) {
  const int x0 = static_cast<int>(std::lround(u));
  const int y0 = static_cast<int>(std::lround(v));
  const int r = std::max(0, verify.neighbourhood_px);
  const double sigma = depth.noise_at_1m_m * std::pow(z, depth.noise_exponent);
  const double tau = verify.registration_tolerance_m + verify.depth_noise_sigmas * sigma;
  for (int y = y0 - r; y <= y0 + r; ++y) {
    if (y < 0 || y >= view.depth.rows) continue;
    const float* row = view.depth.ptr<float>(y);
    for (int x = x0 - r; x <= x0 + r; ++x) {
      if (x < 0 || x >= view.depth.cols) continue;
      const double d = row[x];
      if (!(d >= depth.min_m && d <= depth.max_m)) continue;
      if (std::abs(z - d) <= tau) return true;
    }
  }
  return false;
}

KeypointAgreement MeasureKeypointAgreement(const std::vector<LiftedFeatures>& source,
                                           const Scan& source_scan,
                                           const std::vector<LiftedFeatures>& target,
                                           const Scan& target_scan,
                                           const Transform& T_target_source,
                                           const VerifyConfig& verify, const DepthModel& depth,
                                           const AgreementSettings& settings) {
  KeypointAgreement out;
  const size_t views = std::min(target.size(), target_scan.views.size());
  // Per target view: the co-visible source keypoints (view, row) and where they land.
  std::vector<std::vector<std::pair<int, int>>> rows(views);
  std::vector<std::vector<Eigen::Vector3d>> landed(views);
  std::vector<std::vector<char>> near_view(views);  // seen alike from both cameras
  const double cos_near = std::cos(settings.near_view_deg * M_PI / 180.0);
  std::vector<Transform> camera_from_scan(views);
  for (size_t t = 0; t < views; ++t) {
    camera_from_scan[t] = target_scan.views[t].T_scan_camera.inverse();
  }
  for (size_t s = 0; s < source.size(); ++s) {
    const LiftedFeatures& f = source[s];
    // The source camera's centre in the target scan's frame.
    const Eigen::Vector3d source_centre =
        s < source_scan.views.size()
            ? (T_target_source * source_scan.views[s].T_scan_camera.col(3)).head<3>()
            : Eigen::Vector3d(T_target_source.topRightCorner<3, 1>());
    const int n = std::min<int>(static_cast<int>(f.points.size()), kAgreementKeypoints);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d q = (T_target_source * f.points[i].homogeneous()).head<3>();
      for (size_t t = 0; t < views; ++t) {
        const View& view = target_scan.views[t];
        const Eigen::Vector3d c = (camera_from_scan[t] * q.homogeneous()).head<3>();
        if (c.z() < depth.min_m) continue;
        const double u = view.intrinsics.fx * c.x() / c.z() + view.intrinsics.cx;
        const double v = view.intrinsics.fy * c.y() / c.z() + view.intrinsics.cy;
        if (u < 0 || v < 0 || u > view.depth.cols - 1 || v > view.depth.rows - 1) continue;
        if (!OnSurface(view, u, v, c.z(), verify, depth)) continue;
        rows[t].emplace_back(static_cast<int>(s), i);
        landed[t].push_back(q);
        const Eigen::Vector3d to_source = source_centre - q;
        const Eigen::Vector3d to_target = view.T_scan_camera.topRightCorner<3, 1>() - q;
        const double ds = to_source.norm(), dt = to_target.norm();
        const bool alike = ds > 0 && dt > 0 && to_source.dot(to_target) >= cos_near * ds * dt &&
                           std::max(ds, dt) <= settings.near_view_scale * std::min(ds, dt);
        near_view[t].push_back(alike ? 1 : 0);
        break;
      }
    }
  }
  const double r2 = settings.radius_m * settings.radius_m;
  for (size_t t = 0; t < views; ++t) {
    const LiftedFeatures& g = target[t];
    const int m = std::min<int>(static_cast<int>(g.points.size()), kAgreementKeypoints);
    if (rows[t].empty() || m == 0) continue;
    const Eigen::Index dim = g.features.descriptors.cols();
    Eigen::MatrixXf queries(static_cast<Eigen::Index>(rows[t].size()), dim);
    for (size_t k = 0; k < rows[t].size(); ++k) {
      const auto [s, i] = rows[t][k];
      queries.row(static_cast<Eigen::Index>(k)) =
          source[static_cast<size_t>(s)].features.descriptors.row(i);
    }
    const Eigen::MatrixXf cosine = queries * g.features.descriptors.topRows(m).transpose();
    for (size_t k = 0; k < rows[t].size(); ++k) {
      Eigen::Index best = 0;
      cosine.row(static_cast<Eigen::Index>(k)).maxCoeff(&best);
      const Eigen::Vector3d& q = landed[t][k];
      const bool agrees = (g.points[static_cast<size_t>(best)] - q).squaredNorm() < r2;
      int near = 0;
      for (int j = 0; j < m; ++j) {
        if ((g.points[static_cast<size_t>(j)] - q).squaredNorm() < r2) ++near;
      }
      const double chance = static_cast<double>(near) / m;
      ++out.covisible;
      out.agreeing += agrees ? 1 : 0;
      out.chance += chance;
      if (near_view[t][k]) {
        ++out.covisible_near;
        out.agreeing_near += agrees ? 1 : 0;
        out.chance_near += chance;
      }
    }
  }
  return out;
}

std::vector<LiftedFeatures> Features(const FeatureExtractor& extractor, const Scan& scan,
                                     const PipelineConfig& config) {
  std::vector<LiftedFeatures> out;
  for (const View& view : scan.views) {
    out.push_back(
        ExtractLiftedFeatures(extractor, view, LiftForView(config.lift, config.depth, view)));
  }
  return out;
}

Scan Mirrored(Scan scan) {
  for (View& view : scan.views) {
    cv::flip(view.color, view.color, 1);
    cv::flip(view.depth, view.depth, 1);
  }
  return scan;
}

int Run(int argc, char** argv) {
  CLI::App app{"what tells a mirrored scan's fit from a right result"};
  std::vector<std::string> files;
  std::string data = "../shared/data";
  std::vector<double> radii = {0.05, 0.1, 0.2};
  app.add_option("records", files, "pairs.jsonl files")->required();
  app.add_option("--data", data, "folder of the scenes")->capture_default_str();
  app.add_option("--radius", radii, "agreement radii (m)");
  CLI11_PARSE(app, argc, argv);

  const PipelineConfig config;
  const std::unique_ptr<FeatureExtractor> extractor =
      MakeFeatureExtractor(config.features, ResolveAssetsDir(config.assets_dir), config.inference);
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) throw InputError(file + ": cannot open");
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      const nlohmann::json rec = nlohmann::json::parse(line);
      if (!rec.contains("T_est") || !rec.contains("scene")) continue;
      const std::string root = data + "/" + rec.at("scene").get<std::string>();
      Scan source = LoadScan(root + "@" + std::to_string(rec.at("source").get<int>()));
      const Scan target = LoadScan(root + "@" + std::to_string(rec.at("target").get<int>()));
      const bool mirrored = rec.value("mirrored", false);
      if (mirrored) source = Mirrored(std::move(source));
      Transform T = Transform::Identity();
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) T(r, c) = rec.at("T_est")[r][c].get<double>();
      }
      const auto fs = Features(*extractor, source, config);
      const auto ft = Features(*extractor, target, config);
      nlohmann::json out;
      out["key"] = rec.value("key", rec.value("list", std::string()) + " " +
                                        std::to_string(rec.at("target").get<int>()) + " " +
                                        std::to_string(rec.at("source").get<int>()));
      out["benchmark"] = rec.value("benchmark", rec.value("list", std::string()));
      out["mirrored"] = mirrored;
      out["valid"] = rec.value("valid", false);
      out["path"] = rec.value("path", std::string());
      if (rec.contains("rotation_error_deg")) {
        out["re"] = rec["rotation_error_deg"];
        out["te"] = rec["translation_error_m"];
      }
      const Eigen::Matrix3d R = target.views[0].T_scan_camera.topLeftCorner<3, 3>().transpose() *
                                T.topLeftCorner<3, 3>() *
                                source.views[0].T_scan_camera.topLeftCorner<3, 3>();
      out["camera_turn_deg"] = std::acos(std::clamp((R.trace() - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
      // Handedness of the images: distinctive matches of the source as given and flipped.
      std::vector<ViewLift> lifts;
      for (const View& view : source.views) {
        lifts.push_back(LiftForView(config.lift, config.depth, view));
      }
      out["distinctive"] = DistinctiveMatches(fs, ft);
      out["distinctive_flipped"] =
          DistinctiveMatches(ExtractMirroredFeatures(*extractor, source, lifts), ft);
      for (double radius : radii) {
        AgreementSettings settings;
        settings.radius_m = radius;
        const KeypointAgreement a = MeasureKeypointAgreement(fs, source, ft, target, T,
                                                             config.verify, config.depth, settings);
        out["r" + std::to_string(static_cast<int>(radius * 100 + 0.5))] = {
            a.covisible, a.agreeing, a.chance, a.covisible_near, a.agreeing_near, a.chance_near};
      }
      std::cout << out.dump() << std::endl;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "zeroreg-mirror-measures: " << e.what() << "\n";
    return 2;
  }
}
