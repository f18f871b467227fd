#include "recordings/keyframes.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "zeroreg/error.hpp"

namespace zeroreg {

namespace {

void Require(bool ok, const std::string& field, const std::string& expected, double value) {
  if (!ok) {
    throw InputError("keyframes." + field + " = " + std::to_string(value) + ": expected " +
                     expected);
  }
}

bool UsableDepth(const View& view) {
  return !view.depth.empty() && view.depth.type() == CV_32FC1 && view.intrinsics.fx > 0 &&
         view.intrinsics.fy > 0;
}

}  // namespace

void ValidateKeyframeConfig(const KeyframeConfig& c) {
  Require(c.covisibility_threshold >= 0.0 && c.covisibility_threshold <= 1.0,
          "covisibility_threshold", "a fraction in [0, 1]", c.covisibility_threshold);
  Require(c.depth_tolerance_m > 0.0, "depth_tolerance_m", "> 0 (metres)", c.depth_tolerance_m);
  Require(c.pixel_stride >= 1, "pixel_stride", ">= 1", c.pixel_stride);
  Require(c.min_depth_m >= 0.0, "min_depth_m", ">= 0 (metres)", c.min_depth_m);
  Require(c.max_depth_m > c.min_depth_m, "max_depth_m", "> min_depth_m (metres)", c.max_depth_m);
  Require(c.fallback_every >= 1, "fallback_every", ">= 1 (frames)", c.fallback_every);
}

double SeenFraction(const View& a, const View& b, const Transform& T_b_a,
                    const KeyframeConfig& config) {
  if (!UsableDepth(a) || !UsableDepth(b)) {
    throw InputError("SeenFraction: views '" + a.name + "' and '" + b.name +
                     "' need depth (CV_32FC1, metres) and intrinsics");
  }
  const Intrinsics& ka = a.intrinsics;
  const Intrinsics& kb = b.intrinsics;
  const Eigen::Matrix3d R = T_b_a.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T_b_a.topRightCorner<3, 1>();
  long long total = 0, agree = 0;
  for (int v = 0; v < a.depth.rows; v += config.pixel_stride) {
    const float* row = a.depth.ptr<float>(v);
    for (int u = 0; u < a.depth.cols; u += config.pixel_stride) {
      const double z = row[u];
      if (!std::isfinite(z) || z <= config.min_depth_m || z >= config.max_depth_m) continue;
      ++total;
      const Eigen::Vector3d p_a((u - ka.cx) * z / ka.fx, (v - ka.cy) * z / ka.fy, z);
      const Eigen::Vector3d p = R * p_a + t;
      if (p.z() <= config.min_depth_m) continue;
      const double ub = std::round(kb.fx * p.x() / p.z() + kb.cx);
      const double vb = std::round(kb.fy * p.y() / p.z() + kb.cy);
      if (ub < 0 || vb < 0 || ub >= b.depth.cols || vb >= b.depth.rows) continue;
      const float d = b.depth.at<float>(static_cast<int>(vb), static_cast<int>(ub));
      if (std::isfinite(d) && d > 0 && std::abs(d - p.z()) < config.depth_tolerance_m) ++agree;
    }
  }
  return total == 0 ? 0.0 : static_cast<double>(agree) / static_cast<double>(total);
}

double Covisibility(const View& a, const Transform& T_world_a, const View& b,
                    const Transform& T_world_b, const KeyframeConfig& config) {
  const Transform T_b_a = T_world_b.inverse() * T_world_a;
  return std::min(SeenFraction(a, b, T_b_a, config),
                  SeenFraction(b, a, T_world_a.inverse() * T_world_b, config));
}

KeyframeSelector::KeyframeSelector(const KeyframeConfig& config) : config_(config) {
  ValidateKeyframeConfig(config_);
}

bool KeyframeSelector::Add(const View& frame, const std::optional<Transform>& T_world_camera) {
  last_covisibility_.reset();
  ++frames_seen_;
  bool keyframe = false;
  if (frames_seen_ == 1) {
    keyframe = true;
  } else if (T_world_camera && keyframe_pose_ && UsableDepth(frame) && UsableDepth(keyframe_)) {
    last_covisibility_ = Covisibility(frame, *T_world_camera, keyframe_, *keyframe_pose_, config_);
    keyframe = *last_covisibility_ < config_.covisibility_threshold;
  } else {
    keyframe = since_keyframe_ + 1 >= config_.fallback_every;
  }
  if (!keyframe) {
    ++since_keyframe_;
    return false;
  }
  since_keyframe_ = 0;
  keyframe_ = View();
  keyframe_.name = frame.name;
  keyframe_.depth = frame.depth;  // shares the pixels (cv::Mat), as a View copy would
  keyframe_.intrinsics = frame.intrinsics;
  keyframe_pose_ = T_world_camera;
  return true;
}

std::vector<int> SelectKeyframes(const std::vector<View>& frames,
                                 const std::vector<std::optional<Transform>>& poses,
                                 const KeyframeConfig& config) {
  if (!poses.empty() && poses.size() != frames.size()) {
    throw InputError("SelectKeyframes: " + std::to_string(poses.size()) + " poses for " +
                     std::to_string(frames.size()) +
                     " frames: expected one per frame, or none (every k-th frame)");
  }
  KeyframeSelector selector(config);
  std::vector<int> keyframes;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (selector.Add(frames[i], poses.empty() ? std::nullopt : poses[i])) {
      keyframes.push_back(static_cast<int>(i));
    }
  }
  return keyframes;
}

}  // namespace zeroreg
