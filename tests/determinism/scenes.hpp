// Scenes whose state hashes are compared: run twice in one process (determinism_test.cpp),
// against checked-in golden values, and between a g++ and a clang++ build (hash_scenes.cpp,
// scripts/compare_compilers.sh).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dynamics/scenes.hpp"
#include "dynamics/world.hpp"

namespace grip::determinism {

struct HashScene {
  std::string name;
  std::function<uint64_t()> run;  // builds the scene, steps it, returns runHash()
};

// A hash of the whole run: every step's World::stateHash(), so a difference that later
// settles away is still seen.
inline uint64_t runHash(World& w, int steps, double dt = 1.0 / 60.0) {
  StateHash h;
  for (int i = 0; i < steps; ++i) {
    w.step(dt);
    h.add(w.stateHash());
  }
  return h.value();
}

inline BodyId addDynamic(World& w, const ShapePtr& shape, const Vec3& p,
                         const Vec3& v = Vec3::Zero(), const Quat& q = Quat::Identity()) {
  BodyDef d;
  d.shape = shape;
  d.position = p;
  d.orientation = q;
  d.linearVelocity = v;
  return w.createBody(d);
}

inline uint64_t pile200() {
  World w;
  scenes::addGround(w);
  scenes::addBoxPile(w, 200);
  return runHash(w, 180);
}

inline uint64_t stack20() {
  WorldDef def;
  def.relaxIterations = 4;
  World w(def);
  scenes::addGround(w);
  scenes::addBoxStack(w, 20);
  return runHash(w, 180);
}

inline uint64_t ballIntoStack() {
  World w;
  scenes::addGround(w);
  scenes::addBoxStack(w, 10);
  addDynamic(w, Shape::sphere(0.15), Vec3(-3, 1, 0.02), Vec3(8, 2, 0));
  return runHash(w, 240);
}

// A box sliding down a 30 degree slope beside a rolling sphere and capsule.
inline uint64_t incline() {
  World w;
  const Quat q(Eigen::AngleAxisd(30.0 * kPi / 180.0, Vec3::UnitZ()));
  BodyDef slope;
  slope.type = BodyType::Static;
  slope.shape = Shape::box(Vec3(20, 0.5, 2));
  slope.orientation = q;
  slope.material = {0.5, 0.3, 0.0, 1000.0};
  w.createBody(slope);
  const Vec3 up = q * Vec3::UnitY();
  addDynamic(w, Shape::box(Vec3::Constant(0.1)), up * 0.6, Vec3::Zero(), q);
  addDynamic(w, Shape::sphere(0.1), up * 0.6 + Vec3(0, 0, 0.5));
  addDynamic(w, Shape::capsule(0.05, 0.1), up * 0.6 + Vec3(0, 0, -0.5), Vec3::Zero(),
             q * Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX())));
  return runHash(w, 180);
}

// Every shape type (convex hulls go through libccd), restitution, and sleeping then waking.
inline uint64_t mixed() {
  World w;
  scenes::addGround(w);
  const ShapePtr hull = Shape::convexHull({{0.1, 0, 0},
                                           {-0.1, 0, 0},
                                           {0, 0.12, 0},
                                           {0, -0.05, 0.1},
                                           {0, -0.05, -0.1},
                                           {0.03, 0.1, 0.04}});
  const ShapePtr rounded = Shape::box(Vec3(0.08, 0.04, 0.06), 0.01);
  for (int i = 0; i < 24; ++i) {
    const Vec3 p(0.15 * (i % 4) - 0.2, 0.3 + 0.25 * (i / 4), 0.11 * (i % 3) - 0.1);
    const Quat q(Eigen::AngleAxisd(0.37 * i, Vec3(1, 1, 0).normalized()));
    switch (i % 4) {
      case 0:
        addDynamic(w, hull, p, Vec3::Zero(), q);
        break;
      case 1:
        addDynamic(w, Shape::capsule(0.04, 0.08), p, Vec3::Zero(), q);
        break;
      case 2:
        addDynamic(w, Shape::sphere(0.06), p);
        break;
      default:
        addDynamic(w, rounded, p, Vec3::Zero(), q);
        break;
    }
  }
  BodyDef bouncy;
  bouncy.shape = Shape::sphere(0.05);
  bouncy.position = Vec3(1, 1.5, 0);
  bouncy.material.restitution = 0.6;
  const BodyId ball = w.createBody(bouncy);
  const uint64_t settle = runHash(w, 300);
  w.addForce(ball, Vec3(-3, 0, 0), ForceMode::Impulse);  // wakes the pile when it arrives
  StateHash h;
  h.add(settle);
  h.add(runHash(w, 180));
  return h.value();
}

inline std::vector<HashScene> hashScenes() {
  return {{"pile200", pile200},
          {"stack20", stack20},
          {"ball_into_stack", ballIntoStack},
          {"incline", incline},
          {"mixed", mixed}};
}

}  // namespace grip::determinism
