#include "eval/prior.hpp"

#include "eval/seeded_random.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace zeroreg {
namespace {

// FNV-1a: a fixed hash of the pair key (std::hash may differ between standard libraries).
std::uint64_t HashKey(const std::string& key) {
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : key) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

nlohmann::json PriorErrorToJson(const PriorError& e) {
  return {{"rotation_deg", e.rotation_deg},
          {"translation_m", e.translation_m},
          {"max_rotation_deg", e.max_rotation_deg},
          {"max_translation_m", e.max_translation_m}};
}

MotionPrior PriorOffTheTruth(const Transform& T_gt, const PriorError& error, std::uint64_t seed,
                             const std::string& pair_key) {
  std::mt19937_64 rng(HashKey(pair_key) ^ (seed * 0x9E3779B97F4A7C15ull));
  const Eigen::Vector3d axis = UniformUnitVector(rng);
  const Eigen::Vector3d direction = UniformUnitVector(rng);
  Transform offset = Transform::Identity();
  offset.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(error.rotation_deg * M_PI / 180.0, axis).toRotationMatrix();
  offset.topRightCorner<3, 1>() = error.translation_m * direction;
  MotionPrior prior;
  prior.T_target_source = T_gt * offset;
  prior.max_rotation_deg = error.max_rotation_deg;
  prior.max_translation_m = error.max_translation_m;
  return prior;
}

}  // namespace zeroreg
