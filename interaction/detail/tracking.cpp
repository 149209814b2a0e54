#include "interaction/tracking.hpp"

namespace grip {

namespace {

// A bone frame with +Y along `dir` and +Z as close to `dorsal` (out of the back of the hand) as
// possible; the same convention poseHand uses.
Quat boneFrame(const Vec3& dir, const Vec3& dorsal) {
  Vec3 y = dir.normalized();
  Vec3 z = dorsal - dorsal.dot(y) * y;
  if (z.squaredNorm() < 1e-12) {
    Vec3 t1, t2;
    tangentBasis(y, t1, t2);
    z = t1;
  }
  z.normalize();
  Mat3 m;
  m.col(0) = y.cross(z);
  m.col(1) = y;
  m.col(2) = z;
  return Quat(m).normalized();
}

Transform boneBetween(const Vec3& a, const Vec3& b, const Vec3& dorsal) {
  Transform t;
  t.p = 0.5 * (a + b);
  t.q = boneFrame(b - a, dorsal);
  return t;
}

constexpr std::array<std::array<int, 4>, 5> kXrChains = {{
    {2, 3, 4, 5},      // thumb: metacarpal, proximal, distal, tip
    {7, 8, 9, 10},     // index: proximal, intermediate, distal, tip
    {12, 13, 14, 15},  // middle
    {17, 18, 19, 20},  // ring
    {22, 23, 24, 25},  // little
}};

}  // namespace

HandPose fromOpenXR(const OpenXRHandFrame& frame) {
  HandPose pose;
  if (!frame.isActive) return pose;
  for (int j = 0; j < kXrJointCount; ++j) {
    if (!frame.valid[j] || !isFinite(frame.joints[j])) return pose;
  }
  const Transform& palm = frame.joints[0];
  pose.bones[kPalmBone] = {palm.p, palm.q.normalized()};
  for (int f = 0; f < 5; ++f) {
    for (int seg = 0; seg < 3; ++seg) {
      const Transform& a = frame.joints[kXrChains[f][seg]];
      const Transform& b = frame.joints[kXrChains[f][seg + 1]];
      pose.bones[boneIndex(Finger(f), seg)] = boneBetween(a.p, b.p, a.q * Vec3::UnitY());
    }
  }
  pose.tracked = true;
  return pose;
}

Transform leapToWorld(const LeapConversion& c) {
  Mat3 deviceToHead = Mat3::Identity();
  if (c.hmdMode) deviceToHead << -1, 0, 0, 0, 0, -1, 0, -1, 0;  // thesis 3.8.1
  const Quat tilt = Quat(Eigen::AngleAxisd(c.mountTilt.x(), Vec3::UnitX())) *
                    Quat(Eigen::AngleAxisd(c.mountTilt.y(), Vec3::UnitY())) *
                    Quat(Eigen::AngleAxisd(c.mountTilt.z(), Vec3::UnitZ()));
  Transform mount;
  mount.p = c.mountOffset;
  mount.q = tilt * Quat(deviceToHead);
  return c.hmdPose * mount;
}

Vec3 leapPointToWorld(const LeapConversion& c, const Vec3& mm) {
  Vec3 x = 0.001 * mm;
  if (c.sourceLeftHanded) x.z() = -x.z();
  return leapToWorld(c).apply(x);
}

HandPose fromLeap(const LeapHandFrame& frame, const LeapConversion& c) {
  HandPose pose;
  if (!frame.isTracked) return pose;
  const Transform toWorld = leapToWorld(c);
  auto point = [&](const Vec3& mm) {
    Vec3 x = 0.001 * mm;
    if (c.sourceLeftHanded) x.z() = -x.z();
    return toWorld.apply(x);
  };
  auto direction = [&](Vec3 d) {
    if (c.sourceLeftHanded) d.z() = -d.z();
    return toWorld.rotate(d);
  };
  const Vec3 dorsal = -direction(frame.palmNormal);
  const Vec3 forward = direction(frame.palmDirection);
  // Palm frame: +Y dorsal, -Z toward the fingers.
  Vec3 y = dorsal.normalized();
  Vec3 z = -(forward - forward.dot(y) * y);
  if (!y.allFinite() || z.squaredNorm() < 1e-12) return pose;
  z.normalize();
  Mat3 m;
  m.col(0) = y.cross(z);
  m.col(1) = y;
  m.col(2) = z;
  pose.bones[kPalmBone] = {point(frame.palmPosition), Quat(m).normalized()};
  for (int f = 0; f < 5; ++f) {
    for (int seg = 0; seg < 3; ++seg) {
      const LeapBone& b = frame.digits[f][seg + 1];  // skip the metacarpal
      pose.bones[boneIndex(Finger(f), seg)] =
          boneBetween(point(b.prevJoint), point(b.nextJoint), dorsal);
    }
  }
  pose.tracked = isFinite(pose);
  return pose;
}

}  // namespace grip
