// The World: bodies, forces, the step, queries and events. Creation by def struct, value
// handles back. Every public call validates its input and throws grip::Error naming the bad
// field; a call that throws leaves the world as it was.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "collision/narrowphase.hpp"
#include "collision/query.hpp"
#include "collision/shape.hpp"
#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/id.hpp"

namespace grip {

struct BodyTag;
using BodyId = Id<BodyTag>;

enum class BodyType : uint8_t { Static, Kinematic, Dynamic };

// How addForce/addForceAtPosition/addTorque interpret their vector (Unity/PhysX semantics):
//   Force          N, integrated over the next step (a = F/m).       Accumulates until step.
//   Acceleration   m/s^2, like Force but ignores mass (F = m a).      Accumulates until step.
//   Impulse        N s, changes velocity now (dv = J/m).
//   VelocityChange m/s, changes velocity now, ignoring mass (dv = v).
// For torques the same holds with the inertia tensor in place of the mass.
enum class ForceMode : uint8_t { Force, Acceleration, Impulse, VelocityChange };

// Friction and restitution of a surface. When two bodies touch, frictions combine by the
// geometric mean sqrt(a*b) (as Box2D and Bullet do) and restitution by the maximum.
struct MaterialDef {
  double staticFriction = 0.6;
  double dynamicFriction = 0.5;  // must not exceed staticFriction
  double restitution = 0.0;
  double density = 1000.0;  // kg/m^3, used when BodyDef.mass is 0
};

// Which bodies collide, by Box2D's rule. A body is of the kinds set in `category` and collides
// with the kinds set in `mask`; two bodies collide when each one's mask holds the other's
// category. A shared group decides before the bits: bodies of the same positive group always
// collide, of the same negative group never (the parts of one tool, say). Sensors are filtered
// the same way. The default collides with every default body.
struct CollisionFilter {
  uint64_t category = 1;
  uint64_t mask = ~uint64_t{0};
  int32_t group = 0;
};

inline bool shouldCollide(const CollisionFilter& a, const CollisionFilter& b) {
  if (a.group != 0 && a.group == b.group) return a.group > 0;
  return (a.mask & b.category) != 0 && (b.mask & a.category) != 0;
}

// Which bodies a query sees: those of a kind its mask holds. The default sees every body.
struct QueryFilter {
  uint64_t mask = ~uint64_t{0};
};

struct JointTag;
using JointId = Id<JointTag>;

// How a joint holds two bodies together, at its anchor and along its axis, as they were when
// it was made:
//   Fixed   welds them: no relative motion.
//   Ball    a ball and socket: the anchor stays one point of both; they turn freely about it
//           (within a cone, if given one).
//   Hinge   a door's hinge: a ball joint that turns about the axis only.
//   Slider  a drawer's rail: b slides along the axis, neither turns against the other.
enum class JointType : uint8_t { Fixed, Ball, Hinge, Slider, Distance };
// Hinges, sliders and distance joints have a position along their axis (an angle, a travel, a
// stretch), and so limits, motors and springs.
inline bool hasAxisPosition(JointType t) {
  return t == JointType::Hinge || t == JointType::Slider || t == JointType::Distance;
}

struct JointDef {
  JointType type = JointType::Ball;
  BodyId a = {}, b = {};       // two bodies, at least one dynamic; a may be static or kinematic
  Vec3 anchor = Vec3::Zero();  // world, where the bodies are when the joint is made
  Vec3 axis = Vec3::UnitY();   // world (any length > 0): the hinge's axis, the slider's rail
  // Distance joints: the anchor on b (world; `anchor` is a's). They keep the anchors at the
  // distance they start at (a rod); with a limit on the stretch (m, from that distance) they
  // are a rope ([-length, 0]: slack up to the full length) or a bumper, with a spring a spring
  // toward springTarget's stretch, with a motor a winch.
  Vec3 anchorB = Vec3::Zero();
  // Limits on the hinge's angle (rad, b turning about the axis relative to a, within
  // [-pi, pi]), the slider's translation (m, b along the axis relative to a) or the distance
  // joint's stretch (m), all counted from the bodies' poses when the joint is made.
  bool enableLimit = false;
  double lower = 0.0, upper = 0.0;
  // A motor drives the hinge's turn or the slider's travel toward `motorSpeed` (rad/s or m/s,
  // the limits' sense) with at most `maxMotorForce` (N m or N). Speed 0 makes it joint
  // friction: the joint holds until pushed harder than that.
  bool enableMotor = false;
  double motorSpeed = 0.0;
  double maxMotorForce = 0.0;
  // A spring pulls the hinge's angle or the slider's travel toward `springTarget` at
  // `springHertz` (> 0) with `springDampingRatio` (>= 0), as Box2D's: a door closer.
  bool enableSpring = false;
  double springHertz = 0.0;
  double springDampingRatio = 0.0;
  double springTarget = 0.0;
  // Ball joints: a cone that b's copy of `axis` stays within about a's (the swing, rad, in
  // (0, pi); Jolt's swing-twist cone, PhysX's limit cone): a shoulder, a hanging lamp that
  // must not swing into the ceiling. The twist about the axis stays free.
  bool enableCone = false;
  double coneAngle = 0.0;
  bool collideConnected = false;  // false: the two bodies make no contacts with each other
  // The joint breaks (goes, reported by jointBreakEvents) at the end of a step whose last
  // substep had it exert more than `breakForce` (N) on b, or more than `breakTorque` (N m)
  // about its anchor (jointForce, jointTorque); infinity: never (Unity's breakForce).
  double breakForce = std::numeric_limits<double>::infinity();
  double breakTorque = std::numeric_limits<double>::infinity();
};

struct BodyDef {
  BodyType type = BodyType::Dynamic;
  ShapePtr shape = nullptr;
  MaterialDef material = {};
  Vec3 position = Vec3::Zero();  // of the body origin (the shape frame)
  Quat orientation = Quat::Identity();
  Vec3 linearVelocity = Vec3::Zero();   // of the centre of mass
  Vec3 angularVelocity = Vec3::Zero();  // world frame
  double mass = 0.0;            // > 0 overrides density (inertia scaled to match); 0: from density
  double linearDamping = 0.0;   // 1/s
  double angularDamping = 0.0;  // 1/s
  double gravityScale = 1.0;
  bool isSensor = false;  // reports overlaps, never makes contact constraints
  CollisionFilter filter = {};
  bool allowSleep = true;
  bool isAwake = true;
  uint64_t userData = 0;
  std::string name = {};
};

struct WorldDef {
  Vec3 gravity = Vec3(0.0, -9.81, 0.0);
  int substeps = 4;  // solver substeps per step (soft step solver)
  // s: a step longer than substeps x this (a frame hitch passed as dt) takes more substeps, one
  // per maxSubstep (up to 1000), so that its contacts keep their stiffness (contactHertz is
  // capped at a quarter of the substep rate: 1/120 s holds 30 Hz) and a settled stack stands
  // through a 0.5 s step (docs/dynamics.md). Steps of 1/30 s or less at 4 substeps keep them.
  double maxSubstep = 1.0 / 120.0;
  int relaxIterations = 1;          // velocity passes without position bias per substep (the last
                                    // one propagates support from the ground up: shock propagation)
  int maxRelaxIterations = 24;      // tall islands get extra relax passes, up to this many
                                    // (per island, from its height in contact levels)
  int positionIterations = 2;       // position projection passes after the velocities
  double positionCorrection = 0.2;  // fraction of the overlap the projection removes per pass
  double positionSlop = 0.0005;     // m, overlap the projection leaves alone
  double contactHertz = 30.0;       // contact stiffness (capped at a quarter substep rate)
  double contactDampingRatio = 10.0;  // heavily damped: no bounce from position correction
  double maxPushoutVelocity = 3.0;    // m/s, cap on the speed that resolves overlap
  double restitutionThreshold = 1.0;  // m/s, slower impacts do not bounce
  // m, contacts are made this much farther out than the pair's speed, acceleration and spin
  // can close in a step (docs/dynamics.md)
  double speculativeDistance = 0.0075;
  // A convex pair that moved less than this (B relative to A) since its manifold was computed
  // carries the manifold along instead of running the narrowphase (Jolt's body pair cache).
  double contactReuseDistance = 0.001;  // m; 0 always recomputes
  double contactReuseAngle = 0.035;     // rad (2 degrees)
  double linearSlop = 0.005;    // m, overlap within which velocity contacts stay rigid (no push)
  double stickVelocity = 0.01;  // m/s, tangential speed below which a contact may stick again
  bool enableSleep = true;
  double sleepLinearVelocity = 0.05;   // m/s
  double sleepAngularVelocity = 0.05;  // rad/s
  double timeToSleep = 0.5;            // s below the thresholds before an island sleeps
  double maxLinearSpeed = 400.0;       // m/s, a guard against blow-ups
  double maxAngularSpeed = 200.0;      // rad/s, the same for spin (PhysX: 100, Jolt: 47)
  // Threads a step may use, the caller's included (1..64). With 256 moving bodies or more the
  // narrowphase and the solve run in two regions on two threads; the result is bit-identical
  // for any count (docs/performance.md).
  int workerThreads = 1;
  // Joint stiffness and damping ratio of the soft constraint that pulls a joint's drift back
  // (capped at a quarter of the substep rate, as the contacts' are).
  double jointHertz = 60.0;
  double jointDampingRatio = 2.0;
};

struct ContactEvent {
  BodyId a, b;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();  // from a to b
  double approachSpeed = 0.0;   // normal closing speed at begin (m/s)
};

struct SensorEvent {
  BodyId sensor, visitor;
};

// A joint that broke (JointDef::breakForce, breakTorque): its id (no longer valid), its bodies,
// and the force and torque it exerted on b when it broke (as jointForce and jointTorque).
struct JointBreakEvent {
  JointId joint;
  BodyId a, b;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
};

struct WorldRayHit {
  BodyId body;
  RayHit hit;
};

struct OverlapHit {
  BodyId body;
  Manifold manifold;  // normal points from the query shape to the body
};

// Per-step work counters, for benchmarks and the "skip what a scene doesn't need" checks.
struct StepStats {
  int awakeBodies = 0;
  int candidatePairs = 0;
  int manifolds = 0;
  int reusedManifolds = 0;  // carried along from an earlier step without a narrowphase
  int contactPoints = 0;
  int islands = 0;
  int sleepingIslands = 0;
  int directIslands = 0;  // islands of very unequal masses whose normals were solved directly
  int solveRegions = 1;   // 2 when the awake bodies were cut in two for the solve (workerThreads)
};

class World {
 public:
  explicit World(const WorldDef& def = WorldDef{});
  ~World();
  // A copy holds everything that decides what comes next: the bodies, the contacts with their
  // warm-start impulses, sleep, time, gravity, the last step's events and stats. Stepping the
  // copy gives the same states, bit for bit, as stepping the original (snapshots, rollback,
  // what-if), and the same body ids name the same bodies in both. Worker threads are not
  // copied: a copy makes its own on first use. A moved-from world may only be assigned to or
  // destroyed.
  World(const World& other);
  World& operator=(const World& other);
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  BodyId createBody(const BodyDef& def);
  void destroyBody(BodyId id);
  bool isValid(BodyId id) const;

  // Joints (docs/dynamics.md, "Joints"), solved with the contacts in every substep. Joined
  // bodies sleep and wake together; destroying a body destroys its joints.
  JointId createJoint(const JointDef& def);
  void destroyJoint(JointId id);
  bool isValid(JointId id) const;
  int jointCount() const;
  JointType jointType(JointId id) const;
  // A hinge's angle (rad) or a slider's translation (m), counted from where it was made (as
  // its limits are); ball and fixed joints have none (an error).
  double jointPosition(JointId id) const;
  // The rate of jointPosition (rad/s or m/s).
  double jointSpeed(JointId id) const;
  // Turns a hinge's, slider's or distance joint's motor on or off (as JointDef's fields);
  // wakes the bodies. A distance joint left with no limit, motor or spring is a rod at the
  // length it has then (a winch stops and holds).
  void setJointMotor(JointId id, bool enable, double speed, double maxForce);
  // Turns the limits on (with new bounds, as JointDef's) or off; wakes the bodies.
  void setJointLimits(JointId id, bool enable, double lower, double upper);
  // Turns the spring on (with a new stiffness, damping and target, as JointDef's) or off.
  void setJointSpring(JointId id, bool enable, double springHertz, double springDampingRatio,
                      double springTarget);
  // A distance joint's length (m, > 0): the rod's, and what its limits, spring target and
  // jointPosition count from (a rope shortened by its full length's change).
  void setJointLength(JointId id, double length);
  // The force the joint exerted on b over the last step's last substep (N; on a the opposite),
  // as contactForce: a door hanging on two hinges feels its weight in them.
  Vec3 jointForce(JointId id) const;
  // The torque the joint exerted on b about its anchor over the same substep (N m; on a the
  // opposite, with jointForce's moment): a hinge's holding torque, a motor's or a spring's along
  // the axis.
  Vec3 jointTorque(JointId id) const;

  // Advances the world by dt seconds.
  void step(double dt);

  // Forces. Force and Acceleration accumulate until the next step; Impulse and
  // VelocityChange act at once. Each wakes the body. Static and kinematic bodies ignore them.
  void addForce(BodyId id, const Vec3& force, ForceMode mode = ForceMode::Force);
  void addForceAtPosition(BodyId id, const Vec3& force, const Vec3& worldPoint,
                          ForceMode mode = ForceMode::Force);
  void addTorque(BodyId id, const Vec3& torque, ForceMode mode = ForceMode::Force);
  // forces[i] at worldPoints[i] on one body: the same as addForceAtPosition for each i in order
  // (bit for bit), with one body lookup and one wake. Throws before applying anything when the
  // sizes differ or a vector is not finite.
  void addForcesAtPositions(BodyId id, std::span<const Vec3> forces,
                            std::span<const Vec3> worldPoints, ForceMode mode = ForceMode::Force);
  // The force and torque (about the centre of mass) accumulated for the next step.
  Vec3 accumulatedForce(BodyId id) const;
  Vec3 accumulatedTorque(BodyId id) const;

  // Body state.
  BodyType bodyType(BodyId id) const;
  Transform pose(BodyId id) const;     // of the body origin
  Vec3 centerOfMass(BodyId id) const;  // world
  Vec3 localCenterOfMass(BodyId id) const;
  Vec3 linearVelocity(BodyId id) const;  // of the centre of mass
  Vec3 angularVelocity(BodyId id) const;
  Vec3 velocityAtPoint(BodyId id, const Vec3& worldPoint) const;
  double mass(BodyId id) const;  // 0 for static and kinematic bodies
  double inverseMass(BodyId id) const;
  Mat3 inertiaWorld(BodyId id) const;  // about the centre of mass
  Mat3 inverseInertiaWorld(BodyId id) const;
  const Shape& shape(BodyId id) const;
  ShapePtr shapePtr(BodyId id) const;
  const MaterialDef& material(BodyId id) const;
  const std::string& name(BodyId id) const;
  uint64_t userData(BodyId id) const;
  bool isAwake(BodyId id) const;
  bool isSensor(BodyId id) const;
  Aabb bounds(BodyId id) const;

  void setPose(BodyId id, const Vec3& position, const Quat& orientation);
  void setLinearVelocity(BodyId id, const Vec3& v);
  void setAngularVelocity(BodyId id, const Vec3& w);
  // Kinematic bodies: set the velocities that carry the body to `target` over dt.
  void moveKinematic(BodyId id, const Vec3& position, const Quat& orientation, double dt);
  void setMaterial(BodyId id, const MaterialDef& m);
  // Turns the body static, kinematic or dynamic (Unity's isKinematic, Box2D's b2Body_SetType,
  // Jolt's SetMotionType): a dynamic one gets its mass from its shape (or BodyDef::mass, or
  // setMass's); it keeps moving as it moved, except that a static one stops. Wakes it and what
  // it touches. Not for a plane, nor for a body whose joint would be left without a dynamic
  // body.
  void setBodyType(BodyId id, BodyType type);
  // A dynamic body's mass (kg, > 0), as Unity's Rigidbody.mass: the same shape of another
  // density, so its centre of mass stays and its inertia scales with the mass. Wakes it.
  void setMass(BodyId id, double mass);
  // As BodyDef's fields of the same names; each wakes the body (allowSleep = false keeps it
  // awake from now on).
  void setGravityScale(BodyId id, double scale);
  void setDamping(BodyId id, double linear, double angular);  // 1/s, >= 0
  void setAllowSleep(BodyId id, bool allow);
  void setUserData(BodyId id, uint64_t data);
  // From the next step on; the body and what touches or overlaps it wake, so that their pairs
  // are made or dropped under the new filter (a dropped touching pair reports its end).
  void setCollisionFilter(BodyId id, const CollisionFilter& filter);
  CollisionFilter collisionFilter(BodyId id) const;
  void wake(BodyId id);

  // Queries. Sensors are skipped, and so are bodies of a kind the filter's mask does not hold.
  std::optional<WorldRayHit> rayCast(const Vec3& origin, const Vec3& dir, double maxDistance,
                                     const QueryFilter& filter = {}) const;
  // Ray cast against one body only (child: one compound child, or -1 for all).
  std::optional<RayHit> rayCastBody(BodyId id, const Vec3& origin, const Vec3& dir,
                                    double maxDistance, int child = -1) const;
  // The first body a convex shape (not a plane or compound) swept from `t` along dir would
  // touch within maxDistance (Unity's SphereCast and BoxCast, Jolt's CastShape): how far it
  // moved, where and with which normal of the body it touched (collision/query.hpp).
  std::optional<WorldRayHit> shapeCast(const Shape& shape, const Transform& t, const Vec3& dir,
                                       double maxDistance, const QueryFilter& filter = {}) const;
  // Bodies (and their children) within `margin` of `shape` placed at `t`, ordered by body.
  void overlap(const Shape& shape, const Transform& t, double margin, std::vector<OverlapHit>& hits,
               const QueryFilter& filter = {}) const;
  SurfacePoint closestPoint(BodyId id, const Vec3& worldPoint) const;
  // The bodies whose bounds overlap `box` (Box2D's b2World_OverlapAABB, Jolt's CollideAABox), in
  // body order: a broadphase question, no shapes tested.
  void queryBounds(const Aabb& box, std::vector<BodyId>& bodies,
                   const QueryFilter& filter = {}) const;

  // Events of the last step, in a deterministic order. Every begin gets its end: a pair taken
  // away between steps (destroyBody, or setBodyType leaving two bodies that make no contact)
  // ends in the next step's end lists, ahead of that step's own, with the ids it had (a
  // destroyed body's no longer valid), as Box2D v3.1 reports a destroyed shape's. A body that
  // falls asleep touching or inside a sensor has not left: its pairs go on.
  const std::vector<ContactEvent>& contactBeginEvents() const;
  const std::vector<ContactEvent>& contactEndEvents() const;
  const std::vector<SensorEvent>& sensorBeginEvents() const;
  const std::vector<SensorEvent>& sensorEndEvents() const;
  const std::vector<JointBreakEvent>& jointBreakEvents() const;  // in joint slot order

  // Every body id alive, in creation-slot order.
  std::vector<BodyId> bodies() const;
  int bodyCount() const;
  // Contact constraints the solver handled in the last step (points, and manifolds).
  int contactConstraintCount() const;
  // The manifolds between two bodies in the last step, as the solver used them (one per
  // child pair, speculative points included), normals pointing from a to b.
  std::vector<Manifold> contactManifolds(BodyId a, BodyId b) const;
  // The force the contacts between a and b exerted on b in the last step (N; on a the
  // opposite): the normal and friction impulses they held at its end, over a substep's length,
  // so the mean force of its last substep. A box at rest presses on the floor with its weight;
  // zero where they do not touch. A sleeping pair keeps its last.
  Vec3 contactForce(BodyId a, BodyId b) const;
  const StepStats& stats() const;
  const WorldDef& def() const;
  void setGravity(const Vec3& g);  // a change wakes every sleeping dynamic body
  Vec3 gravity() const;
  double time() const;
  uint64_t stepCount() const;

  // Hash of everything that decides what comes next (bit exact): the bodies' motion, sleep
  // and what the setters change, the joints' impulses and settings, gravity, the contacts'
  // warm-start memory. Two worlds that hash alike step alike (docs/determinism.md).
  uint64_t stateHash() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Kinetic plus gravitational potential energy of the dynamic bodies (J).
double totalEnergy(const World& w);

}  // namespace grip
