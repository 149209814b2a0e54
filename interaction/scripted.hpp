// Scripted hands for tests, demos and benchmarks: keyframed grasp poses along a global path,
// with optional seeded tracking noise and tracking-loss intervals. sample(t) is a pure function
// of t, so a script replays bit for bit.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "interaction/hand.hpp"

namespace grip {

struct HandKeyframe {
  double time = 0.0;
  Transform palm;  // palm frame in the world
  GraspPose pose = GraspPose::Open;
  std::optional<HandShape> shape;  // explicit joint angles instead of `pose`
};

struct ScriptedHandDef {
  HandDef hand;
  std::vector<HandKeyframe> keys;  // strictly increasing times
  // Tracking noise: independent Gaussian jitter per bone and frame (std. dev., metres and
  // radians), from `seed`. Zero: none.
  double positionNoise = 0.0;
  double rotationNoise = 0.0;
  uint64_t seed = 1;
  // Closed intervals [start, end] in seconds during which the hand is not tracked.
  std::vector<std::pair<double, double>> trackingLoss;
};

class ScriptedHand {
 public:
  explicit ScriptedHand(ScriptedHandDef def);  // validates, throws grip::Error
  // The pose at time t: palm position interpolated linearly, orientation by slerp, joint angles
  // linearly; held constant before the first and after the last key.
  HandPose sample(double t) const;
  const ScriptedHandDef& def() const { return def_; }

 private:
  ScriptedHandDef def_;
};

}  // namespace grip
