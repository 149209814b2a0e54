#include "interaction/scenarios.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamics/scenes.hpp"

namespace grip::scenarios {

BodyId addFloor(World& w, double staticFriction, double dynamicFriction) {
  BodyDef d;
  d.type = BodyType::Static;
  d.shape = Shape::plane(Vec3::UnitY(), 0.0);
  d.material.staticFriction = staticFriction;
  d.material.dynamicFriction = dynamicFriction;
  d.name = "floor";
  return w.createBody(d);
}

BodyId addBox(World& w, const Vec3& halfExtents, double mass, const Vec3& position,
              const Quat& orientation, double staticFriction, double dynamicFriction) {
  BodyDef d;
  d.shape = Shape::box(halfExtents);
  d.mass = mass;
  d.position = position;
  d.orientation = orientation;
  d.material.staticFriction = staticFriction;
  d.material.dynamicFriction = dynamicFriction;
  d.name = "box";
  return w.createBody(d);
}

BodyId addCylinder(World& w, double radius, double halfLength, double mass, const Vec3& position,
                   const Quat& orientation, int sides) {
  if (sides < 3) throw Error("addCylinder.sides", "must be at least 3");
  std::vector<Vec3> pts;
  for (int i = 0; i < sides; ++i) {
    const double a = 2.0 * kPi * i / sides;
    for (double z : {-halfLength, halfLength}) {
      pts.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
  }
  BodyDef d;
  d.shape = Shape::convexHull(pts);
  d.mass = mass;
  d.position = position;
  d.orientation = orientation;
  d.name = "cylinder";
  return w.createBody(d);
}

Tower addTower(World& w, int layers) {
  return {scenes::addJengaTower(w, layers), Vec3(0.0375, 0.0075, 0.0125)};
}

HandPose parkedHand(const HandDef& def, const Vec3& where) {
  Transform palm;
  palm.p = where;
  return poseHand(def, palm, handShape(GraspPose::Open));
}

void pressBone(HandPose& pose, const HandDef& def, int bone, const Vec3& facePoint,
               const Vec3& faceNormal, const Vec3& axis, double depth) {
  const Vec3 n = faceNormal.normalized();
  Transform& t = pose.bones[bone];
  if (bone == kPalmBone) {
    // Palm side (-Y of the palm frame) against the face.
    const Vec3 y = n;
    Vec3 z = axis - axis.dot(y) * y;
    z.normalize();
    Mat3 m;
    m.col(0) = y.cross(z);
    m.col(1) = y;
    m.col(2) = z;
    t.q = Quat(m);
    t.p = facePoint + n * (def.scale * def.palmHalfExtents.y() - depth);
    return;
  }
  const int f = (bone - 1) / 3, seg = (bone - 1) % 3;
  const double r = def.scale * def.fingers[f].radius[seg];
  t.q = Quat::FromTwoVectors(Vec3::UnitY(), axis.normalized());
  t.p = facePoint + n * (r - depth);
}

namespace {

// The deepest penetration of one bone into one body (positive inside), or -inf apart.
double boneDepth(const World& w, BodyId body, const Shape& bone, const Transform& t,
                 std::vector<OverlapHit>& hits) {
  double depth = -std::numeric_limits<double>::infinity();
  w.overlap(bone, t, 0.0, hits);
  for (const OverlapHit& hit : hits) {
    if (hit.body != body) continue;
    for (int k = 0; k < hit.manifold.pointCount; ++k) {
      depth = std::max(depth, -hit.manifold.points[k].separation);
    }
  }
  return depth;
}

}  // namespace

HandShape closeHandOn(const World& w, BodyId body, const HandDef& def, const Transform& palm,
                      const HandShape& from, const HandShape& to, double squeeze, int steps) {
  if (steps < 1) throw Error("closeHandOn.steps", "must be at least 1");
  requireNonNegative(squeeze, "closeHandOn.squeeze");
  const HandShapes shapes = makeHandShapes(def);
  std::vector<OverlapHit> hits;
  HandShape shape = from;
  for (int f = 0; f < 5; ++f) shape[f].spread = to[f].spread;
  for (int f = 0; f < 5; ++f) {
    int moving = 0;  // joints [moving, 3) still close
    for (int i = 1; i <= steps && moving < 3; ++i) {
      HandShape next = shape;
      for (int j = moving; j < 3; ++j) {
        next[f].flex[j] = from[f].flex[j] + (to[f].flex[j] - from[f].flex[j]) * i / steps;
      }
      const HandPose pose = poseHand(def, palm, next);
      // The most proximal bone of the finger that reached the squeeze depth stops its joints.
      int stop = -1;
      for (int seg = moving; seg < 3 && stop < 0; ++seg) {
        const int b = boneIndex(Finger(f), seg);
        if (boneDepth(w, body, *shapes.bones[b], pose.bones[b], hits) >= squeeze) stop = seg;
      }
      shape = next;
      if (stop >= 0) moving = stop + 1;  // the joints up to the touching bone stay here
    }
  }
  return shape;
}

HandPose pinchCube(const HandDef& def, const Vec3& centre, double halfWidth, double depth) {
  HandPose pose = parkedHand(def);
  pressBone(pose, def, boneIndex(Finger::Thumb, 2), centre - halfWidth * Vec3::UnitX(),
            -Vec3::UnitX(), Vec3::UnitZ(), depth);
  pressBone(pose, def, boneIndex(Finger::Index, 2), centre + halfWidth * Vec3::UnitX(),
            Vec3::UnitX(), Vec3::UnitZ(), depth);
  return pose;
}

std::vector<HandPose> cubeHeldByPhalanges(const std::vector<HandDef>& defs, const Vec3& centre,
                                          double halfWidth, int phalanges, double depth) {
  if (phalanges < 1 || phalanges > 16 * static_cast<int>(defs.size())) {
    throw Error("phalanges", "must be between 1 and 16 per hand");
  }
  std::vector<HandPose> poses;
  for (const HandDef& d : defs) poses.push_back(parkedHand(d));
  // Slots on a face: two rows by four columns; bones alternate between opposite faces so that
  // the normal forces cancel pairwise.
  const double rows[2] = {-0.45, 0.45};
  const double cols[4] = {-0.75, -0.25, 0.25, 0.75};
  const Vec3 normals[4] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitZ(), -Vec3::UnitZ()};
  for (int i = 0; i < phalanges; ++i) {
    const int hand = i / 16, bone = i % 16;
    const int face = (i % 2) + 2 * ((i / 16) % 2);  // pairs on +-x, the second hand on +-z
    // Slot order: each next pair sits opposite the previous one on the face, so any number of
    // pairs is roughly centred.
    constexpr int kSlotOrder[8] = {5, 2, 1, 6, 4, 3, 0, 7};
    const int slot = kSlotOrder[(i % 16) / 2];
    const Vec3 n = normals[face];
    const Vec3 side = std::abs(n.x()) > 0.5 ? Vec3::UnitZ() : Vec3::UnitX();
    const Vec3 facePoint = centre + halfWidth * n + halfWidth * rows[slot / 4] * Vec3::UnitY() +
                           halfWidth * cols[slot % 4] * side;
    pressBone(poses[hand], defs[hand], bone, facePoint, n, Vec3::UnitY(), depth);
  }
  return poses;
}

HoldScene buildHoldScene(World& w, Interaction& ix, int phalanges, double depth) {
  HoldScene s;
  addFloor(w);
  for (int i = 0; i < 10; ++i) {
    const double x = -0.6 + 0.3 * (i % 5), z = i < 5 ? -0.4 : 0.4;
    s.boxes.push_back(addBox(w, Vec3::Constant(0.05), 1.0, Vec3(x, 0.05, z)));
  }
  const double half = 0.05;
  const Vec3 centre(0.0, 0.3, 0.0);
  s.cube = addBox(w, Vec3::Constant(half), 0.2, centre);
  const int handCount = (phalanges + 15) / 16;
  std::vector<HandDef> defs(handCount);
  for (int h = 0; h < handCount; ++h) {
    defs[h].side = h == 0 ? Handedness::Right : Handedness::Left;
    s.hands.push_back(ix.addHand(defs[h]));
  }
  s.poses = cubeHeldByPhalanges(defs, centre, half, phalanges, depth);
  for (int h = 0; h < handCount; ++h) ix.setHandPose(s.hands[h], s.poses[h]);
  return s;
}

}  // namespace grip::scenarios
