// Helpers shared by the stress tests: finiteness checks and small scene builders.
#pragma once

#include <string>
#include <vector>

#include "dynamics/scenes.hpp"
#include "dynamics/world.hpp"

namespace grip::stress {

// True when every live body's pose and velocities are finite; names the first bad body.
inline bool allFinite(const World& w, std::string* bad = nullptr) {
  for (BodyId id : w.bodies()) {
    if (isFinite(w.pose(id)) && isFinite(w.linearVelocity(id)) && isFinite(w.angularVelocity(id)))
      continue;
    if (bad) *bad = "body " + std::to_string(id.index) + " '" + w.name(id) + "'";
    return false;
  }
  return true;
}

// The largest linear speed of any body.
inline double maxSpeed(const World& w) {
  double s = 0.0;
  for (BodyId id : w.bodies()) s = std::max(s, w.linearVelocity(id).norm());
  return s;
}

inline BodyId addBody(World& w, const ShapePtr& shape, const Vec3& position, double mass = 1.0,
                      BodyType type = BodyType::Dynamic) {
  BodyDef d;
  d.type = type;
  d.shape = shape;
  d.position = position;
  d.mass = type == BodyType::Dynamic ? mass : 0.0;
  return w.createBody(d);
}

}  // namespace grip::stress
