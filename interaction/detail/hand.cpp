#include "interaction/hand.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace grip {

namespace {

Quat axisAngle(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(angle, axis));
}

// Bone frames carry their axis along +Y; the finger rest direction is the palm's -Z.
const Quat kAlongFingers = axisAngle(-0.5 * kPi, Vec3::UnitX());

double thumbSide(Handedness h) {
  return h == Handedness::Right ? -1.0 : 1.0;
}

// Knuckle (first joint) of each finger in the palm frame of a right hand at scale 1, x mirrored
// for the left hand. The thumb's first joint (CMC) sits on the palm side near the wrist.
const std::array<Vec3, 5> kKnuckles = {{
    {0.030, -0.010, 0.020},  // thumb (x toward the thumb side, see thumbSide)
    {0.027, 0.0, -0.047},    // index
    {0.008, 0.0, -0.047},    // middle
    {-0.011, 0.0, -0.045},   // ring
    {-0.029, 0.0, -0.040},   // pinky
}};

// The thumb leaves the palm toward the thumb side and palm side, rolled so that its flexion
// closes toward the index finger.
constexpr double kThumbYaw = 0.75;
constexpr double kThumbPitch = 0.45;
constexpr double kThumbRoll = 1.0;

}  // namespace

const char* boneName(int bone) {
  static const char* names[kBonesPerHand] = {
      "palm",          "thumb_metacarpal", "thumb_proximal",
      "thumb_distal",  "index_proximal",   "index_intermediate",
      "index_distal",  "middle_proximal",  "middle_intermediate",
      "middle_distal", "ring_proximal",    "ring_intermediate",
      "ring_distal",   "pinky_proximal",   "pinky_intermediate",
      "pinky_distal"};
  return bone >= 0 && bone < kBonesPerHand ? names[bone] : "unknown";
}

void validate(const HandDef& def) {
  requirePositive(def.scale, "HandDef.scale");
  for (int i = 0; i < 3; ++i) requirePositive(def.palmHalfExtents[i], "HandDef.palmHalfExtents");
  for (const FingerSize& f : def.fingers) {
    for (int s = 0; s < 3; ++s) {
      requirePositive(f.length[s], "HandDef.fingers.length");
      requirePositive(f.radius[s], "HandDef.fingers.radius");
      if (f.radius[s] * 2.0 > f.length[s] * 1.5) {
        throw Error("HandDef.fingers.radius", "is too large for its segment length");
      }
    }
  }
}

HandShapes makeHandShapes(const HandDef& def) {
  validate(def);
  HandShapes s;
  s.bones[kPalmBone] = Shape::box(def.scale * def.palmHalfExtents);
  s.halfLength[kPalmBone] = def.scale * def.palmHalfExtents.z();
  for (int f = 0; f < 5; ++f) {
    for (int seg = 0; seg < 3; ++seg) {
      const double len = def.scale * def.fingers[f].length[seg];
      const double r = def.scale * def.fingers[f].radius[seg];
      // The capsule spans joint to joint; the distal one ends at the fingertip (its rounded cap
      // is the finger pad), so its axis stops one radius short of the tip.
      const double axisHalf = isDistal(boneIndex(Finger(f), seg)) ? 0.5 * len - 0.5 * r : 0.5 * len;
      s.bones[boneIndex(Finger(f), seg)] = Shape::capsule(r, std::max(axisHalf, 0.25 * len));
      s.halfLength[boneIndex(Finger(f), seg)] = 0.5 * len;
    }
  }
  return s;
}

bool isFinite(const HandPose& p) {
  for (const Transform& t : p.bones) {
    if (!isFinite(t)) return false;
  }
  return true;
}

const char* graspPoseName(GraspPose p) {
  switch (p) {
    case GraspPose::Open:
      return "open";
    case GraspPose::Pinch:
      return "pinch";
    case GraspPose::Power:
      return "power";
    case GraspPose::Flat:
      return "flat";
    case GraspPose::Point:
      return "point";
  }
  return "unknown";
}

HandShape handShape(GraspPose p) {
  switch (p) {
    case GraspPose::Open:
      return {{{0.35, {0.15, 0.1, 0.1}},
               {0.12, {0.12, 0.10, 0.05}},
               {0.0, {0.12, 0.10, 0.05}},
               {-0.12, {0.12, 0.10, 0.05}},
               {-0.25, {0.12, 0.10, 0.05}}}};
    case GraspPose::Flat:
      return {{{0.15, {0.0, 0.0, 0.0}},
               {0.03, {0.0, 0.0, 0.0}},
               {0.0, {0.0, 0.0, 0.0}},
               {-0.03, {0.0, 0.0, 0.0}},
               {-0.06, {0.0, 0.0, 0.0}}}};
    case GraspPose::Pinch:
      return {{{0.0, {0.55, 0.35, 0.3}},
               {0.05, {0.75, 0.55, 0.25}},
               {0.0, {0.8, 0.9, 0.5}},
               {-0.08, {0.9, 1.0, 0.6}},
               {-0.15, {1.0, 1.1, 0.6}}}};
    case GraspPose::Power:
      return {{{-0.2, {0.7, 0.5, 0.4}},
               {0.0, {1.0, 1.2, 0.7}},
               {0.0, {1.0, 1.2, 0.7}},
               {0.0, {1.0, 1.2, 0.7}},
               {0.0, {1.0, 1.2, 0.7}}}};
    case GraspPose::Point:
      return {{{-0.1, {0.8, 0.8, 0.5}},
               {0.05, {0.0, 0.0, 0.0}},
               {0.0, {1.4, 1.6, 1.0}},
               {0.0, {1.4, 1.6, 1.0}},
               {0.0, {1.4, 1.6, 1.0}}}};
  }
  return handShape(GraspPose::Open);
}

HandShape blend(const HandShape& a, const HandShape& b, double t) {
  HandShape r;
  for (int f = 0; f < 5; ++f) {
    r[f].spread = (1.0 - t) * a[f].spread + t * b[f].spread;
    for (int j = 0; j < 3; ++j) r[f].flex[j] = (1.0 - t) * a[f].flex[j] + t * b[f].flex[j];
  }
  return r;
}

HandPose poseHand(const HandDef& def, const Transform& palm, const HandShape& shape) {
  HandPose pose;
  pose.tracked = true;
  pose.bones[kPalmBone] = palm;
  const double side = thumbSide(def.side);
  for (int f = 0; f < 5; ++f) {
    const Vec3& k = kKnuckles[f];
    // Mirror across x so that +x in kKnuckles is the thumb side for both hands.
    Vec3 joint = palm.apply(def.scale * Vec3(side * k.x(), k.y(), k.z()));
    Quat q;
    if (f == 0) {
      q = palm.q * axisAngle(-side * (kThumbYaw + shape[0].spread), Vec3::UnitY()) *
          axisAngle(-kThumbPitch, Vec3::UnitX()) * kAlongFingers *
          axisAngle(side * kThumbRoll, Vec3::UnitY());
    } else {
      q = palm.q * axisAngle(-side * shape[f].spread, Vec3::UnitY()) * kAlongFingers;
    }
    for (int seg = 0; seg < 3; ++seg) {
      q = q * axisAngle(-shape[f].flex[seg], Vec3::UnitX());
      const double len = def.scale * def.fingers[f].length[seg];
      const Vec3 axis = q * Vec3::UnitY();
      Transform& bone = pose.bones[boneIndex(Finger(f), seg)];
      bone.q = q;
      bone.p = joint + 0.5 * len * axis;
      joint += len * axis;
    }
  }
  return pose;
}

Vec3 fingertip(const HandDef& def, const HandPose& pose, Finger f) {
  const int b = boneIndex(f, 2);
  const double len = def.scale * def.fingers[static_cast<int>(f)].length[2];
  return pose.bones[b].apply(Vec3(0.0, 0.5 * len, 0.0));
}

}  // namespace grip
