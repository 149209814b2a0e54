// Narrowphase: contact manifolds between two shapes. Stateless and deterministic: the same
// inputs give the same points in the same order, with feature ids that stay the same while the
// same features touch (the solver matches them to warm start).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "collision/shape.hpp"

namespace grip {

struct ContactPoint {
  Vec3 position = Vec3::Zero();  // world, midway between the two surfaces
  double separation = 0.0;       // signed distance along the normal; negative = overlap
  uint32_t featureId = 0;        // stable id of the touching feature pair
};

struct Manifold {
  Vec3 normal = Vec3::UnitY();  // world, unit, pointing from shape A to shape B
  std::array<ContactPoint, 4> points{};
  int pointCount = 0;
  uint32_t childA = 0, childB = 0;  // compound child indices (0 for non-compounds)
};

// Appends one manifold per touching (child, child) pair whose separation is below `margin`
// (speculative contacts). A plane may only be shape A or B against a non-plane.
// Returns the number of manifolds appended.
int collide(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double margin,
            std::vector<Manifold>& out);

// The same for two convex shapes only: writes at most one manifold; false when farther apart
// than margin.
bool collideConvex(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                   double margin, Manifold& out);

}  // namespace grip
