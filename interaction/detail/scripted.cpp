#include "interaction/scripted.hpp"

#include <bit>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace grip {

namespace {

uint64_t splitmix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// A standard normal number determined by (seed, time, stream): Box-Muller on two hashed
// uniforms. Counter based, so the noise at time t does not depend on which frames came before.
double gaussian(uint64_t seed, double t, uint64_t stream) {
  const uint64_t base = splitmix(seed ^ splitmix(std::bit_cast<uint64_t>(t)) ^ (stream << 1));
  const double u1 = (static_cast<double>(splitmix(base) >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = (static_cast<double>(splitmix(base + 1) >> 11) + 0.5) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

HandShape shapeOf(const HandKeyframe& k) {
  return k.shape ? *k.shape : handShape(k.pose);
}

}  // namespace

ScriptedHand::ScriptedHand(ScriptedHandDef def) : def_(std::move(def)) {
  validate(def_.hand);
  if (def_.keys.empty()) throw Error("ScriptedHandDef.keys", "needs at least one keyframe");
  for (size_t i = 0; i < def_.keys.size(); ++i) {
    const HandKeyframe& k = def_.keys[i];
    requireFinite(k.time, "HandKeyframe.time");
    requireFinite(k.palm.p, "HandKeyframe.palm");
    requireFinite(k.palm.q, "HandKeyframe.palm");
    if (i > 0 && !(k.time > def_.keys[i - 1].time)) {
      throw Error("HandKeyframe.time", "keyframe times must increase strictly");
    }
  }
  for (auto& k : def_.keys) k.palm.q.normalize();
  requireNonNegative(def_.positionNoise, "ScriptedHandDef.positionNoise");
  requireNonNegative(def_.rotationNoise, "ScriptedHandDef.rotationNoise");
  for (const auto& [a, b] : def_.trackingLoss) {
    requireFinite(a, "ScriptedHandDef.trackingLoss");
    requireFinite(b, "ScriptedHandDef.trackingLoss");
    if (b < a) throw Error("ScriptedHandDef.trackingLoss", "interval ends before it starts");
  }
}

HandPose ScriptedHand::sample(double t) const {
  for (const auto& [a, b] : def_.trackingLoss) {
    if (t >= a && t <= b) return HandPose{};  // untracked
  }
  const auto& keys = def_.keys;
  size_t i = 0;
  while (i + 1 < keys.size() && keys[i + 1].time <= t) ++i;
  Transform palm = keys[i].palm;
  HandShape shape = shapeOf(keys[i]);
  if (i + 1 < keys.size() && t > keys[i].time) {
    const HandKeyframe& a = keys[i];
    const HandKeyframe& b = keys[i + 1];
    const double s = (t - a.time) / (b.time - a.time);
    palm.p = (1.0 - s) * a.palm.p + s * b.palm.p;
    palm.q = a.palm.q.slerp(s, b.palm.q);
    shape = blend(shapeOf(a), shapeOf(b), s);
  }
  HandPose pose = poseHand(def_.hand, palm, shape);
  if (def_.positionNoise > 0.0 || def_.rotationNoise > 0.0) {
    for (int b = 0; b < kBonesPerHand; ++b) {
      const uint64_t s = static_cast<uint64_t>(b) * 8;
      const Vec3 dp(gaussian(def_.seed, t, s), gaussian(def_.seed, t, s + 1),
                    gaussian(def_.seed, t, s + 2));
      const Vec3 dr(gaussian(def_.seed, t, s + 3), gaussian(def_.seed, t, s + 4),
                    gaussian(def_.seed, t, s + 5));
      pose.bones[b].p += def_.positionNoise * dp;
      const Vec3 rot = def_.rotationNoise * dr;
      if (rot.norm() > 0.0) {
        pose.bones[b].q =
            (Quat(Eigen::AngleAxisd(rot.norm(), rot.normalized())) * pose.bones[b].q).normalized();
      }
    }
  }
  return pose;
}

}  // namespace grip
