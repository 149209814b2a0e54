// Input adapters: tracked hand data in a device's convention -> grip's HandPose (metres,
// right-handed, Y up). Conversions happen here and nowhere else.
#pragma once

#include <array>

#include "interaction/hand.hpp"

namespace grip {

// ---- OpenXR XR_EXT_hand_tracking ------------------------------------------------------------

// The 26 joints of XrHandJointEXT, in its order.
enum class XrJoint : int {
  Palm = 0,
  Wrist,
  ThumbMetacarpal,
  ThumbProximal,
  ThumbDistal,
  ThumbTip,
  IndexMetacarpal,
  IndexProximal,
  IndexIntermediate,
  IndexDistal,
  IndexTip,
  MiddleMetacarpal,
  MiddleProximal,
  MiddleIntermediate,
  MiddleDistal,
  MiddleTip,
  RingMetacarpal,
  RingProximal,
  RingIntermediate,
  RingDistal,
  RingTip,
  LittleMetacarpal,
  LittleProximal,
  LittleIntermediate,
  LittleDistal,
  LittleTip,
};
inline constexpr int kXrJointCount = 26;

// One XrHandJointLocationsEXT: joint poses in metres in the app's (right-handed) reference
// space; each joint's -Z points from the joint toward the fingertip, +Y out of the back of the
// hand.
struct OpenXRHandFrame {
  bool isActive = false;
  std::array<Transform, kXrJointCount> joints{};
  std::array<bool, kXrJointCount> valid{};  // position and orientation valid
};

// Bones from joints: each finger bone spans two consecutive joints (the thumb uses metacarpal,
// proximal, distal; the fingers proximal, intermediate, distal), the palm is the palm joint.
// An inactive frame or a missing joint gives an untracked pose (tracking lost this frame).
// Bone sizes come from the HandDef, not from the frame.
HandPose fromOpenXR(const OpenXRHandFrame& frame);

// ---- Leap Motion ----------------------------------------------------------------------------

struct LeapBone {
  Vec3 prevJoint = Vec3::Zero();  // mm, Leap device frame (right-handed)
  Vec3 nextJoint = Vec3::Zero();
};
// One Leap hand: per digit metacarpal, proximal, intermediate, distal (the thumb's metacarpal
// has zero length, as Leap reports it), palm position/normal/direction, all in millimetres.
struct LeapHandFrame {
  bool isTracked = false;
  bool isLeft = false;
  Vec3 palmPosition = Vec3::Zero();
  Vec3 palmNormal = -Vec3::UnitY();     // out of the palm
  Vec3 palmDirection = -Vec3::UnitZ();  // wrist toward fingers
  std::array<std::array<LeapBone, 4>, 5> digits{};
};

// The thesis's 3.8.1 chain, right-handed (grip needs no z flip; `sourceLeftHanded` flips z for
// data recorded from a left-handed engine such as Unity):
//   x_world = hmdPose * T_mount * R_mount * M_desktop->hmd * S_mm->m * x_leap,
// M_desktop->hmd = [[-1,0,0],[0,0,-1],[0,-1,0]] when the device is mounted on a headset,
// R_mount = Rx(alpha) Ry(beta) Rz(gamma) for tilted mounts.
struct LeapConversion {
  bool hmdMode = true;
  Vec3 mountOffset = Vec3::Zero();  // metres, in the headset frame (see the presets)
  Vec3 mountTilt = Vec3::Zero();    // (alpha, beta, gamma) radians about x, y, z
  Transform hmdPose;                // the headset in the world (identity: world = view)
  bool sourceLeftHanded = false;
  // The thesis's mounts. Its offsets are in Unity's left-handed frame (+z forward); grip's
  // headset frame looks down -z, so z changes sign here.
  static LeapConversion riftDK2() { return {true, Vec3(0.0, 0.0, -0.08), Vec3::Zero(), {}, false}; }
  static LeapConversion holoLens() {
    return {true, Vec3(0.0, 0.07, -0.05), Vec3::Zero(), {}, false};
  }
  static LeapConversion desktop() { return {false, Vec3::Zero(), Vec3::Zero(), {}, false}; }
};

// The rigid part of the chain as one transform (the mm->m scale is applied before it).
Transform leapToWorld(const LeapConversion& c);
Vec3 leapPointToWorld(const LeapConversion& c, const Vec3& mm);
HandPose fromLeap(const LeapHandFrame& frame, const LeapConversion& c);

}  // namespace grip
