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
