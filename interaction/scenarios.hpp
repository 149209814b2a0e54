// Hand-interaction scenes, written once and used by the tests, the benchmarks and the demo.
#pragma once

#include <vector>

#include "interaction/interaction.hpp"

namespace grip::scenarios {

// A static floor: the half space y <= 0.
BodyId addFloor(World& w, double staticFriction = 0.6, double dynamicFriction = 0.5);

// A dynamic box of the given half extents and mass.
BodyId addBox(World& w, const Vec3& halfExtents, double mass, const Vec3& position,
              const Quat& orientation = Quat::Identity(), double staticFriction = 0.6,
              double dynamicFriction = 0.5);

// A dynamic cylinder: a `sides`-sided prism of the given radius, its axis along the local z axis
// from -halfLength to +halfLength.
BodyId addCylinder(World& w, double radius, double halfLength, double mass, const Vec3& position,
                   const Quat& orientation = Quat::Identity(), int sides = 32);

// A Jenga-like tower on the floor: `layers` layers of 3 blocks (7.5 x 1.5 x 2.5 cm, 14 g, wood
// on wood mu_s 0.4, mu_d 0.35), each layer crossed with the one below; the even layers run along
// x. blocks[3 * layer + k], k = 0..2 from -z (or -x) to +z (or +x).
struct Tower {
  std::vector<BodyId> blocks;
  Vec3 blockHalfExtents;  // of an x-running block
};
Tower addTower(World& w, int layers);

// A hand pose whose bones are all far away from any scene (y = 10 m): start from it and place
// only the bones a test needs.
HandPose parkedHand(const HandDef& def, const Vec3& where = Vec3(0.0, 10.0, 0.0));

// Places a finger bone so that its capsule axis runs along `axis` and its surface sinks `depth`
// into a face with outward normal `faceNormal` through `facePoint` (a palm bone: its thickness
// along the normal). The bone's nearest surface point is then facePoint - depth * faceNormal.
void pressBone(HandPose& pose, const HandDef& def, int bone, const Vec3& facePoint,
               const Vec3& faceNormal, const Vec3& axis, double depth);

// Closes a hand on a body the way a grasp planner does (GraspIt's auto-grasp): from `from`
// toward `to`, the joints of each finger turn together in `steps` small steps; once a bone of
// the finger has sunk `squeeze` into the body, the joints up to that bone stop and the joints
// beyond it keep closing (so the finger wraps around the body). The palm stays at `palm`.
// Returns the joint angles where every finger stopped; the spread is taken from `to`.
HandShape closeHandOn(const World& w, BodyId body, const HandDef& def, const Transform& palm,
                      const HandShape& from, const HandShape& to, double squeeze, int steps = 400);

// Two opposing fingertips (thumb and index distal capsules, axes along z) squeezing the x faces
// of an axis-aligned cube of half width `halfWidth` centred at `centre`, each sunk `depth` into
// its face. The hold threshold of this pinch is 2 mu_s gamma depth = m g.
HandPose pinchCube(const HandDef& def, const Vec3& centre, double halfWidth, double depth);

// `phalanges` bones (1..32, two hands of 16) pressed `depth` into the four side faces of an
// axis-aligned cube, in opposing pairs, so that the cube is held. Fills `poses` with one pose per
// hand used and returns them.
std::vector<HandPose> cubeHeldByPhalanges(const std::vector<HandDef>& defs, const Vec3& centre,
                                          double halfWidth, int phalanges, double depth);

// The benchmark scene: a floor, ten boxes resting on it, and a 0.2 kg cube of edge 0.1 m at
// (0, 0.3, 0) held by `phalanges` contact phalanges (9-sample patches). The hands are added to
// `ix` and posed; returns the held cube.
struct HoldScene {
  BodyId cube;
  std::vector<BodyId> boxes;
  std::vector<HandId> hands;
  std::vector<HandPose> poses;
};
HoldScene buildHoldScene(World& w, Interaction& ix, int phalanges, double depth = 0.004);

}  // namespace grip::scenarios
