// grip beside Bullet (Debian's libbullet-dev, default settings), same scenes, same process.
// Build with -DGRIP_WITH_BULLET=ON; run build/bench/peers_bench.
// Counters: ms_per_step (wall time per step), below (bodies whose centre went below the ground
// at any step), drift_mm (largest movement of the stack's top over the run).
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <memory>

#include "dynamics/scenes.hpp"

using namespace grip;

namespace {

constexpr double kDt = 1.0 / 60.0;

// Initial poses come from grip's scene builders, so both engines start identically.
struct Pose {
  Vec3 p;
  Quat q;
  double half;
};

std::vector<Pose> pileLayout(int count) {
  World w;
  std::vector<Pose> out;
  for (BodyId id : scenes::addBoxPile(w, count)) out.push_back({w.pose(id).p, w.pose(id).q, 0.1});
  return out;
}

std::vector<Pose> stackLayout(int count) {
  World w;
  std::vector<Pose> out;
  for (BodyId id : scenes::addBoxStack(w, count, 0.1, 1.0))
    out.push_back({w.pose(id).p, w.pose(id).q, 0.05});
  return out;
}

// A Bullet world at its defaults: dbvt broadphase, sequential impulse solver, 10 iterations.
struct BulletWorld {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  explicit BulletWorld(const std::vector<Pose>& boxes) {
    world.setGravity(btVector3(0, -9.81, 0));
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0));
    add(shapes.back().get(), 0.0, btTransform::getIdentity());
    for (const Pose& b : boxes) {
      shapes.push_back(std::make_unique<btBoxShape>(btVector3(b.half, b.half, b.half)));
      btTransform t(btQuaternion(b.q.x(), b.q.y(), b.q.z(), b.q.w()),
                    btVector3(b.p.x(), b.p.y(), b.p.z()));
      add(shapes.back().get(), 1.0, t);
    }
  }
  ~BulletWorld() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }
  void add(btCollisionShape* s, double mass, const btTransform& t) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) s->calculateLocalInertia(mass, inertia);
    motions.push_back(std::make_unique<btDefaultMotionState>(t));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions.back().get(), s, inertia);
    info.m_friction = 0.6;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(bodies.back().get());
  }
  void step() { world.stepSimulation(kDt, 1, kDt); }
  Vec3 position(size_t i) const {  // i: box index (0 = first box)
    const btVector3& o = bodies[i + 1]->getWorldTransform().getOrigin();
    return Vec3(o.x(), o.y(), o.z());
  }
  size_t boxCount() const { return bodies.size() - 1; }
};

struct GripWorld {
  World world;
  std::vector<BodyId> boxes;
  explicit GripWorld(const std::vector<Pose>& layout) {
    scenes::addGround(world);
    for (const Pose& b : layout) {
      BodyDef d;
      d.shape = Shape::box(Vec3::Constant(b.half));
      d.mass = 1.0;
      d.position = b.p;
      d.orientation = b.q;
      boxes.push_back(world.createBody(d));
    }
  }
  void step() { world.step(kDt); }
  Vec3 position(size_t i) const { return world.pose(boxes[i]).p; }
  size_t boxCount() const { return boxes.size(); }
};

// One iteration = build the scene, then `steps` steps. Counters: ms_per_step (mean wall time
// of the steps alone), below (boxes whose centre went below the ground at any step),
// drift_mm (largest movement of the last box, the stack's top, from where it started).
template <class Engine>
void runScene(benchmark::State& state, const std::vector<Pose>& layout, int steps) {
  double below = 0, drift = 0, stepMs = 0;
  int runs = 0;
  for (auto _ : state) {
    auto e = std::make_unique<Engine>(layout);
    const Vec3 top0 = e->position(e->boxCount() - 1);
    std::vector<uint8_t> wentBelow(e->boxCount(), 0);
    for (int s = 0; s < steps; ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      e->step();
      stepMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (size_t i = 0; i < e->boxCount(); ++i) wentBelow[i] |= e->position(i).y() < 0.0;
      drift = std::max(drift, (e->position(e->boxCount() - 1) - top0).norm());
    }
    below = 0;
    for (uint8_t b : wentBelow) below += b;
    ++runs;
  }
  state.counters["ms_per_step"] = stepMs / (runs * steps);
  state.counters["below"] = below;
  state.counters["drift_mm"] = drift * 1e3;
}

void BM_Peer_Pile1000_Grip(benchmark::State& s) {
  runScene<GripWorld>(s, pileLayout(1000), 180);
}
void BM_Peer_Pile1000_Bullet(benchmark::State& s) {
  runScene<BulletWorld>(s, pileLayout(1000), 180);
}
void BM_Peer_Pile100_Grip(benchmark::State& s) {
  runScene<GripWorld>(s, pileLayout(100), 180);
}
void BM_Peer_Pile100_Bullet(benchmark::State& s) {
  runScene<BulletWorld>(s, pileLayout(100), 180);
}
void BM_Peer_Stack20_Grip(benchmark::State& s) {
  runScene<GripWorld>(s, stackLayout(20), 600);
}
void BM_Peer_Stack20_Bullet(benchmark::State& s) {
  runScene<BulletWorld>(s, stackLayout(20), 600);
}
void BM_Peer_Stack10_Grip(benchmark::State& s) {
  runScene<GripWorld>(s, stackLayout(10), 600);
}
void BM_Peer_Stack10_Bullet(benchmark::State& s) {
  runScene<BulletWorld>(s, stackLayout(10), 600);
}

BENCHMARK(BM_Peer_Pile1000_Grip)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_Peer_Pile1000_Bullet)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_Peer_Pile100_Grip)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_Peer_Pile100_Bullet)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_Peer_Stack20_Grip)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Peer_Stack20_Bullet)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Peer_Stack10_Grip)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Peer_Stack10_Bullet)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
