#include "eval/prior.hpp"

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

// A double in [0, 1) from the generator's top 53 bits.
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// A unit vector uniform on the sphere (Archimedes: z uniform in [-1, 1], longitude uniform).
Eigen::Vector3d UnitVector(std::mt19937_64& rng) {
  const double z = 2.0 * Uniform(rng) - 1.0;
  const double longitude = 2.0 * M_PI * Uniform(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(longitude), r * std::sin(longitude), z};
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
  const Eigen::Vector3d axis = UnitVector(rng);
  const Eigen::Vector3d direction = UnitVector(rng);
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
