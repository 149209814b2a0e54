// grip behind the sweep's Sim interface, and the grid grip is swept over.
#include <algorithm>

#include "dynamics/scenes.hpp"
#include "dynamics/world.hpp"
#include "sweep/sweep.hpp"

namespace grip::sweep {

namespace {

class GripSim : public Sim {
 public:
  GripSim(const SceneDef& sc, const Settings& s, int threads = 1)
      : world_(def(sc, s, threads)), dt_(s.dt) {
    // The ground's friction is 1: grip combines by the geometric mean, and each solid is
    // given the square of its coefficient, so a pair gets the product (see SolidDef).
    if (sc.ground) scenes::addGround(world_, 1.0, 1.0);
  }
  int add(const SolidDef& s) override {
    BodyDef d;
    d.shape = s.sphere ? Shape::sphere(s.radius) : Shape::box(s.halfExtents);
    d.mass = s.mass;
    d.position = s.position;
    d.orientation = s.orientation;
    d.linearVelocity = s.linearVelocity;
    d.angularVelocity = s.angularVelocity;
    d.material.staticFriction = d.material.dynamicFriction = s.friction * s.friction;
    d.material.restitution = s.restitution;  // grip takes the larger; the ground has 0
    if (!s.collides) d.filter.mask = 0;
    ids_.push_back(world_.createBody(d));
    return static_cast<int>(ids_.size()) - 1;
  }
  void addForce(int body, const Vec3& f) override { world_.addForce(ids_[body], f); }
  void joinBall(int a, int b, const Vec3& anchor) override {
    JointDef j;
    j.a = a >= 0 ? ids_[a] : fixedPoint(anchor);
    j.b = ids_[b];
    j.anchor = anchor;
    world_.createJoint(j);
  }
  void step() override { world_.step(dt_); }
  Vec3 position(int body) const override { return world_.pose(ids_[body]).p; }
  Quat orientation(int body) const override { return world_.pose(ids_[body]).q; }
  Vec3 linearVelocity(int body) const override { return world_.linearVelocity(ids_[body]); }
  Vec3 angularVelocity(int body) const override { return world_.angularVelocity(ids_[body]); }

 private:
  // A static body to hang joints on, touching nothing.
  BodyId fixedPoint(const Vec3& at) {
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = Shape::sphere(0.01);
    d.position = at;
    d.filter.mask = 0;
    return world_.createBody(d);
  }
  static WorldDef def(const SceneDef& sc, const Settings& s, int threads) {
    WorldDef d;
    d.workerThreads = threads;
    d.gravity = sc.gravity;
    d.substeps = s.substeps;
    d.maxSubstep = std::max(d.maxSubstep, s.dt / s.substeps);  // the setting swept, as it is
    d.relaxIterations = s.iterations;
    d.enableSleep = sc.sleep;
    return d;
  }
  World world_;
  double dt_;
  std::vector<BodyId> ids_;
};

// The same engine sharing its narrowphase and contact preparation over two threads.
class GripSim2 final : public GripSim {
 public:
  GripSim2(const SceneDef& sc, const Settings& s) : GripSim(sc, s, 2) {}
};

}  // namespace

std::vector<Settings> product(const std::vector<double>& ratesHz, const std::vector<int>& substeps,
                              const std::vector<int>& iterations) {
  std::vector<Settings> g;
  for (double hz : ratesHz)
    for (int n : substeps)
      for (int it : iterations) g.push_back({1.0 / hz, n, it});
  return g;
}

Engine gripEngine() {
  const WorldDef d;
  Engine e = engineOf<GripSim>("grip", {1.0 / 60.0, d.substeps, d.relaxIterations},
                               [](const std::string& scene, bool quick) {
                                 if (quick) return product({60, 240}, {1, 4}, {1});
                                 if (scene == "pile")
                                   return product(kPileRatesHz, {1, 2, 3, 4}, {1});
                                 return product({30, 60, 120, 240, 480}, {1, 2, 4, 8, 16}, {1, 4});
                               });
  e.hands = true;
  return e;
}

Engine gripTwoThreadEngine() {
  const WorldDef d;
  // Only the pile has enough pairs to be shared out; the small scenes would run as on one
  // thread, so they are not repeated.
  return engineOf<GripSim2>("grip-2t", {1.0 / 60.0, d.substeps, d.relaxIterations},
                            [](const std::string& scene, bool quick) {
                              if (scene != "pile") return std::vector<Settings>{};
                              if (quick) return product({60, 240}, {1, 4}, {1});
                              return product(kPileRatesHz, {1, 2, 3, 4}, {1});
                            });
}

}  // namespace grip::sweep
