// Shared helpers for the collision tests.
#pragma once

#include <random>
#include <vector>

#include "core/math.hpp"

namespace grip::test {

inline std::vector<Vec3> boxCorners(const Vec3& h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  return v;
}

inline Transform at(const Vec3& p, const Quat& q = Quat::Identity()) {
  return Transform{p, q};
}

inline Quat rot(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

// Deterministic pseudo-random points (fixed seed, fixed distribution code path).
inline std::vector<Vec3> randomPoints(int n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = (static_cast<double>(rng()) / 4294967295.0 * 2.0 - 1.0) * scale;
    v.push_back(p);
  }
  return v;
}

}  // namespace grip::test
