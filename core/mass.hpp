// Mass properties of the primitive shapes and of closed triangle meshes (convex hulls and
// the preprocessing tool's meshes). Inertia is about the centre of mass, in the shape frame.
#pragma once

#include <array>
#include <vector>

#include "core/math.hpp"

namespace grip {

struct MassProperties {
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();  // about com
  double volume = 0.0;
};

MassProperties sphereMass(double radius, double density);
MassProperties boxMass(const Vec3& halfExtents, double density);
// Capsule along the local Y axis: a segment of length 2*halfHeight swept by radius.
MassProperties capsuleMass(double radius, double halfHeight, double density);
// A closed, outward-oriented triangle mesh (exact, by signed tetrahedra).
MassProperties meshMass(const std::vector<Vec3>& vertices,
                        const std::vector<std::array<int, 3>>& triangles, double density);

// Inertia of `m` moved so that it is taken about `point` instead of the centre of mass
// (parallel axis theorem) and rotated into another frame by `q`.
Mat3 shiftInertia(const Mat3& inertiaAboutCom, double mass, const Vec3& comToPoint);
Mat3 rotateInertia(const Mat3& inertia, const Quat& q);

}  // namespace grip
