// The skeletal hand of the thesis (3.5.1): per hand 16 bones, a box palm and three capsules per
// finger. Bones are only used to find and drive contacts; they never become World bodies, so the
// engine's own contact resolution never sees them.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "collision/shape.hpp"
#include "core/math.hpp"

namespace grip {

enum class Handedness : uint8_t { Left, Right };
enum class Finger : uint8_t { Thumb, Index, Middle, Ring, Pinky };

inline constexpr int kBonesPerHand = 16;
inline constexpr int kPalmBone = 0;
// Bone index of a finger segment; segment 0 is nearest the palm (for the thumb: the metacarpal,
// as OpenXR and Leap Motion's thumb have no intermediate phalanx).
constexpr int boneIndex(Finger f, int segment) {
  return 1 + 3 * static_cast<int>(f) + segment;
}
constexpr bool isDistal(int bone) {
  return bone > 0 && (bone - 1) % 3 == 2;
}
// The thumb and the palm touch with a wider skin area (3.5.4).
constexpr bool hasWidePatch(int bone) {
  return bone <= boneIndex(Finger::Thumb, 2);
}
const char* boneName(int bone);

// Sizes of one finger: segment lengths (joint to joint, the distal one to the fingertip) and
// capsule radii, in metres.
struct FingerSize {
  std::array<double, 3> length{};
  std::array<double, 3> radius{};
};

// One hand. Defaults are an adult hand (about the 50th percentile of adult hand measurements:
// hand length ~19 cm, breadth ~8.5 cm); `scale` sizes all of it at once.
struct HandDef {
  Handedness side = Handedness::Right;
  double scale = 1.0;
  // Palm box half extents in the palm frame: x across the knuckles, y thickness, z wrist to
  // knuckles.
  Vec3 palmHalfExtents = Vec3(0.042, 0.013, 0.047);
  std::array<FingerSize, 5> fingers = {{
      {{0.046, 0.032, 0.030}, {0.0115, 0.0105, 0.0095}},  // thumb: metacarpal, proximal, distal
      {{0.040, 0.024, 0.022}, {0.0095, 0.0088, 0.0082}},  // index
      {{0.045, 0.028, 0.023}, {0.0098, 0.0090, 0.0084}},  // middle
      {{0.042, 0.027, 0.023}, {0.0092, 0.0085, 0.0080}},  // ring
      {{0.033, 0.019, 0.020}, {0.0082, 0.0076, 0.0072}},  // pinky
  }};
  std::string name;
};

// Throws grip::Error naming the bad field (non-finite or non-positive sizes).
void validate(const HandDef& def);

// The collision shape of each bone, in the bone's own frame: the palm is a box centred on its
// frame, each finger bone a capsule along its local +Y axis centred between its joints.
struct HandShapes {
  std::array<ShapePtr, kBonesPerHand> bones;
  std::array<double, kBonesPerHand> halfLength{};  // along +Y (palm: half extent z)
};
HandShapes makeHandShapes(const HandDef& def);

// One tracked pose of a hand: the world transform of each bone's frame. The palm frame follows
// OpenXR's palm joint: +Y out of the back of the hand, -Z from wrist toward the fingers, +X to
// the right for both hands. Finger bone frames carry their capsule along +Y toward the tip.
struct HandPose {
  std::array<Transform, kBonesPerHand> bones{};
  bool tracked = false;  // false: no data this frame (tracking lost)
};
bool isFinite(const HandPose& p);

// Joint angles of one finger (radians): spread about the palm normal, flexion of each joint
// (positive curls toward the palm side).
struct FingerJoints {
  double spread = 0.0;
  std::array<double, 3> flex{};
};
using HandShape = std::array<FingerJoints, 5>;

enum class GraspPose : uint8_t { Open, Pinch, Power, Flat, Point };
const char* graspPoseName(GraspPose p);
HandShape handShape(GraspPose p);
HandShape blend(const HandShape& a, const HandShape& b, double t);

// Forward kinematics: the bone frames of a hand whose palm frame is `palm` and whose fingers take
// the joint angles `shape`.
HandPose poseHand(const HandDef& def, const Transform& palm, const HandShape& shape);
// Where each fingertip ends up (the far end of the distal capsule axis), for placing hands.
Vec3 fingertip(const HandDef& def, const HandPose& pose, Finger f);

}  // namespace grip
