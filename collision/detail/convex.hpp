// Private: convex cores (a shape minus its rounding radius, placed in the world), GJK distance
// between two cores and penetration depth through libccd. Shared by narrowphase and queries.
#pragma once

#include "collision/shape.hpp"

namespace grip::detail {

// A convex shape reduced to its core: a point (sphere), a segment (capsule), a box or a hull.
// The full shape is the core grown by `radius`.
struct Core {
  const Shape* shape = nullptr;
  Transform t;
  double radius = 0.0;

  Core(const Shape& s, const Transform& tr) : shape(&s), t(tr), radius(s.radius()) {}
  // The core point farthest along a world direction (need not be unit).
  Vec3 support(const Vec3& dir) const;
  Vec3 center() const { return t.apply(shape->localCenter()); }
};

struct CoreDistance {
  bool overlap = false;  // the cores intersect (distance 0): use corePenetration
  double distance = 0.0;
  Vec3 pointA = Vec3::Zero(), pointB = Vec3::Zero();  // closest points on the cores
  // Unit direction A to B of the last non-zero GJK estimate; zero if there was none. When
  // the cores merely touch this is the contact normal, where EPA's answer is arbitrary.
  Vec3 direction = Vec3::Zero();
};

// GJK distance between two cores (fixed iteration cap, deterministic).
CoreDistance coreDistance(const Core& a, const Core& b);

// Closest point of a core to the point x (distance 0 with overlap set when x is inside).
CoreDistance pointDistance(const Core& a, const Vec3& x);

// Ray cast against a convex shape in its own frame, rounding included (GJK ray cast).
// Starting inside gives t = 0 and a zero normal. dir is unit length.
bool convexRayCast(const Shape& s, const Vec3& origin, const Vec3& dir, double maxDistance,
                   double& t, Vec3& normal);
// A convex shape moving along dir from movingPose (in the target's frame): the first t at which
// it touches the target, the target's outward normal and a point of the target's surface
// there. Starting in touch gives t = 0 and a zero normal. dir is unit length.
bool convexShapeCast(const Shape& target, const Shape& moving, const Transform& movingPose,
                     const Vec3& dir, double maxDistance, double& t, Vec3& normal, Vec3& point);

struct CorePenetration {
  bool ok = false;
  double depth = 0.0;           // >= 0
  Vec3 normal = Vec3::UnitY();  // from A to B: moving B by depth * normal separates the cores
  Vec3 point = Vec3::Zero();    // roughly the middle of the overlap
};

// Penetration depth of two intersecting cores via libccd (EPA, MPR as a fallback).
CorePenetration corePenetration(const Core& a, const Core& b);

}  // namespace grip::detail
