// Geometric queries against one shape: ray casts and closest surface points.
#pragma once

#include <cstdint>

#include "collision/shape.hpp"

namespace grip {

struct RayHit {
  double distance = 0.0;        // along the unit direction
  Vec3 point = Vec3::Zero();    // world
  Vec3 normal = Vec3::UnitY();  // world, outward surface normal at the hit
  uint32_t child = 0;           // compound child hit (0 otherwise)
};

// First hit of the ray origin + t*dir, 0 <= t <= maxDistance, dir unit length. A ray starting
// inside a solid shape hits at t = 0 with the normal opposing dir.
bool rayCast(const Shape& s, const Transform& t, const Vec3& origin, const Vec3& dir,
             double maxDistance, RayHit& hit);
// The same restricted to one compound child (or the shape itself for non-compounds).
bool rayCastChild(const Shape& s, const Transform& t, uint32_t child, const Vec3& origin,
                  const Vec3& dir, double maxDistance, RayHit& hit);

// First contact of the convex shape `moving` (not a plane or compound) swept from `tm` along
// dir, 0 <= t <= maxDistance, with the shape s at t: hit.distance is how far it moved, point a
// point where they touch and normal the outward normal of s there (a compound: of the child
// hit first). A shape that starts touching or overlapping s hits at 0 with the normal
// opposing dir. dir is unit length.
bool shapeCast(const Shape& s, const Transform& t, const Shape& moving, const Transform& tm,
               const Vec3& dir, double maxDistance, RayHit& hit);

struct SurfacePoint {
  Vec3 point = Vec3::Zero();    // world, closest point on the surface
  Vec3 normal = Vec3::UnitY();  // world, outward
  double distance = 0.0;        // signed: negative when the query point is inside
  uint32_t child = 0;
};

// Closest point on the surface of the shape to `x` (planes, primitives, hulls, compounds; a
// compound with an SDF answers from the SDF). Always succeeds for valid shapes.
SurfacePoint closestPoint(const Shape& s, const Transform& t, const Vec3& x);

// The world-space centre of a compound child (or of the shape): where the thesis's contact ray
// is aimed.
Vec3 childCenter(const Shape& s, const Transform& t, uint32_t child);

}  // namespace grip
