// Private state of the World. Bodies live in slots (index + generation); hot per-step solver
// data lives in flat arrays rebuilt each step in a fixed order, so results are deterministic.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "collision/broadphase.hpp"
#include "dynamics/detail/workers.hpp"
#include "dynamics/world.hpp"

namespace grip::detail {

struct Body {
  uint32_t generation = 0;  // bumped each time the slot is reused; ids carry it
  bool alive = false;
  BodyType type = BodyType::Dynamic;
  ShapePtr shape;
  MaterialDef material;
  Transform pose;                // body origin
  Vec3 localCom = Vec3::Zero();  // centre of mass in the body frame
  Vec3 com = Vec3::Zero();       // world centre of mass
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  double invMass = 0.0;
  Mat3 inertiaLocal = Mat3::Zero();  // about the com, body frame
  Mat3 invInertiaLocal = Mat3::Zero();
  // The principal axes (body frame = principalFrame * principal frame) and moments, for the
  // free-rotation update; an isotropic body (a cube, a sphere) spins about a fixed axis.
  Quat principalFrame = Quat::Identity();
  Vec3 principalInertia = Vec3::Zero();
  bool isotropic = true;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();              // ForceMode::Force
  Vec3 linearAccel = Vec3::Zero(), angularAccel = Vec3::Zero();  // ForceMode::Acceleration
  double linearDamping = 0.0, angularDamping = 0.0, gravityScale = 1.0;
  bool sensor = false, allowSleep = true, awake = true;
  double sleepTime = 0.0;
  uint32_t sleepGroup = 0;  // which sleeping island it belongs to (0: none)
  uint64_t userData = 0;
  std::string name;
  Aabb aabb;
  int solverIndex = 0;  // index into the step's solver bodies (0: the static body)

  bool isDynamic() const { return type == BodyType::Dynamic; }
  Mat3 invInertiaWorld() const {
    const Mat3 R = pose.q.toRotationMatrix();
    return R * invInertiaLocal * R.transpose();
  }
};

// Warm-start memory of one contact point.
struct PointState {
  uint32_t featureId = 0;
  double normalImpulse = 0.0;
};

// One manifold between two bodies (one child pair), as the narrowphase made it this step,
// plus the impulses it carries from step to step.
struct ContactManifold {
  uint32_t bodyA = 0, bodyB = 0;  // slot indices, bodyA < bodyB
  Manifold m;
  PointState state[4];
  double friction[3] = {0.0, 0.0, 0.0};  // patch friction impulses: tangent 1, 2, twist
  bool sliding = false;
  bool touching = false;
  // Static friction holds a sticking patch at a point fixed on both bodies (body frames), so
  // a patch that creeps a little every step is pulled back instead of drifting away.
  bool anchored = false;
  Vec3 anchorA = Vec3::Zero(), anchorB = Vec3::Zero();
  double approachSpeed = 0.0;  // fastest normal closing speed seen before it touched

  uint64_t pairKey() const { return (uint64_t(bodyA) << 32) | bodyB; }
  bool keyLess(const ContactManifold& o) const {
    if (bodyA != o.bodyA) return bodyA < o.bodyA;
    if (bodyB != o.bodyB) return bodyB < o.bodyB;
    if (m.childA != o.m.childA) return m.childA < o.m.childA;
    return m.childB < o.m.childB;
  }
};

// Velocity-level state of one body inside the solver; index 0 is the immovable world.
struct SolverBody {
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  Vec3 dp = Vec3::Zero();          // centre-of-mass displacement since the step began
  Vec3 dtheta = Vec3::Zero();      // small rotation since the step began (for separations)
  Quat dq = Quat::Identity();      // the same rotation, integrated exactly (for the pose)
  Vec3 correction = Vec3::Zero();  // rotation applied by the position projection
  double invMass = 0.0;
  Mat3 invI = Mat3::Zero();  // world inverse inertia, fixed over the step
};

// One constraint row, prepared so that solving it costs a few dot products:
// velocity = lin.(vB - vA) + angB.wB - angA.wA; an impulse moves vA, wA by -mA lin, -dwA and
// vB, wB by +mB lin, +dwB per unit (dw = I^-1 ang).
struct SolverRow {
  Vec3 lin = Vec3::Zero();
  Vec3 angA = Vec3::Zero(), angB = Vec3::Zero();
  Vec3 dwA = Vec3::Zero(), dwB = Vec3::Zero();
  double mass = 0.0;     // effective mass
  double impulse = 0.0;  // accumulated
};

struct SolverPoint {
  SolverRow normal;
  double separation = 0.0;  // at the step's start
  double maxNormalImpulse = 0.0;
  double relativeVelocity = 0.0;  // fastest normal approach this step (for restitution)
};

// A manifold: non-penetration per point, Coulomb friction for the whole patch at its centre
// (two tangent rows and a twist row about the normal), capped by mu times the patch's
// total normal impulse.
struct SolverManifold {
  int a = 0, b = 0;             // solver body indices
  int source = 0;               // index into the contact manifold list
  Vec3 normal = Vec3::UnitY();  // from a to b
  double staticFriction = 0.0, dynamicFriction = 0.0, restitution = 0.0;
  double twistRadius = 0.0;  // mean distance of the points from the patch centre
  bool sliding = false;
  bool warm = false;  // started with impulses from the previous step
  int count = 0;
  // Bounds for skipping a manifold that cannot push (solveNormal): the smallest separation at
  // the step's start and the largest |r x n| of a point on each body. Next to the fields above,
  // so that skipping reads one cache line.
  double minSeparation = 0.0, reachA = 0.0, reachB = 0.0;
  bool rowsReady = false;  // the rows, K and the patch solve are prepared (prepareRows)
  SolverPoint p[4];
  Vec3 patchCentre = Vec3::Zero();
  SolverRow friction[3];               // tangent 1, tangent 2, twist
  double anchorError[2] = {0.0, 0.0};  // tangential drift from the anchor at the step's start
  bool anchored = true;                // whether the drift is pulled back (static friction)
  double K[4][4] = {};                 // normal coupling between the points: K_ij = J_i M^-1 J_j^T
  // Shock propagation moves only the body farther from the ground (which one is fixed for
  // the step): its coupling and row masses, computed once per step.
  uint8_t shockMoves = 0;  // 0 both, 1 only a, 2 only b
  double shockK[4][4] = {};
  double shockNormalMass[4] = {}, shockFrictionMass[3] = {};
  // A patch of 3 or 4 points moves the bodies in three ways only: along n at the centre and
  // by relative rotation about t1 and t2. Its rigid rows are solved exactly in that basis
  // (solveNormalBlock); `block` is false where the points are too close to a line.
  bool block = false;
  bool direct = false;         // its island's normals are solved directly (computeLevels)
  SolverRow centre;            // the normal row at the patch centre
  Vec3 spinA[2], spinB[2];     // I^-1 t1, I^-1 t2 of each body (the rotation rows' dw)
  double fit[3][4] = {};       // basis velocities from point velocities (least squares)
  double slack[4] = {};        // point impulses that add up to no force or moment (4 points)
  double blockInv[3][3] = {};  // inverse of the basis rows' coupling
  double shockBlockInv[3][3] = {};
};

struct SensorPair;

struct SensorPair {
  uint32_t sensor = 0, visitor = 0;
  bool operator<(const SensorPair& o) const {
    return sensor != o.sensor ? sensor < o.sensor : visitor < o.visitor;
  }
  bool operator==(const SensorPair& o) const { return sensor == o.sensor && visitor == o.visitor; }
};

// What one chunk of the narrowphase's pairs found (see World::Impl::narrowphase).
struct NarrowphaseChunk {
  std::vector<ContactManifold> manifolds;
  std::vector<SensorPair> sensorPairs;
  std::vector<Manifold> scratch;
};

}  // namespace grip::detail

namespace grip {

struct World::Impl {
  WorldDef def;
  std::vector<detail::Body> bodies;
  std::vector<uint32_t> freeSlots;
  int aliveCount = 0;
  double time = 0.0;
  uint64_t steps = 0;
  uint32_t nextSleepGroup = 1;

  SweepBroadphase broadphase;
  std::vector<Aabb> proxyBoxes;
  std::vector<uint8_t> proxyActive;
  std::vector<uint32_t> proxyBody;
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  std::vector<Manifold> scratch;  // for queries
  std::vector<detail::NarrowphaseChunk> narrowphaseChunks;
  std::unique_ptr<detail::Workers> workers;  // made on first use when def.workerThreads > 1

  std::vector<detail::ContactManifold> contacts;  // sorted by key
  std::vector<detail::ContactManifold> previous;
  std::vector<detail::SensorPair> sensorPairs, previousSensorPairs;

  std::vector<detail::SolverBody> solverBodies;
  std::vector<uint32_t> awakeBodies;  // slot indices of awake dynamic/kinematic bodies
  std::vector<detail::SolverManifold> solverManifolds;
  std::vector<int> levels, adjacencyStart, adjacency, shockOrder, fill, queue;  // shock order
  std::vector<int> islandOf, islandDepth, relaxPasses;  // relax passes per manifold
  std::vector<int> firstSubstepPasses;  // the same in the first substep (new contacts get more)
  std::vector<double> islandLightest, islandHeaviest;  // inverse masses per island
  // Small islands of very unequal masses, solved directly (lists of manifold indices, each
  // list ended by -1), and per manifold whether it is in one.
  std::vector<int> directManifolds;
  std::vector<char> solvedDirectly;
  std::vector<std::pair<int, int>> directScratch;

  std::vector<ContactEvent> beginEvents, endEvents;
  std::vector<SensorEvent> sensorBegin, sensorEnd;
  StepStats stats;
  int constraintCount = 0;

  // Stages of one step (see step.cpp).
  bool collide(double dt);  // true when it woke a sleeping body
  void narrowphase(size_t beginPair, size_t endPair, double dt,
                   detail::NarrowphaseChunk& out) const;
  // task(begin, end, chunk) for [0, count) cut into chunks of perChunk, on the workers when
  // there are any and more than one chunk (see workers.hpp).
  void inChunks(size_t count, size_t perChunk,
                const std::function<void(size_t, size_t, size_t)>& task);
  void contactEvents();
  void solve(double dt);
  void prepareContacts();
  void prepareManifold(detail::SolverManifold& m);  // m.source set
  void prepareRows(detail::SolverManifold& m);
  void computeLevels();
  void prepareShock(size_t manifold);
  void projectPositions();
  void integrateVelocities(double h);
  void integratePositions(double h);
  void applyRestitution();
  void storeImpulses();
  void updateSleep(double dt);
  void finishStep();

  detail::Body& body(BodyId id, const char* field);
  const detail::Body& body(BodyId id, const char* field) const;
  BodyId idOf(uint32_t slot) const { return BodyId{slot, bodies[slot].generation}; }
  void wakeBody(uint32_t slot);
  void refreshBounds(detail::Body& b) const;
};

}  // namespace grip
