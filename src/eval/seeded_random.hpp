#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>

namespace zeroreg {

// A double in [0, 1) from the generator's top 53 bits: the same numbers on every standard library
// (std::uniform_real_distribution's algorithm is implementation-defined).
inline double Uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// A unit vector uniform on the sphere (Archimedes: z uniform in [-1, 1], longitude uniform).
inline Eigen::Vector3d UniformUnitVector(std::mt19937_64& rng) {
  const double z = 2.0 * Uniform01(rng) - 1.0;
  const double longitude = 2.0 * M_PI * Uniform01(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(longitude), r * std::sin(longitude), z};
}

}  // namespace zeroreg
