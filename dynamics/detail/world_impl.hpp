// Private state of the World. Bodies live in slots (index + generation); hot per-step solver
// data lives in flat arrays rebuilt each step in a fixed order, so results are deterministic.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "collision/aabb_tree.hpp"
#include "collision/broadphase.hpp"
#include "dynamics/detail/workers.hpp"
#include "dynamics/world.hpp"

namespace grip::detail {

// A vector no longer than `max`, in its own direction; infinite parts count as the largest
// (a sum of huge but finite forces can overflow, and inf * 0 must not become NaN).
Vec3 limitLength(const Vec3& v, double max);
// Loads so large that F/m or I^-1 T would overflow, scaled down first: the speed limit caps
// what they do anyway.
Vec3 tameLoad(const Vec3& x);

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
  double definedMass = 0.0;          // BodyDef::mass or setMass's (0: from the density)
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
  CollisionFilter filter;
  double sleepTime = 0.0;
  // Where the body was when its calm time began: a body that only trembles about a pose (the
  // rest of a pile does) stays calm, as its mean velocity over the calm time is small.
  Vec3 restCom = Vec3::Zero();
  Quat restQ = Quat::Identity();
  uint32_t sleepGroup = 0;  // which sleeping island it belongs to (0: none)
  uint64_t userData = 0;
  std::string name;
  Aabb aabb;

  bool isDynamic() const { return type == BodyType::Dynamic; }
  // What accelerates it before any contact: gravity and the applied loads (tamed). Most bodies
  // feel gravity only, and skip the taming.
  Vec3 loadAcceleration(const Vec3& gravity) const {
    if (force.isZero() && linearAccel.isZero()) return gravityScale * gravity;
    return invMass * tameLoad(force) + gravityScale * gravity + tameLoad(linearAccel);
  }
  // Its calm time starts again, from where it is now.
  void restartCalm() {
    sleepTime = 0.0;
    restCom = com, restQ = pose.q;
  }
  Mat3 invInertiaWorld() const {
    const Mat3 R = pose.q.toRotationMatrix();
    return R * invInertiaLocal * R.transpose();
  }
};

// Soft constraint coefficients: a spring of `hertz` with damping ratio `zeta`, discretised
// implicitly for substep h (Box2D v3's b2MakeSoft).
struct Softness {
  double biasRate = 0.0, massScale = 1.0, impulseScale = 0.0;
};
inline Softness makeSoft(double hertz, double zeta, double h) {
  const double omega = 2.0 * kPi * hertz;
  const double a1 = 2.0 * zeta + h * omega;
  const double a2 = h * omega * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return {omega / a1, a2 * a3, a3};
}

// How far a body may move this step before any contact (collide), per body slot: apart from
// the Body, whose cache lines stay with the thread that solves it.
struct BodyMotion {
  Vec3 acceleration = Vec3::Zero();  // from gravity and the applied loads
  double turnTravel = 0.0;           // m, how far its points can move by turning
};

// Warm-start memory of one contact point.
struct PointState {
  uint32_t featureId = 0;
  double normalImpulse = 0.0;
};

// Regions of the step (World::Impl::assignRegions).
constexpr uint8_t kAcross = 2;         // a manifold between the two regions
constexpr uint8_t kNoRegion = 3;       // a body that does not move (static, asleep), the world
constexpr size_t kRegionBodies = 256;  // fewer awake bodies stay one region

// The indices of the set bytes of `flags`, ascending: eight bytes at a time, as in a world of
// sleeping bodies most are clear.
inline void setSlots(const std::vector<uint8_t>& flags, std::vector<uint32_t>& out) {
  out.clear();
  const size_t n = flags.size();
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t word;
    std::memcpy(&word, flags.data() + i, sizeof word);
    if (word == 0) continue;
    for (size_t k = i; k < i + 8; ++k)
      if (flags[k]) out.push_back(static_cast<uint32_t>(k));
  }
  for (; i < n; ++i)
    if (flags[i]) out.push_back(static_cast<uint32_t>(i));
}

// The indices [first, last), for a range-for. (Not std::views::iota: clang 14 cannot compile
// libstdc++ 12's.)
struct IndexRange {
  struct Iterator {
    int i;
    int operator*() const { return i; }
    Iterator& operator++() { return ++i, *this; }
    bool operator!=(const Iterator& o) const { return i != o.i; }
  };
  int first = 0, last = 0;
  Iterator begin() const { return {first}; }
  Iterator end() const { return {last}; }
};

// The key of a pair of body slots, a < b.
inline uint64_t makePairKey(uint32_t a, uint32_t b) {
  return (uint64_t(a) << 32) | b;
}
// The two body slots of a pair key.
inline uint32_t firstOfPair(uint64_t key) {
  return static_cast<uint32_t>(key >> 32);
}
inline uint32_t secondOfPair(uint64_t key) {
  return static_cast<uint32_t>(key);
}

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
  // Where the narrowphase last ran for this pair of convex shapes: B's pose in A's frame, its
  // margin, the normal in A's frame and each point as fixed on either body. While the pair moves
  // less than the reuse thresholds from there, the manifold is carried along instead of recomputed.
  bool reused = false;  // this step's manifold was carried along
  Transform computedAt;
  double margin = 0.0;  // the speculative margin it was computed with
  Vec3 localNormal = Vec3::UnitY();
  Vec3 onA[4], onB[4];

  uint64_t pairKey() const { return makePairKey(bodyA, bodyB); }
  // Contact lists are kept in this order: bodies, then children.
  std::tuple<uint32_t, uint32_t, uint32_t, uint32_t> key() const {
    return {bodyA, bodyB, m.childA, m.childB};
  }
  bool keyLess(const ContactManifold& o) const { return key() < o.key(); }
};

// Velocity-level state of one body inside the solver; index 0 is the immovable world.
// Aligned so that what the solve passes read of a body (velocities, motion since the step
// began, inverse mass) spans two cache lines.
struct alignas(64) SolverBody {
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  Vec3 dp = Vec3::Zero();      // centre-of-mass displacement since the step began
  Vec3 dtheta = Vec3::Zero();  // small rotation since the step began (for separations)
  double turned = 0.0;         // |dtheta|, set with it each substep (read by the idle bounds)
  double invMass = 0.0;
  Mat3 invI = Mat3::Zero();        // world inverse inertia, fixed over the step
  Quat dq = Quat::Identity();      // the same rotation, integrated exactly (for the pose)
  Vec3 correction = Vec3::Zero();  // rotation applied by the position projection
  // The next substep's warm start (World::Impl::warmStart): the velocities at this
  // substep's start, and the reactions a shock pass held back from this body.
  Vec3 startV = Vec3::Zero(), startW = Vec3::Zero();
  Vec3 heldV = Vec3::Zero(), heldW = Vec3::Zero();
  // What the joints changed this substep: left out of the held change, as a warm start at last
  // substep's arms would spin a fast-turning body in ways no joint row then takes back.
  Vec3 jointV = Vec3::Zero(), jointW = Vec3::Zero();
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

// A manifold: non-penetration per point, Coulomb friction for the whole patch at its centre
// (two tangent rows and a twist row about the normal), capped by mu times the patch's
// total normal impulse.
//
// The normal rows live in the patch basis. Every point shares the normal n, and its lever arm
// differs from the centre's by d_k x n, which lies in the tangent plane: d_k x n = alpha_k t1 +
// beta_k t2. So point k's normal velocity is g0 + alpha_k g1 + beta_k g2, where g0 is the
// centre's normal velocity and g1, g2 the relative spin about t1 and t2, and any set of point
// impulses acts on the bodies only through its three sums (sum l_k, sum alpha_k l_k, sum
// beta_k l_k). A manifold stores the three basis rows once instead of a row per point.
struct alignas(64) SolverManifold {
  // The first cache line holds what the solve passes read of every manifold, most of which
  // they find idle (idleByBounds): the bodies, the normal, the bounds for skipping a manifold
  // that cannot push (the smallest separation at the step's start and the largest |r x n| of a
  // point on each body), the point count and two flags.
  int a = 0, b = 0;             // solver body indices
  Vec3 normal = Vec3::UnitY();  // from a to b
  double minSeparation = 0.0, reachA = 0.0, reachB = 0.0;
  int count = 0;
  bool rowsReady = false;  // the basis, friction rows and patch solve are prepared (prepareRows)
  bool bouncy = false;     // restitution != 0 (restitution itself is in the next cache line)

  int source = 0;         // index into its run of the contact list
  uint8_t sourceRun = 0;  // which run (ContactRuns)
  double staticFriction = 0.0, dynamicFriction = 0.0, restitution = 0.0;
  double twistRadius = 0.0;  // mean distance of the points from the patch centre
  bool sliding = false;
  bool warm = false;     // started with impulses from the previous step
  bool anchored = true;  // whether the drift is pulled back (static friction)
  bool block = false;    // the exact patch solve applies (3 or 4 points not near a line)
  bool direct = false;   // its island's normals are solved directly (computeLevels)
  // Shock propagation moves only the body farther from the ground (which one is fixed for
  // the step): 0 both, 1 only a, 2 only b.
  uint8_t shockMoves = 0;
  bool shockReady = false;  // the shock rows below are prepared (prepareShockRows)
  bool shockBlock = false;  // the exact patch solve applies in the shock pass
  uint8_t region = 0;       // 0 or 1: both moving bodies in that region; kAcross: one in each

  // Per point.
  double separation[4] = {};           // at the step's start
  double alpha[4] = {}, beta[4] = {};  // d_k x n = alpha_k t1 + beta_k t2
  double impulse[4] = {};              // accumulated normal impulse
  double maxImpulse[4] = {};           // largest increase this step (restitution)
  double approach[4] = {};             // fastest normal approach this step (restitution)
  double pointMass[4] = {}, shockPointMass[4] = {};  // effective mass of the normal row

  // The basis rows: the normal at the patch centre (velocity n.(vB - vA) + armB.wB - armA.wA)
  // and the relative rotations about t1 and t2 (t.(wB - wA)).
  Vec3 armA = Vec3::Zero(), armB = Vec3::Zero();     // (centre - com) x n
  Vec3 dwA = Vec3::Zero(), dwB = Vec3::Zero();       // I^-1 arm
  Vec3 spinA[2], spinB[2];                           // I^-1 t1, I^-1 t2 of each body
  double basisK[3][3] = {}, shockBasisK[3][3] = {};  // the basis rows' coupling Jb M^-1 Jb^T
  double K[4][4] = {}, shockK[4][4] = {};            // the points' coupling K_ij = c_i . Kb c_j
  bool couplingReady = false, shockCouplingReady = false;  // K, shockK (pointCouplings)

  Vec3 patchCentre = Vec3::Zero();
  SolverRow friction[3];               // tangent 1, tangent 2, twist
  double anchorError[2] = {0.0, 0.0};  // tangential drift from the anchor at the step's start
  double shockFrictionMass[3] = {};
  // The exact patch solve (solveNormalBlock): basis velocities from point velocities by least
  // squares, point impulses that add up to nothing (4 points), the basis coupling inverted.
  double fit[3][4] = {};
  double slack[4] = {};
  double blockInv[3][3] = {}, shockBlockInv[3][3] = {};
};

// What computeLevels reads of a manifold, packed: its walks over the contact graph read 12
// bytes a manifold instead of its cache lines (with two regions, most of them the other
// thread's). Written where the manifold's own fields are (prepareContacts, prepareShock).
struct ManifoldLink {
  int a = 0, b = 0;        // solver body indices
  bool bearing = false;    // warm or touching: it carries a load
  bool coldTouch = false;  // it starts touching without a warm start
  uint8_t count = 0;       // points
  uint8_t shockMoves = 0;  // as SolverManifold::shockMoves
};

// What one hand-down of the load pass changed (World::Impl::solve), to undo it.
struct LoadStep {
  int manifold = 0, island = 0, upper = 0, lower = 0;
  double impulse[4] = {}, maxImpulse[4] = {}, friction[3] = {};
  bool sliding = false;
  Vec3 v = Vec3::Zero(), w = Vec3::Zero(), heldV = Vec3::Zero(), heldW = Vec3::Zero();
  Vec3 lowerHeldV = Vec3::Zero(), lowerHeldW = Vec3::Zero();
};

// One constraint row of a joint: velocity = lin.(vB - vA) + angB.wB - angA.wA, `error` its
// position (drift); dwA and dwB are the bodies' turn per unit impulse (the inverse inertias
// times angA and angB, filled where the solve has the bodies: World::Impl::frameJoints).
struct JointRow {
  Vec3 lin = Vec3::Zero(), angA = Vec3::Zero(), angB = Vec3::Zero();
  double error = 0.0;
  Vec3 dwA = Vec3::Zero(), dwB = Vec3::Zero();
};

// A joint's rows for its bodies at some pose (joints.cpp: jointRows).
struct JointRows {
  int count = 0;
  JointRow locked[6];
  JointRow limit;         // along +axis: its velocity opens the hinge or the slider
  double position = 0.0;  // the hinge's angle or the slider's translation
  // False for bodies so far apart (1e150 m) that the arms overflow: such a joint holds nothing
  // rather than turning the bodies' velocities into NaN.
  bool finite() const;
};

// A joint's rows and its bodies' inverse inertias where the solve has the bodies now: built
// once each time the positions move (the step's start, each substep's position update) and
// shared by the warm start and the passes until the next move.
struct JointFrame {
  JointRows rows;
  bool holds = false;  // the rows are finite (JointRows::finite)
  // The rows' coupling K = J M^-1 J^T (the locked rows, then the axis row where the joint has
  // a spring, motor or limit) and its Cholesky factor L (1 / its diagonal in inv), shared by
  // every solve of the frame: K depends on the poses alone.
  int coupled = 0;
  double K[7][7] = {}, L[7][7] = {}, inv[7] = {};
};

// Where a joined body is (the solve's current pose, or the body's own between steps): its
// centre of mass, orientation as quaternion and matrix, and inverse inertia in the world;
// `stamp` tells which frame of the solve filled it (World::Impl::frameJoints).
struct JointPose {
  Vec3 com = Vec3::Zero();
  Quat q = Quat::Identity();
  Mat3 R = Mat3::Identity(), invI = Mat3::Zero();
  uint32_t stamp = 0;
};

// A joint (World::createJoint): what it holds, in the bodies' frames, and the impulses it
// carries from substep to substep (a substep's accumulated impulses, as the contacts').
struct Joint {
  uint32_t generation = 0;
  bool alive = false;
  JointType type = JointType::Ball;
  uint32_t a = 0, b = 0;                              // body slots
  Vec3 localA = Vec3::Zero(), localB = Vec3::Zero();  // the anchor from each centre of mass
  Vec3 axisA = Vec3::UnitY(), axisB = Vec3::UnitY();  // the unit axis in each body's frame
  Quat reference = Quat::Identity();                  // qA^-1 qB when made
  double restLength = 0.0;                            // a distance joint's, when made
  double rodStretch = 0.0;  // a distance rod's length from restLength (where a winch stopped)
  bool enableLimit = false, collideConnected = false, enableMotor = false, enableSpring = false;
  double lower = 0.0, upper = 0.0, motorSpeed = 0.0, maxMotorForce = 0.0;
  double springHertz = 0.0, springDampingRatio = 0.0, springTarget = 0.0;
  double impulse[6] = {};                         // the locked rows (jointRows' order)
  double lowerImpulse = 0.0, upperImpulse = 0.0;  // the limit's two sides
  double motorImpulse = 0.0, springImpulse = 0.0;
  double breakForce = 0.0, breakTorque = 0.0;  // JointDef's (infinity: never)
  int sa = 0, sb = 0;                          // solver indices this step (0: immovable)
  JointFrame frame;                            // this substep's rows (World::Impl::frameJoints)
};

struct SensorPair;

struct SensorPair {
  uint32_t sensor = 0, visitor = 0;
  bool operator<(const SensorPair& o) const {
    return sensor != o.sensor ? sensor < o.sensor : visitor < o.visitor;
  }
  bool operator==(const SensorPair& o) const { return sensor == o.sensor && visitor == o.visitor; }
};

// A step's contact manifolds in three runs, each in key order: the pairs of region 0 and
// of region 1 (by the region of the pair's first moving body; each region's narrowphase
// runs on the thread that solves it, so its manifolds stay in that thread's cache), then
// the contacts kept between bodies that did not move. One region: run 1 is empty.
struct ContactRuns {
  static constexpr int kKept = 2;
  // Each run on cache lines of its own: the two regions' threads append to theirs at once,
  // and with the three vectors on one line the narrowphase took twice as long on two threads.
  struct alignas(64) Run : std::vector<ContactManifold> {
    // Each manifold's pair key and whether it touches, in the run's order: the walks along
    // every run (the narrowphase's lookup of last step's manifolds, the kept contacts, events,
    // islands) read these few cache lines instead of every manifold, which the other region's
    // thread made. Set again whenever the run changes.
    std::vector<uint64_t> pairKeys;
    std::vector<uint8_t> touching;
    void indexKeys() {
      pairKeys.resize(size()), touching.resize(size());
      for (size_t i = 0; i < size(); ++i)
        pairKeys[i] = (*this)[i].pairKey(), touching[i] = (*this)[i].touching;
    }
  };
  Run run[3];

  template <class Each>
  void forEach(const Each& each) const {
    for (const std::vector<ContactManifold>& r : run)
      for (const ContactManifold& c : r) each(c);
  }
  // Index of the first manifold of run r whose pair is not before `pairKey`.
  size_t firstOf(int r, uint64_t pairKey) const {
    const auto first =
        std::lower_bound(run[r].begin(), run[r].end(), pairKey,
                         [](const ContactManifold& c, uint64_t key) { return c.pairKey() < key; });
    return static_cast<size_t>(first - run[r].begin());
  }
};

// What one region's narrowphase found besides manifolds (see World::Impl::narrowphase); on
// cache lines of its own, as the regions' threads write theirs at once.
struct alignas(64) NarrowphaseOut {
  std::vector<SensorPair> sensorPairs;
  std::vector<uint32_t> sleepersTouched;  // sleeping bodies a touching contact must wake
  int reused = 0;
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
  double lastSubstep = 0.0;  // s: the last step's substep (contactForce)
  // The substeps of a step of dt: def.substeps, more where they would exceed def.maxSubstep.
  int substepsFor(double dt) const {
    const double needed = std::ceil(dt / def.maxSubstep * (1.0 - 1e-9));  // (1/30 / 1/60: 2)
    return needed > def.substeps ? static_cast<int>(std::min(needed, 1000.0)) : def.substeps;
  }
  uint32_t nextSleepGroup = 1;
  // Each sleeping island's bodies by its sleep group (updateSleep), so that waking one wakes
  // them without walking every body. A body that left (destroyed, given another type) is
  // told apart by its own sleepGroup.
  std::unordered_map<uint32_t, std::vector<uint32_t>> sleepingIslands;

  SweepBroadphase broadphase;
  std::vector<Aabb> proxyBoxes;
  std::vector<uint8_t> proxyActive;
  std::vector<uint32_t> proxyBody;
  std::vector<detail::BodyMotion> motion;  // per body slot (collide)
  std::vector<uint8_t> bodyRegion;  // per body slot: its region, kNoRegion if it does not move
  // Per body slot: alive, awake and not static (markMoving, after every change of those), so
  // that a step finds the few moving bodies among many sleeping ones without reading them.
  std::vector<uint8_t> movingSlot;
  std::vector<uint32_t> movers;         // the moving slots, ascending (collide)
  std::vector<uint32_t> contactMovers;  // the movers the contact runs were made with (keepContacts)
  std::vector<uint32_t> nearMovers;     // scratch: still bodies near the movers (collide)
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  // The queries' index (world.cpp, "queries"): a tree over the bodies' boxes as they were when
  // it was built, and the bodies whose boxes changed since, tested one by one until testing
  // them has cost about a build. Built by the first query that needs it,
  // under `lock`, so that queries may run on several threads at once between steps.
  struct QueryIndex {
    static Aabb nothing() { return {Vec3::Constant(1.0), Vec3::Constant(-1.0)}; }  // meets none
    AabbTree tree;
    // Per body slot: its box (nothing() for a free slot), kept here together so that the loose
    // tests and a build do not walk the bodies' cache lines; whether it changed since the build.
    std::vector<Aabb> boxes;
    std::vector<uint8_t> moved;
    std::vector<uint32_t> movedList;  // the moved slots, ascending, as of `dirty` last clear
    std::vector<Aabb> buildBoxes;     // a build's boxes and their slots (kept, as the tree's)
    std::vector<uint32_t> buildSlots;
    bool dirty = true;          // boxes may have changed since movedList was made
    size_t looseTests = 0;      // moved bodies tested one by one since the build
    struct Lock : std::mutex {  // not copied with the world: a copy has its own
      Lock() = default;
      Lock(const Lock&) {}
      Lock& operator=(const Lock&) { return *this; }
    } lock;
  };
  mutable QueryIndex queries;
  detail::NarrowphaseOut narrowphaseOut[2];  // per region
  int regionCount = 1;                       // this step's (assignRegions)
  std::vector<uint32_t> regionSlots;         // the moving bodies, region 0's first (assignRegions)
  size_t regionSlotEnd = 0;                  // where region 1's start in regionSlots
  std::vector<uint32_t> regionOrder;         // scratch (assignRegions)
  std::vector<double> regionScratch;
  size_t regionPairEnd = 0;                                   // pairs: region 0's, then region 1's
  std::vector<std::pair<uint32_t, uint32_t>> regionOnePairs;  // scratch (collide)
  // Made on first use when def.workerThreads > 1. Threads are no part of the state: a copy of
  // the world starts without them.
  struct OwnWorkers {
    std::unique_ptr<detail::Workers> pool;
    OwnWorkers() = default;
    OwnWorkers(const OwnWorkers&) {}
    OwnWorkers& operator=(const OwnWorkers&) = delete;
    OwnWorkers(OwnWorkers&&) = default;
    OwnWorkers& operator=(OwnWorkers&&) = default;
  } workers;

  detail::ContactRuns contacts;
  // Last step's, for the narrowphase's warm-start matching and the events; after collide only
  // the events read it. Not moved up while atRest, and its kept run moved out when
  // keptTakenOver.
  detail::ContactRuns previous;
  bool atRest = false;         // this step found nothing moving, and nor did the last (collide)
  bool keptTakenOver = false;  // this step's kept run is last step's, moved (keepContacts)
  std::vector<detail::SensorPair> sensorPairs, previousSensorPairs;

  std::vector<detail::SolverBody> solverBodies;
  std::vector<uint32_t> awakeBodies;  // the solver bodies' slots (solver index - 1)
  std::vector<int> solverIndexOf;     // per body slot: its solver index (0: the static body)
  std::vector<double> calmTimes;      // per solver body (updateSleep)
  std::vector<uint8_t> calmDynamic;   // per solver body: dynamic (updateSleep)
  std::vector<detail::SolverManifold> solverManifolds;
  // The solve's view of the regions (assignRegions, setUpSolverBodies): each half's solver bodies
  // and manifolds are worked on by its own thread; the manifolds across the cut come after,
  // on one thread. The same order with one thread or two.
  std::vector<uint8_t> solverRegion;  // per solver body: 0, 1 or kNoRegion (immovable)
  int regionBodyEnd = 0;              // awakeBodies: region 0's before, region 1's from here
  int manifoldEnd[2] = {0, 0};        // solverManifolds: region 0, region 1, then across
  int shockEnd[2] = {0, 0};           // the same for shockOrder
  int worldTwin = 0;                  // the world as region 1's manifolds see it
  std::vector<int> levels, adjacencyStart, adjacency, shockOrder, fill, queue;  // shock order
  std::vector<detail::ManifoldLink> links;              // per solver manifold (computeLevels)
  std::vector<int> islandOf, islandDepth, relaxPasses;  // relax passes per manifold
  std::vector<uint8_t> bearing;         // per solver body: reached through load-bearing contacts
  std::vector<int> firstSubstepPasses;  // the same in the first substep (new contacts get more)
  // The load pass (solve): the manifolds on which their upper body rests alone, in a chain of
  // such bodies down to a static one, from the top down; each one's island; what each accepted
  // hand-down changed, to undo an island's.
  std::vector<int> soleSupports, soleSupportIslands;
  std::vector<char> grounded, islandRefused;
  std::vector<detail::LoadStep> loadLog;
  std::vector<double> islandLightest, islandHeaviest;  // inverse masses per island
  // Small islands of very unequal masses, solved directly (lists of manifold indices, each
  // list ended by -1), and per manifold whether it is in one.
  std::vector<int> directManifolds;
  std::vector<char> solvedDirectly;
  std::vector<std::pair<int, int>> directScratch;

  // Joints in slots, as bodies; the pairs of bodies whose joints switch their contacts off
  // (sorted pair keys, for the narrowphase); the joints the solve works on this step.
  std::vector<detail::Joint> joints;
  std::vector<uint32_t> freeJointSlots;
  int jointAliveCount = 0;
  std::vector<uint64_t> jointPairs;
  std::vector<uint32_t> solvedJoints;
  std::vector<detail::JointPose> jointPoses;  // by body slot, for frameJoints
  uint32_t jointFrameStamp = 0;

  std::vector<ContactEvent> beginEvents, endEvents;
  std::vector<JointBreakEvent> jointBreaks;
  std::vector<SensorEvent> sensorBegin, sensorEnd;
  // The ends of touching pairs and sensor overlaps that destroyBody or setBodyType took away
  // between steps: the next step's end lists open with them, so each begin has its end.
  std::vector<ContactEvent> droppedEnds;
  std::vector<SensorEvent> droppedSensorEnds;
  StepStats stats;
  int constraintCount = 0;

  // Stages of one step (see step.cpp).
  bool collide(double dt);  // true when it woke a sleeping body
  void keepSensorPairs();
  void assignRegions();
  // A cursor per run of previous, all walked forward along pairs in key order.
  using PreviousCursors = std::array<size_t, 3>;
  const detail::ContactManifold* findPrevious(PreviousCursors& from, uint32_t ia, uint32_t ib,
                                              uint32_t childA, uint32_t childB) const;
  void narrowphase(int region, double dt);
  void keepContacts();
  void contactEvents();
  void solve(double dt);
  void setUpSolverBodies();
  detail::IndexRange bodiesOf(int region) const;  // (setUpSolverBodies)
  detail::ContactManifold& sourceOf(const detail::SolverManifold& m) {
    return contacts.run[m.sourceRun][static_cast<size_t>(m.source)];
  }
  // work(0) and work(1) at once on two threads (regions split, workerThreads > 1), else one
  // after the other: the same result.
  template <class Work>
  void inBothRegions(const Work& work);
  // each(i) for the manifolds of a region (0, 1 or kAcross), in index order.
  template <class Each>
  void forManifolds(int region, const Each& each);
  void prepareContacts();
  void prepareManifold(detail::SolverManifold& m);  // m.source set
  void prepareRows(detail::SolverManifold& m);
  void computeLevels();
  void prepareShock(size_t manifold);
  void projectPosition(detail::SolverManifold& m);  // one manifold's share of a pass
  void integrateVelocity(int slot, double h);       // awake body `slot` (solver index slot + 1)
  void warmStart(detail::SolverBody& b, int substep);
  void integratePosition(int slot, double h);
  void applyRestitution(detail::SolverManifold& m);
  void storeImpulses(const detail::SolverManifold& m);
  void updateSleep(double dt);
  // Joints (joints.cpp): a sleeping body joined to a moving one wakes before the step; the
  // solve's share, serial after both regions' work.
  void wakeJoinedBodies();
  void prepareJoints();
  void frameJoints();
  void warmStartJoints();
  void solveJoints(double h, bool useBias);
  void indexJointPairs();
  void releaseJoint(uint32_t slot);
  void destroyJointsOf(uint32_t body);
  void breakJoints();
  void finishStep();

  detail::Body& body(BodyId id, const char* field);
  const detail::Body& body(BodyId id, const char* field) const;
  BodyId idOf(uint32_t slot) const { return BodyId{slot, bodies[slot].generation}; }
  ContactEvent contactEvent(const detail::ContactManifold& c) const;
  void wakeContactPartners(uint32_t slot);  // every body with a contact with it
  // Takes away the manifolds `drops` picks (between steps), each touching pair's end queued
  // in droppedEnds.
  template <class Drops>
  void dropContacts(const Drops& drops);
  void wakeBody(uint32_t slot);
  // A joint's limit, motor or spring changed by `change`, and its bodies woken (joints.cpp).
  template <class Change>
  void changeAxisDrive(uint32_t slot, const Change& change);
  void wakeAround(uint32_t slot);  // the body, and every body near it
  // The body's box from its pose, after every pose change (createBody, setPose, the solve).
  void refreshBounds(uint32_t slot);
  void markMoving(uint32_t slot) {
    const detail::Body& b = bodies[slot];
    movingSlot[slot] = b.alive && b.awake && b.type != BodyType::Static;
  }
  // The slots of the bodies whose boxes may overlap `box` or meet the ray, ascending (as the
  // queries visited every body before the tree: the same hits in the same order).
  void queryCandidates(const Aabb& box, std::vector<uint32_t>& out) const;
  void rayCandidates(const Vec3& origin, const Vec3& dir, double maxT,
                     std::vector<uint32_t>& out) const;
  template <class Tree, class Loose>
  void candidates(const Tree& treeHits, const Loose& looseHit, std::vector<uint32_t>& out) const;
  bool calm(const detail::Body& b, double dt) const;
};

template <class Work>
void World::Impl::inBothRegions(const Work& work) {
  if (def.workerThreads > 1 && regionCount == 2) {
    if (!workers.pool) workers.pool = std::make_unique<detail::Workers>(def.workerThreads);
    workers.pool->runEach([&work](int thread) {  // (small enough for std::function's own store)
      if (thread < 2) work(thread);
    });
  } else {
    work(0), work(1);
  }
}

}  // namespace grip
