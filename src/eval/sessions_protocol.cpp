#include "eval/sessions_protocol.hpp"

#include "eval/seeded_random.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

namespace zeroreg {

Transform SeededUnalignment(std::uint64_t seed, double max_translation_m) {
  std::mt19937_64 rng(seed * 2654435761u + 1);
  // Shoemake's uniform random unit quaternion.
  const double u1 = Uniform01(rng), u2 = Uniform01(rng), u3 = Uniform01(rng);
  const Eigen::Quaterniond q(
      std::sqrt(u1) * std::cos(2 * M_PI * u3), std::sqrt(1 - u1) * std::sin(2 * M_PI * u2),
      std::sqrt(1 - u1) * std::cos(2 * M_PI * u2), std::sqrt(u1) * std::sin(2 * M_PI * u3));
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
  T.topRightCorner<3, 1>() = UniformUnitVector(rng) * (max_translation_m * Uniform01(rng));
  return T;
}

std::map<int, Transform> DriftedOdometry(const std::map<int, Transform>& ground_truth,
                                         std::uint64_t seed, double translation_fraction,
                                         double rotation_deg) {
  std::mt19937_64 rng(seed * 2654435761u + 2);
  std::map<int, Transform> out;
  const Transform* previous_truth = nullptr;
  Transform previous = Transform::Identity();
  for (const auto& [id, T] : ground_truth) {
    if (!previous_truth) {
      out[id] = T;
    } else {
      Transform motion = previous_truth->inverse() * T;
      Transform error = Transform::Identity();
      error.topLeftCorner<3, 3>() =
          Eigen::AngleAxisd(rotation_deg * M_PI / 180.0, UniformUnitVector(rng)).toRotationMatrix();
      error.topRightCorner<3, 1>() =
          UniformUnitVector(rng) * (translation_fraction * motion.topRightCorner<3, 1>().norm());
      out[id] = previous * motion * error;
    }
    previous_truth = &T;
    previous = out[id];
  }
  return out;
}

std::map<int, Transform> Moved(const Transform& T, const std::map<int, Transform>& poses) {
  std::map<int, Transform> out;
  for (const auto& [id, pose] : poses) out[id] = T * pose;
  return out;
}

double AbsoluteTrajectoryError(const std::map<int, Transform>& estimate,
                               const std::map<int, Transform>& ground_truth) {
  double sum = 0.0;
  int n = 0;
  for (const auto& [id, T] : estimate) {
    const auto it = ground_truth.find(id);
    if (it == ground_truth.end()) continue;
    sum += (T.topRightCorner<3, 1>() - it->second.topRightCorner<3, 1>()).squaredNorm();
    ++n;
  }
  return n ? std::sqrt(sum / n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace zeroreg
