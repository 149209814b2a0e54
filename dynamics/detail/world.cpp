// The World's public API: creation, validation, forces, state access and queries.
#include <algorithm>
#include <optional>

#include <Eigen/Eigenvalues>

#include "dynamics/detail/world_impl.hpp"

namespace grip {

using detail::Body;

namespace {

void validateWorldDef(const WorldDef& d) {
  requireFinite(d.gravity, "WorldDef.gravity");
  if (d.substeps < 1 || d.substeps > 64) throw Error("WorldDef.substeps", "must be in 1..64");
  requirePositive(d.maxSubstep, "WorldDef.maxSubstep");
  if (d.relaxIterations < 0 || d.relaxIterations > 64)
    throw Error("WorldDef.relaxIterations", "must be in 0..64");
  if (d.maxRelaxIterations < 0 || d.maxRelaxIterations > 256)
    throw Error("WorldDef.maxRelaxIterations", "must be in 0..256");
  if (d.positionIterations < 0 || d.positionIterations > 64)
    throw Error("WorldDef.positionIterations", "must be in 0..64");
  requireNonNegative(d.positionCorrection, "WorldDef.positionCorrection");
  if (d.positionCorrection > 1.0) throw Error("WorldDef.positionCorrection", "must be at most 1");
  requireNonNegative(d.positionSlop, "WorldDef.positionSlop");
  requirePositive(d.contactHertz, "WorldDef.contactHertz");
  requireNonNegative(d.contactDampingRatio, "WorldDef.contactDampingRatio");
  requirePositive(d.maxPushoutVelocity, "WorldDef.maxPushoutVelocity");
  requireNonNegative(d.restitutionThreshold, "WorldDef.restitutionThreshold");
  requireNonNegative(d.speculativeDistance, "WorldDef.speculativeDistance");
  requireNonNegative(d.contactReuseDistance, "WorldDef.contactReuseDistance");
  requireNonNegative(d.contactReuseAngle, "WorldDef.contactReuseAngle");
  requireNonNegative(d.linearSlop, "WorldDef.linearSlop");
  requireNonNegative(d.stickVelocity, "WorldDef.stickVelocity");
  requireNonNegative(d.sleepLinearVelocity, "WorldDef.sleepLinearVelocity");
  requireNonNegative(d.sleepAngularVelocity, "WorldDef.sleepAngularVelocity");
  requireNonNegative(d.timeToSleep, "WorldDef.timeToSleep");
  requirePositive(d.maxLinearSpeed, "WorldDef.maxLinearSpeed");
  requirePositive(d.maxAngularSpeed, "WorldDef.maxAngularSpeed");
  if (d.workerThreads < 1 || d.workerThreads > 64)
    throw Error("WorldDef.workerThreads", "must be in 1..64");
  requirePositive(d.jointHertz, "WorldDef.jointHertz");
  requireNonNegative(d.jointDampingRatio, "WorldDef.jointDampingRatio");
}

void validateMaterial(const MaterialDef& m, const char* staticF, const char* dynamicF,
                      const char* restitution, const char* density) {
  requireNonNegative(m.staticFriction, staticF);
  requireNonNegative(m.dynamicFriction, dynamicF);
  if (m.dynamicFriction > m.staticFriction)
    throw Error(dynamicF, "must not exceed the static friction");
  requireNonNegative(m.restitution, restitution);
  if (m.restitution > 1.0) throw Error(restitution, "must be at most 1");
  requirePositive(m.density, density);
}

}  // namespace

World::World(const WorldDef& def) : impl_(std::make_unique<Impl>()) {
  validateWorldDef(def);
  impl_->def = def;
  impl_->bodies.reserve(64);
}

World::~World() = default;

World::World(const World& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}

World& World::operator=(const World& other) {
  if (this == &other) return *this;
  auto copy = std::make_unique<Impl>(*other.impl_);  // all or nothing: ours stays if this throws
  if (impl_ && copy->def.workerThreads == impl_->def.workerThreads)
    copy->workers.pool = std::move(impl_->workers.pool);  // keep our threads
  impl_ = std::move(copy);
  return *this;
}

World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

Body& World::Impl::body(BodyId id, const char* field) {
  if (id.isNull()) throw Error(field, "null body id");
  if (id.index >= bodies.size() || !bodies[id.index].alive ||
      bodies[id.index].generation != id.generation)
    throw Error(field, "unknown or stale body id (index " + std::to_string(id.index) +
                           ", generation " + std::to_string(id.generation) + ")");
  return bodies[id.index];
}

const Body& World::Impl::body(BodyId id, const char* field) const {
  return const_cast<Impl*>(this)->body(id, field);
}

void World::Impl::refreshBounds(uint32_t slot) {
  bodies[slot].aabb = bodies[slot].shape->bounds(bodies[slot].pose);
  queries.boxes[slot] = bodies[slot].aabb;  // (the solve's two regions write different slots)
  queries.moved[slot] = 1;
}

void World::Impl::wakeBody(uint32_t slot) {
  Body& b = bodies[slot];
  if (b.type == BodyType::Static) return;
  if (b.awake) {
    b.restartCalm();
    return;
  }
  auto wake = [&](uint32_t i) {
    Body& o = bodies[i];
    o.awake = true;
    o.restartCalm();
    o.sleepGroup = 0;
    markMoving(i);
  };
  // Wake the whole sleeping island the body belongs to.
  const uint32_t group = b.sleepGroup;
  wake(slot);
  const auto island = sleepingIslands.find(group);
  if (group == 0 || island == sleepingIslands.end()) return;
  for (uint32_t i : island->second)
    if (bodies[i].alive && !bodies[i].awake && bodies[i].sleepGroup == group) wake(i);
  sleepingIslands.erase(island);
}

// Pairs are made and dropped only where a body moves (a pair of still bodies keeps its
// contacts): waking the body and every body whose box comes within the speculative distance
// of its box (a still body's contacts start there) lets the next step find its pairs again.
void World::Impl::wakeAround(uint32_t slot) {
  wakeBody(slot);
  static thread_local std::vector<uint32_t> near;
  queryCandidates(bodies[slot].aabb.inflated(def.speculativeDistance), near);
  for (uint32_t i : near)
    if (i != slot) wakeBody(i);
}

namespace {
// A dynamic body's mass, centre of mass and inertia from its shape and density, or its defined
// mass (the density scaled to match; the inertia scales with it).
void giveMass(Body& b, const char* field) {
  MassProperties mp = b.shape->massProperties(b.material.density);
  if (!(mp.mass > 0.0) || !mp.inertia.allFinite()) throw Error(field, "has no volume, so no mass");
  if (b.definedMass > 0.0) {
    mp.inertia *= b.definedMass / mp.mass;
    mp.mass = b.definedMass;
  }
  b.invMass = 1.0 / mp.mass;
  b.localCom = mp.com;
  b.inertiaLocal = mp.inertia;
  b.invInertiaLocal = mp.inertia.inverse();
  if (!b.invInertiaLocal.allFinite()) throw Error(field, "has a singular inertia");
  const Eigen::SelfAdjointEigenSolver<Mat3> principal(mp.inertia);
  Mat3 axes = principal.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  b.principalFrame = Quat(axes).normalized();
  b.principalInertia = principal.eigenvalues();
  b.isotropic = b.principalInertia.maxCoeff() - b.principalInertia.minCoeff() <=
                1e-9 * b.principalInertia.maxCoeff();
}
}  // namespace

BodyId World::createBody(const BodyDef& d) {
  if (!d.shape) throw Error("BodyDef.shape", "is missing");
  requireFinite(d.position, "BodyDef.position");
  requireFinite(d.orientation, "BodyDef.orientation");
  requireFinite(d.linearVelocity, "BodyDef.linearVelocity");
  requireFinite(d.angularVelocity, "BodyDef.angularVelocity");
  requireNonNegative(d.mass, "BodyDef.mass");
  requireNonNegative(d.linearDamping, "BodyDef.linearDamping");
  requireNonNegative(d.angularDamping, "BodyDef.angularDamping");
  requireFinite(d.gravityScale, "BodyDef.gravityScale");
  validateMaterial(d.material, "BodyDef.material.staticFriction",
                   "BodyDef.material.dynamicFriction", "BodyDef.material.restitution",
                   "BodyDef.material.density");
  if (d.shape->type() == ShapeType::Plane && d.type != BodyType::Static)
    throw Error("BodyDef.shape", "a plane can only belong to a static body");

  Body b;
  b.alive = true;
  b.type = d.type;
  b.shape = d.shape;
  b.material = d.material;
  b.pose.p = d.position;
  b.pose.q = d.orientation.normalized();
  b.linearDamping = d.linearDamping;
  b.angularDamping = d.angularDamping;
  b.gravityScale = d.gravityScale;
  b.sensor = d.isSensor;
  b.filter = d.filter;
  b.allowSleep = d.allowSleep;
  b.awake = d.type != BodyType::Static && d.isAwake;
  b.userData = d.userData;
  b.name = d.name;
  b.definedMass = d.mass;
  if (d.type == BodyType::Dynamic) giveMass(b, "BodyDef.shape");
  if (d.type != BodyType::Static) b.v = d.linearVelocity, b.w = d.angularVelocity;
  b.com = b.pose.apply(b.localCom);
  b.restartCalm();

  uint32_t slot;
  if (!impl_->freeSlots.empty()) {
    slot = impl_->freeSlots.back();
    impl_->freeSlots.pop_back();
    b.generation = impl_->bodies[slot].generation + 1;
    if (b.generation == 0) b.generation = 1;
    impl_->bodies[slot] = std::move(b);
  } else {
    slot = static_cast<uint32_t>(impl_->bodies.size());
    b.generation = 1;
    impl_->bodies.push_back(std::move(b));
    impl_->queries.moved.push_back(1);
    impl_->queries.boxes.emplace_back();
    impl_->movingSlot.push_back(0);
  }
  impl_->markMoving(slot);
  impl_->refreshBounds(slot);
  impl_->queries.dirty = true;
  ++impl_->aliveCount;
  return BodyId{slot, impl_->bodies[slot].generation};
}

void World::Impl::wakeContactPartners(uint32_t slot) {
  contacts.forEach([&](const detail::ContactManifold& c) {
    if (c.bodyA == slot) wakeBody(c.bodyB);
    if (c.bodyB == slot) wakeBody(c.bodyA);
  });
}

template <class Drops>
void World::Impl::dropContacts(const Drops& drops) {
  for (auto& r : contacts.run) {
    // A pair's manifolds are next to each other in its run: one end for the pair.
    std::optional<uint64_t> ended;
    for (const detail::ContactManifold& c : r) {
      if (!c.touching || !drops(c) || ended == c.pairKey()) continue;
      droppedEnds.push_back(contactEvent(c));
      ended = c.pairKey();
    }
    std::erase_if(r, drops);
    r.indexKeys();
  }
}

void World::destroyBody(BodyId id) {
  Body& b = impl_->body(id, "destroyBody.id");
  impl_->destroyJointsOf(id.index);
  // Wake whatever rested on it, then drop its contacts and overlaps (their ends reported by
  // the next step).
  impl_->wakeContactPartners(id.index);
  impl_->dropContacts(
      [&](const detail::ContactManifold& c) { return c.bodyA == id.index || c.bodyB == id.index; });
  std::erase_if(impl_->sensorPairs, [&](const detail::SensorPair& p) {
    if (p.sensor != id.index && p.visitor != id.index) return false;
    impl_->droppedSensorEnds.push_back({impl_->idOf(p.sensor), impl_->idOf(p.visitor)});
    return true;
  });
  impl_->queries.boxes[id.index] = Impl::QueryIndex::nothing();  // found by no query
  if (const auto island = impl_->sleepingIslands.find(b.sleepGroup);
      b.sleepGroup != 0 && island != impl_->sleepingIslands.end()) {
    std::erase(island->second, id.index);
    if (island->second.empty()) impl_->sleepingIslands.erase(island);
  }
  const uint32_t generation = b.generation;  // kept so the slot's next body gets a new one
  b = Body{};
  b.generation = generation;
  impl_->markMoving(id.index);
  impl_->freeSlots.push_back(id.index);
  --impl_->aliveCount;
}

void World::setBodyType(BodyId id, BodyType type) {
  const Body& found = impl_->body(id, "setBodyType.id");
  if (type != BodyType::Static && type != BodyType::Kinematic && type != BodyType::Dynamic)
    throw Error("setBodyType.type", "is not a body type");
  if (type == found.type) return;
  if (found.shape->type() == ShapeType::Plane)
    throw Error("setBodyType.type", "a plane can only belong to a static body");
  if (type != BodyType::Dynamic)
    for (const detail::Joint& j : impl_->joints) {
      const uint32_t other = j.a == id.index ? j.b : j.a;
      if (j.alive && (j.a == id.index || j.b == id.index) && !impl_->bodies[other].isDynamic())
        throw Error("setBodyType.type", "would leave one of its joints without a dynamic body");
    }
  // The new body whole, then swapped in: a shape without volume refuses to be dynamic and
  // leaves the body as it was. It moves on as it moved (the velocities are of the centre of
  // mass, which a dynamic body has at its own and the others at their origin), a static one
  // stops.
  Body b = found;
  const Vec3 v = b.v + b.w.cross(b.pose.p - b.com);  // of the origin
  b.type = type;
  b.invMass = 0.0, b.localCom = Vec3::Zero();
  b.inertiaLocal = b.invInertiaLocal = Mat3::Zero();
  b.principalFrame = Quat::Identity(), b.principalInertia = Vec3::Zero(), b.isotropic = true;
  if (type == BodyType::Dynamic) giveMass(b, "setBodyType.type");
  b.com = b.pose.apply(b.localCom);
  b.v = type == BodyType::Static ? Vec3::Zero() : Vec3(v + b.w.cross(b.com - b.pose.p));
  if (type == BodyType::Static) b.w = Vec3::Zero();
  if (type != BodyType::Dynamic) b.force = b.torque = b.linearAccel = b.angularAccel = Vec3::Zero();
  b.awake = type != BodyType::Static, b.sleepGroup = 0;
  b.restartCalm();
  impl_->bodies[id.index] = std::move(b);
  impl_->markMoving(id.index);
  // Contacts between two bodies neither dynamic nor a sensor are never made: this body's with
  // such partners go (still bodies would keep them). The partners wake to feel the change.
  const auto noPair = [&](const detail::ContactManifold& c) {
    if (c.bodyA != id.index && c.bodyB != id.index) return false;
    const Body &A = impl_->bodies[c.bodyA], &B = impl_->bodies[c.bodyB];
    return !A.isDynamic() && !B.isDynamic() && !A.sensor && !B.sensor;
  };
  impl_->wakeContactPartners(id.index);
  impl_->dropContacts(noPair);
  impl_->wakeBody(id.index);
}

bool World::isValid(BodyId id) const {
  return !id.isNull() && id.index < impl_->bodies.size() && impl_->bodies[id.index].alive &&
         impl_->bodies[id.index].generation == id.generation;
}

// ---- forces -------------------------------------------------------------------------------

void World::addForce(BodyId id, const Vec3& f, ForceMode mode) {
  Body& b = impl_->body(id, "addForce.id");
  requireFinite(f, "addForce.force");
  if (!b.isDynamic()) return;
  switch (mode) {
    case ForceMode::Force:
      b.force += f;
      break;
    case ForceMode::Acceleration:
      b.linearAccel += f;
      break;
    case ForceMode::Impulse:
      b.v += b.invMass * f;
      break;
    case ForceMode::VelocityChange:
      b.v += f;
      break;
  }
  impl_->wakeBody(id.index);
}

void World::addTorque(BodyId id, const Vec3& t, ForceMode mode) {
  Body& b = impl_->body(id, "addTorque.id");
  requireFinite(t, "addTorque.torque");
  if (!b.isDynamic()) return;
  switch (mode) {
    case ForceMode::Force:
      b.torque += t;
      break;
    case ForceMode::Acceleration:
      b.angularAccel += t;
      break;
    case ForceMode::Impulse:
      b.w += b.invInertiaWorld() * t.cwiseMax(-1e100).cwiseMin(1e100);  // no inf - inf
      break;
    case ForceMode::VelocityChange:
      b.w += t;
      break;
  }
  impl_->wakeBody(id.index);
}

void World::addForceAtPosition(BodyId id, const Vec3& f, const Vec3& x, ForceMode mode) {
  Body& b = impl_->body(id, "addForceAtPosition.id");
  requireFinite(f, "addForceAtPosition.force");
  requireFinite(x, "addForceAtPosition.position");
  if (!b.isDynamic()) return;
  // As PhysX's addForceAtPos (which Unity uses): the force acts at the centre of mass and
  // the torque (x - com) x f is applied with the same mode.
  const Vec3 torque = (x - b.com).cross(f);
  addForce(id, f, mode);
  addTorque(id, torque, mode);
}

void World::addForcesAtPositions(BodyId id, std::span<const Vec3> forces,
                                 std::span<const Vec3> points, ForceMode mode) {
  Body& b = impl_->body(id, "addForcesAtPositions.id");
  if (forces.size() != points.size()) {
    throw Error("addForcesAtPositions.worldPoints", "has " + std::to_string(points.size()) +
                                                        " points for " +
                                                        std::to_string(forces.size()) + " forces");
  }
  // x * 0 is 0 for a finite x and NaN otherwise: one sum checks every component.
  Vec3 check = Vec3::Zero();
  for (size_t i = 0; i < forces.size(); ++i) check += 0.0 * forces[i] + 0.0 * points[i];
  if (!check.isZero(0.0)) {
    for (size_t i = 0; i < forces.size(); ++i) {
      requireFinite(forces[i], "addForcesAtPositions.forces");
      requireFinite(points[i], "addForcesAtPositions.worldPoints");
    }
  }
  if (!b.isDynamic() || forces.empty()) return;
  // Accumulated one by one, in order, as addForce and addTorque would (bit for bit).
  Vec3* linear = &b.force;
  Vec3* angular = &b.torque;
  Mat3 angularScale = Mat3::Identity();
  double linearScale = 1.0;
  switch (mode) {
    case ForceMode::Force:
      break;
    case ForceMode::Acceleration:
      linear = &b.linearAccel;
      angular = &b.angularAccel;
      break;
    case ForceMode::Impulse:
      linear = &b.v;
      angular = &b.w;
      linearScale = b.invMass;
      angularScale = b.invInertiaWorld();
      break;
    case ForceMode::VelocityChange:
      linear = &b.v;
      angular = &b.w;
      break;
  }
  Vec3 sumF = *linear, sumT = *angular;
  const bool scaled = mode == ForceMode::Impulse;
  for (size_t i = 0; i < forces.size(); ++i) {
    const Vec3& f = forces[i];
    const Vec3 torque = (points[i] - b.com).cross(f);
    if (scaled) {
      sumF += linearScale * f;
      sumT += angularScale * torque;
    } else {
      sumF += f;
      sumT += torque;
    }
  }
  *linear = sumF;
  *angular = sumT;
  impl_->wakeBody(id.index);
}

Vec3 World::accumulatedForce(BodyId id) const {
  const Body& b = impl_->body(id, "accumulatedForce.id");
  if (b.invMass == 0.0) return b.force;
  return b.force + b.linearAccel / b.invMass;
}

Vec3 World::accumulatedTorque(BodyId id) const {
  const Body& b = impl_->body(id, "accumulatedTorque.id");
  if (b.invMass == 0.0) return b.torque;
  const Mat3 R = b.pose.q.toRotationMatrix();
  return b.torque + R * b.inertiaLocal * R.transpose() * b.angularAccel;
}

// ---- state --------------------------------------------------------------------------------

BodyType World::bodyType(BodyId id) const {
  return impl_->body(id, "bodyType.id").type;
}
Transform World::pose(BodyId id) const {
  return impl_->body(id, "pose.id").pose;
}
Vec3 World::centerOfMass(BodyId id) const {
  return impl_->body(id, "centerOfMass.id").com;
}
Vec3 World::localCenterOfMass(BodyId id) const {
  return impl_->body(id, "localCenterOfMass.id").localCom;
}
Vec3 World::linearVelocity(BodyId id) const {
  return impl_->body(id, "linearVelocity.id").v;
}
Vec3 World::angularVelocity(BodyId id) const {
  return impl_->body(id, "angularVelocity.id").w;
}
Vec3 World::velocityAtPoint(BodyId id, const Vec3& x) const {
  const Body& b = impl_->body(id, "velocityAtPoint.id");
  requireFinite(x, "velocityAtPoint.point");
  return b.v + b.w.cross(x - b.com);
}
double World::mass(BodyId id) const {
  const Body& b = impl_->body(id, "mass.id");
  return b.invMass > 0.0 ? 1.0 / b.invMass : 0.0;
}
double World::inverseMass(BodyId id) const {
  return impl_->body(id, "inverseMass.id").invMass;
}
Mat3 World::inertiaWorld(BodyId id) const {
  const Body& b = impl_->body(id, "inertiaWorld.id");
  return rotateInertia(b.inertiaLocal, b.pose.q);
}
Mat3 World::inverseInertiaWorld(BodyId id) const {
  return impl_->body(id, "inverseInertiaWorld.id").invInertiaWorld();
}
const Shape& World::shape(BodyId id) const {
  return *impl_->body(id, "shape.id").shape;
}
ShapePtr World::shapePtr(BodyId id) const {
  return impl_->body(id, "shapePtr.id").shape;
}
const MaterialDef& World::material(BodyId id) const {
  return impl_->body(id, "material.id").material;
}
const std::string& World::name(BodyId id) const {
  return impl_->body(id, "name.id").name;
}
uint64_t World::userData(BodyId id) const {
  return impl_->body(id, "userData.id").userData;
}
bool World::isAwake(BodyId id) const {
  return impl_->body(id, "isAwake.id").awake;
}
bool World::isSensor(BodyId id) const {
  return impl_->body(id, "isSensor.id").sensor;
}
Aabb World::bounds(BodyId id) const {
  return impl_->body(id, "bounds.id").aabb;
}

void World::setPose(BodyId id, const Vec3& p, const Quat& q) {
  Body& b = impl_->body(id, "setPose.id");
  requireFinite(p, "setPose.position");
  requireFinite(q, "setPose.orientation");
  b.pose.p = p;
  b.pose.q = q.normalized();
  b.com = b.pose.apply(b.localCom);
  impl_->refreshBounds(id.index);
  impl_->queries.dirty = true;
  impl_->wakeBody(id.index);
}

void World::setLinearVelocity(BodyId id, const Vec3& v) {
  Body& b = impl_->body(id, "setLinearVelocity.id");
  requireFinite(v, "setLinearVelocity.velocity");
  if (b.type == BodyType::Static) return;
  b.v = v;
  impl_->wakeBody(id.index);
}

void World::setAngularVelocity(BodyId id, const Vec3& w) {
  Body& b = impl_->body(id, "setAngularVelocity.id");
  requireFinite(w, "setAngularVelocity.velocity");
  if (b.type == BodyType::Static) return;
  b.w = w;
  impl_->wakeBody(id.index);
}

void World::moveKinematic(BodyId id, const Vec3& p, const Quat& q, double dt) {
  Body& b = impl_->body(id, "moveKinematic.id");
  requireFinite(p, "moveKinematic.position");
  requireFinite(q, "moveKinematic.orientation");
  requirePositive(dt, "moveKinematic.dt");
  if (b.type != BodyType::Kinematic) throw Error("moveKinematic.id", "body is not kinematic");
  const Vec3 target = p + q.normalized() * b.localCom;
  b.v = (target - b.com) / dt;
  Quat dq = q.normalized() * b.pose.q.conjugate();
  if (dq.w() < 0) dq.coeffs() = -dq.coeffs();
  const Eigen::AngleAxisd aa(dq);
  b.w = aa.axis() * (aa.angle() / dt);
  impl_->wakeBody(id.index);
}

void World::setMaterial(BodyId id, const MaterialDef& m) {
  Body& b = impl_->body(id, "setMaterial.id");
  validateMaterial(m, "setMaterial.staticFriction", "setMaterial.dynamicFriction",
                   "setMaterial.restitution", "setMaterial.density");
  b.material.staticFriction = m.staticFriction;
  b.material.dynamicFriction = m.dynamicFriction;
  b.material.restitution = m.restitution;
}

void World::setGravityScale(BodyId id, double scale) {
  Body& b = impl_->body(id, "setGravityScale.id");
  requireFinite(scale, "setGravityScale.scale");
  b.gravityScale = scale;
  impl_->wakeBody(id.index);
}

void World::setMass(BodyId id, double mass) {
  Body& b = impl_->body(id, "setMass.id");
  if (!b.isDynamic()) throw Error("setMass.id", "only dynamic bodies have a mass");
  requirePositive(mass, "setMass.mass");
  // The same shape of a new density: the centre of mass and the principal axes stay, the
  // inertia scales with the mass.
  const double scale = mass * b.invMass;
  if (!std::isfinite(scale) || !(scale > 0.0)) throw Error("setMass.mass", "is out of range");
  b.invMass = 1.0 / mass, b.definedMass = mass;
  b.inertiaLocal *= scale, b.principalInertia *= scale;
  b.invInertiaLocal = b.inertiaLocal.inverse();
  impl_->wakeBody(id.index);
}

void World::setDamping(BodyId id, double linear, double angular) {
  Body& b = impl_->body(id, "setDamping.id");
  requireNonNegative(linear, "setDamping.linear");
  requireNonNegative(angular, "setDamping.angular");
  b.linearDamping = linear, b.angularDamping = angular;
  impl_->wakeBody(id.index);
}

void World::setAllowSleep(BodyId id, bool allow) {
  Body& b = impl_->body(id, "setAllowSleep.id");
  b.allowSleep = allow;
  impl_->wakeBody(id.index);
}

void World::setUserData(BodyId id, uint64_t data) {
  impl_->body(id, "setUserData.id").userData = data;
}

void World::setCollisionFilter(BodyId id, const CollisionFilter& filter) {
  Body& b = impl_->body(id, "setCollisionFilter.id");
  b.filter = filter;
  impl_->wakeAround(id.index);
}

CollisionFilter World::collisionFilter(BodyId id) const {
  return impl_->body(id, "collisionFilter.id").filter;
}

void World::wake(BodyId id) {
  impl_->body(id, "wake.id");
  impl_->wakeBody(id.index);
}

// ---- queries ------------------------------------------------------------------------------

// A query's candidates: the tree's bodies that have not moved since it was built, and the
// moved ones by their current boxes; ascending, so the hits and their ties come in body order.
template <class Tree, class Loose>
void World::Impl::candidates(const Tree& treeHits, const Loose& looseHit,
                             std::vector<uint32_t>& out) const {
  // Moved bodies tested one by one, per body in the world, before the tree is built again: a
  // build costs about as much as that many tests (30 against 2 ns a body), so a world that
  // moves and queries little pays at most about twice what testing every body would (ski
  // rental), and one that rests, or asks many queries a step, walks the tree.
  constexpr size_t kTestsPerBuild = 15;
  out.clear();
  const std::lock_guard<std::mutex> hold(queries.lock);
  QueryIndex& q = queries;
  if (q.dirty) {
    detail::setSlots(q.moved, q.movedList);
    q.dirty = false;
  }
  q.looseTests += q.movedList.size();
  if (q.looseTests > kTestsPerBuild * bodies.size()) {
    q.buildBoxes.clear(), q.buildSlots.clear();
    for (uint32_t i = 0; i < q.boxes.size(); ++i)
      if (q.boxes[i].min.x() <= q.boxes[i].max.x())
        q.buildBoxes.push_back(q.boxes[i]), q.buildSlots.push_back(i);
    q.tree.build(q.buildBoxes, q.buildSlots);
    std::fill(q.moved.begin(), q.moved.end(), uint8_t{0});
    q.movedList.clear();
    q.looseTests = 0;
  }
  treeHits(q.tree, [&](uint32_t slot) {
    if (!q.moved[slot]) out.push_back(slot);
  });
  for (uint32_t slot : q.movedList)
    if (looseHit(q.boxes[slot])) out.push_back(slot);
  std::sort(out.begin(), out.end());
}

void World::Impl::queryCandidates(const Aabb& box, std::vector<uint32_t>& out) const {
  candidates([&](const AabbTree& t, const auto& visit) { t.query(box, visit); },
             [&](const Aabb& b) { return b.overlaps(box); }, out);
}

void World::Impl::rayCandidates(const Vec3& origin, const Vec3& dir, double maxT,
                                std::vector<uint32_t>& out) const {
  candidates([&](const AabbTree& t, const auto& visit) { t.rayQuery(origin, dir, maxT, visit); },
             [&](const Aabb& b) { return AabbTree::rayMeetsBox(b, origin, dir, maxT); }, out);
}

namespace {
// Each thread's candidates, kept between its queries.
std::vector<uint32_t>& candidateScratch() {
  thread_local std::vector<uint32_t> slots;
  return slots;
}

// Whether a query with this filter sees the body (sensors it never does).
bool seenBy(const Body& b, const QueryFilter& filter) {
  return b.alive && !b.sensor && (filter.mask & b.filter.category) != 0;
}

void validateRay(const Vec3& origin, const Vec3& dir, double maxDistance, const char* o,
                 const char* d, const char* m) {
  requireFinite(origin, o);
  requireFinite(dir, d);
  if (std::abs(dir.norm() - 1.0) > 1e-6) throw Error(d, "must be a unit vector");
  requireNonNegative(maxDistance, m);
}
}  // namespace

std::optional<WorldRayHit> World::rayCast(const Vec3& origin, const Vec3& dir, double maxDistance,
                                          const QueryFilter& filter) const {
  validateRay(origin, dir, maxDistance, "rayCast.origin", "rayCast.dir", "rayCast.maxDistance");
  std::optional<WorldRayHit> best;
  double bestT = maxDistance;
  std::vector<uint32_t>& slots = candidateScratch();
  impl_->rayCandidates(origin, dir, maxDistance, slots);
  for (uint32_t i : slots) {
    const Body& b = impl_->bodies[i];
    if (!seenBy(b, filter)) continue;
    if (!AabbTree::rayMeetsBox(b.aabb, origin, dir, bestT)) continue;
    RayHit h;
    if (grip::rayCast(*b.shape, b.pose, origin, dir, bestT, h) && (!best || h.distance < bestT)) {
      bestT = h.distance;
      best = WorldRayHit{impl_->idOf(i), h};
    }
  }
  return best;
}

std::optional<WorldRayHit> World::shapeCast(const Shape& shape, const Transform& t, const Vec3& dir,
                                            double maxDistance, const QueryFilter& filter) const {
  requireFinite(t.q, "shapeCast.transform.orientation");
  validateRay(t.p, dir, maxDistance, "shapeCast.transform.position", "shapeCast.dir",
              "shapeCast.maxDistance");
  if (!shape.isConvex())
    throw Error("shapeCast.shape", "must be convex (a sphere, capsule, box or hull)");
  const Transform pose{t.p, t.q.normalized()};
  const Aabb swept = shape.bounds(pose).sweptAlong(dir, maxDistance);
  std::optional<WorldRayHit> best;
  double bestT = maxDistance;
  std::vector<uint32_t>& slots = candidateScratch();
  impl_->queryCandidates(swept, slots);
  for (uint32_t i : slots) {
    const Body& b = impl_->bodies[i];
    if (!seenBy(b, filter)) continue;
    RayHit h;
    if (grip::shapeCast(*b.shape, b.pose, shape, pose, dir, bestT, h) &&
        (!best || h.distance < bestT)) {
      bestT = h.distance;
      best = WorldRayHit{impl_->idOf(i), h};
    }
  }
  return best;
}

std::optional<RayHit> World::rayCastBody(BodyId id, const Vec3& origin, const Vec3& dir,
                                         double maxDistance, int child) const {
  const Body& b = impl_->body(id, "rayCastBody.id");
  validateRay(origin, dir, maxDistance, "rayCastBody.origin", "rayCastBody.dir",
              "rayCastBody.maxDistance");
  RayHit h;
  bool hit;
  if (child < 0) {
    hit = grip::rayCast(*b.shape, b.pose, origin, dir, maxDistance, h);
  } else {
    const size_t n = b.shape->type() == ShapeType::Compound ? b.shape->children().size() : 1;
    if (static_cast<size_t>(child) >= n) throw Error("rayCastBody.child", "out of range");
    hit = grip::rayCastChild(*b.shape, b.pose, static_cast<uint32_t>(child), origin, dir,
                             maxDistance, h);
  }
  if (!hit) return std::nullopt;
  return h;
}

void World::overlap(const Shape& shape, const Transform& t, double margin,
                    std::vector<OverlapHit>& hits, const QueryFilter& filter) const {
  requireFinite(t.p, "overlap.transform.position");
  requireFinite(t.q, "overlap.transform.orientation");
  requireNonNegative(margin, "overlap.margin");
  if (shape.type() == ShapeType::Plane) throw Error("overlap.shape", "cannot be a plane");
  hits.clear();
  const Aabb box = shape.bounds(t).inflated(margin);
  thread_local std::vector<Manifold> scratch;
  std::vector<uint32_t>& slots = candidateScratch();
  impl_->queryCandidates(box, slots);
  for (uint32_t i : slots) {
    const Body& b = impl_->bodies[i];
    if (!seenBy(b, filter)) continue;
    scratch.clear();
    collide(shape, t, *b.shape, b.pose, margin, scratch);
    for (const Manifold& m : scratch) hits.push_back(OverlapHit{impl_->idOf(i), m});
  }
}

void World::queryBounds(const Aabb& box, std::vector<BodyId>& out,
                        const QueryFilter& filter) const {
  requireFinite(box.min, "queryBounds.box.min");
  requireFinite(box.max, "queryBounds.box.max");
  if (!(box.min.array() <= box.max.array()).all())
    throw Error("queryBounds.box", "min must not exceed max");
  out.clear();
  std::vector<uint32_t>& slots = candidateScratch();
  impl_->queryCandidates(box, slots);
  for (uint32_t i : slots)
    if (seenBy(impl_->bodies[i], filter)) out.push_back(impl_->idOf(i));
}

SurfacePoint World::closestPoint(BodyId id, const Vec3& x) const {
  const Body& b = impl_->body(id, "closestPoint.id");
  requireFinite(x, "closestPoint.point");
  return grip::closestPoint(*b.shape, b.pose, x);
}

// ---- bookkeeping --------------------------------------------------------------------------

const std::vector<JointBreakEvent>& World::jointBreakEvents() const {
  return impl_->jointBreaks;
}
const std::vector<ContactEvent>& World::contactBeginEvents() const {
  return impl_->beginEvents;
}
const std::vector<ContactEvent>& World::contactEndEvents() const {
  return impl_->endEvents;
}
const std::vector<SensorEvent>& World::sensorBeginEvents() const {
  return impl_->sensorBegin;
}
const std::vector<SensorEvent>& World::sensorEndEvents() const {
  return impl_->sensorEnd;
}

std::vector<BodyId> World::bodies() const {
  std::vector<BodyId> ids;
  ids.reserve(impl_->aliveCount);
  for (uint32_t i = 0; i < impl_->bodies.size(); ++i)
    if (impl_->bodies[i].alive) ids.push_back(impl_->idOf(i));
  return ids;
}
int World::bodyCount() const {
  return impl_->aliveCount;
}
int World::contactConstraintCount() const {
  return impl_->constraintCount;
}
namespace {

// Calls each(manifold) for every stored manifold between bodies a and b (one per child pair);
// true when a is the higher slot, so that the manifolds' normals point from b to a.
template <class Each>
bool forPairManifolds(const detail::ContactRuns& contacts, BodyId a, BodyId b, const Each& each) {
  const bool flip = a.index > b.index;
  const uint64_t key =
      flip ? detail::makePairKey(b.index, a.index) : detail::makePairKey(a.index, b.index);
  for (int run = 0; run < 3; ++run) {  // each in key order; the pair is in one of them
    const auto& list = contacts.run[run];
    for (size_t i = contacts.firstOf(run, key); i < list.size() && list[i].pairKey() == key; ++i)
      each(list[i]);
  }
  return flip;
}

}  // namespace

std::vector<Manifold> World::contactManifolds(BodyId a, BodyId b) const {
  impl_->body(a, "contactManifolds.a");
  impl_->body(b, "contactManifolds.b");
  std::vector<Manifold> out;
  const bool flip = forPairManifolds(impl_->contacts, a, b,
                                     [&](const detail::ContactManifold& c) { out.push_back(c.m); });
  if (flip)
    for (Manifold& m : out) m.normal = -m.normal, std::swap(m.childA, m.childB);
  return out;
}

Vec3 World::contactForce(BodyId a, BodyId b) const {
  impl_->body(a, "contactForce.a");
  impl_->body(b, "contactForce.b");
  if (!(impl_->lastSubstep > 0.0)) return Vec3::Zero();  // no step yet
  // The stored impulses push the higher slot's body.
  Vec3 impulse = Vec3::Zero();
  const bool flip = forPairManifolds(impl_->contacts, a, b, [&](const detail::ContactManifold& c) {
    Vec3 t1, t2;  // the solver's friction directions (prepareManifold)
    tangentBasis(c.m.normal, t1, t2);
    for (int k = 0; k < c.m.pointCount; ++k) impulse += c.state[k].normalImpulse * c.m.normal;
    impulse += c.friction[0] * t1 + c.friction[1] * t2;
  });
  return (flip ? -impulse : impulse) / impl_->lastSubstep;
}

const StepStats& World::stats() const {
  return impl_->stats;
}
const WorldDef& World::def() const {
  return impl_->def;
}
void World::setGravity(const Vec3& g) {
  requireFinite(g, "setGravity.gravity");
  if (g == impl_->def.gravity) return;
  impl_->def.gravity = g;
  // Every sleeping dynamic body wakes to feel it (a sleeping body must not act otherwise than
  // an awake one would; PhysX, Jolt and Box2D leave them hanging until touched).
  for (uint32_t slot = 0; slot < impl_->bodies.size(); ++slot) {
    const Body& b = impl_->bodies[slot];
    if (b.alive && b.isDynamic() && !b.awake) impl_->wakeBody(slot);
  }
}
Vec3 World::gravity() const {
  return impl_->def.gravity;
}
double World::time() const {
  return impl_->time;
}
uint64_t World::stepCount() const {
  return impl_->steps;
}

uint64_t World::stateHash() const {
  // Everything that decides what comes next (as a copy holds it), so that two worlds hashing
  // alike step alike: what the setters change as well as the motion.
  StateHash h;
  h.add(impl_->def.gravity);
  for (uint32_t i = 0; i < impl_->bodies.size(); ++i) {
    const Body& b = impl_->bodies[i];
    if (!b.alive) continue;
    h.add(uint64_t(i));
    h.add(b.pose);
    h.add(b.v);
    h.add(b.w);
    h.add(uint64_t(b.awake));
    h.add(uint64_t(b.type)), h.add(b.invMass), h.add(b.principalInertia);
    h.add(b.material.staticFriction), h.add(b.material.dynamicFriction);
    h.add(b.material.restitution);
    h.add(b.gravityScale), h.add(b.linearDamping), h.add(b.angularDamping);
    h.add(uint64_t(b.allowSleep)), h.add(b.sleepTime), h.add(b.restCom), h.add(b.restQ);
    h.add(b.filter.category), h.add(b.filter.mask), h.add(uint64_t(int64_t{b.filter.group}));
  }
  for (uint32_t i = 0; i < impl_->joints.size(); ++i) {
    const detail::Joint& j = impl_->joints[i];
    if (!j.alive) continue;
    h.add(uint64_t(i));
    for (double x : j.impulse) h.add(x);
    h.add(j.lowerImpulse), h.add(j.upperImpulse), h.add(j.motorImpulse), h.add(j.springImpulse);
    h.add(j.rodStretch);
    if (j.type == JointType::Distance) h.add(j.restLength);  // setJointLength changes it
    h.add(uint64_t(j.enableLimit)), h.add(j.lower), h.add(j.upper);
    h.add(uint64_t(j.enableMotor)), h.add(j.motorSpeed), h.add(j.maxMotorForce);
    h.add(uint64_t(j.enableSpring)), h.add(j.springHertz), h.add(j.springDampingRatio);
    h.add(j.springTarget);
  }
  // The contacts' warm-start memory, whichever of the contact lists holds each (that depends
  // on what moved): summed and xored over manifolds, so in no particular order.
  uint64_t sum = 0, mixed = 0;
  impl_->contacts.forEach([&](const detail::ContactManifold& c) {
    StateHash m;
    m.add(uint64_t(c.bodyA)), m.add(uint64_t(c.bodyB));
    m.add(uint64_t(c.m.childA)), m.add(uint64_t(c.m.childB));
    for (int k = 0; k < c.m.pointCount; ++k)
      m.add(uint64_t(c.state[k].featureId)), m.add(c.state[k].normalImpulse);
    for (double x : c.friction) m.add(x);
    m.add(uint64_t(c.sliding)), m.add(uint64_t(c.anchored));
    sum += m.value(), mixed ^= m.value();
  });
  h.add(sum), h.add(mixed);
  return h.value();
}

double totalEnergy(const World& w) {
  double e = 0.0;
  for (BodyId id : w.bodies()) {
    if (w.bodyType(id) != BodyType::Dynamic) continue;
    const double m = w.mass(id);
    const Vec3 v = w.linearVelocity(id), om = w.angularVelocity(id);
    e += 0.5 * m * v.squaredNorm() + 0.5 * om.dot(w.inertiaWorld(id) * om);
    e -= m * w.gravity().dot(w.centerOfMass(id));
  }
  return e;
}

}  // namespace grip
