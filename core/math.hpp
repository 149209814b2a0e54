// grip core math: Eigen types in double precision, rigid transforms and small helpers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace grip {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;

inline constexpr double kPi = 3.14159265358979323846;

// A rigid transform: rotate by q, then translate by p.
struct Transform {
  Vec3 p = Vec3::Zero();
  Quat q = Quat::Identity();

  Vec3 apply(const Vec3& x) const { return q * x + p; }
  Vec3 applyInverse(const Vec3& x) const { return q.conjugate() * (x - p); }
  Vec3 rotate(const Vec3& v) const { return q * v; }
  Vec3 rotateInverse(const Vec3& v) const { return q.conjugate() * v; }
  Transform inverse() const {
    Transform t;
    t.q = q.conjugate();
    t.p = -(t.q * p);
    return t;
  }
  // (this * b) applies b first, then this.
  Transform operator*(const Transform& b) const {
    Transform t;
    t.q = q * b.q;
    t.p = q * b.p + p;
    return t;
  }
};

inline bool isFinite(double x) {
  return std::isfinite(x);
}
inline bool isFinite(const Vec3& v) {
  return v.allFinite();
}
inline bool isFinite(const Quat& q) {
  return q.coeffs().allFinite();
}
inline bool isFinite(const Mat3& m) {
  return m.allFinite();
}
inline bool isFinite(const Transform& t) {
  return isFinite(t.p) && isFinite(t.q);
}

inline Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Integrates an orientation by a constant angular velocity w over dt: the exact rotation by
// |w| dt about w (exponential map), so fast spins do not lose accuracy to a first-order step.
inline Quat integrateRotation(const Quat& q, const Vec3& w, double dt) {
  const double angle = w.norm() * dt;
  if (angle < 1e-12) return q;
  const double half = 0.5 * angle;
  const Vec3 axis = w * (std::sin(half) / w.norm());
  Quat r = Quat(std::cos(half), axis.x(), axis.y(), axis.z()) * q;
  r.normalize();
  return r;
}

// Two unit vectors orthogonal to n and to each other (right-handed: t1 x t2 = n).
inline void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2) {
  // Branch on the smallest component for a stable basis (Frisvad-style choice).
  if (std::abs(n.x()) >= 0.57735026919) {
    t1 = Vec3(n.y(), -n.x(), 0.0);
  } else {
    t1 = Vec3(0.0, n.z(), -n.y());
  }
  t1.normalize();
  t2 = n.cross(t1);
}

// Axis-aligned bounding box.
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();

  bool overlaps(const Aabb& b) const {
    return min.x() <= b.max.x() && max.x() >= b.min.x() && min.y() <= b.max.y() &&
           max.y() >= b.min.y() && min.z() <= b.max.z() && max.z() >= b.min.z();
  }
  bool contains(const Vec3& x) const {
    return (x.array() >= min.array()).all() && (x.array() <= max.array()).all();
  }
  Aabb inflated(double r) const { return {min - Vec3::Constant(r), max + Vec3::Constant(r)}; }
  Aabb merged(const Aabb& b) const { return {min.cwiseMin(b.min), max.cwiseMax(b.max)}; }
  // The box swept `distance` along the unit `dir` (an axis dir does not move stays put, also
  // for an infinite distance).
  Aabb sweptAlong(const Vec3& dir, double distance) const {
    Aabb out = *this;
    for (int k = 0; k < 3; ++k) {
      if (dir[k] > 0.0) out.max[k] += distance * dir[k];
      if (dir[k] < 0.0) out.min[k] += distance * dir[k];
    }
    return out;
  }
  Vec3 center() const { return 0.5 * (min + max); }
  Vec3 extent() const { return max - min; }
};

}  // namespace grip
