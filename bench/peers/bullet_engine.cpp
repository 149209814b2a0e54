// Bullet behind the sweep's Sim interface.
#include <btBulletDynamicsCommon.h>

#include "peers/peers.hpp"

namespace grip::peers {

namespace {

class BulletSim final : public sweep::Sim {
 public:
  BulletSim(const sweep::SceneDef& sc, const sweep::Settings& s) : s_(s), sleep_(sc.sleep) {
    world_.setGravity(btVector3(sc.gravity.x(), sc.gravity.y(), sc.gravity.z()));
    world_.getSolverInfo().m_numIterations = s.iterations;
    // Bullet multiplies the friction and restitution of a pair: the ground's are 1.
    if (sc.ground)
      make(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), 0.0,
           btTransform::getIdentity(), 1.0, 1.0);
  }
  ~BulletSim() override {
    for (auto& c : constraints_) world_.removeConstraint(c.get());
    for (auto& b : bodies_) world_.removeRigidBody(b.get());
  }
  int add(const sweep::SolidDef& s) override {
    std::unique_ptr<btCollisionShape> shape;
    if (s.sphere)
      shape = std::make_unique<btSphereShape>(s.radius);
    else
      shape = std::make_unique<btBoxShape>(
          btVector3(s.halfExtents.x(), s.halfExtents.y(), s.halfExtents.z()));
    const btTransform t(
        btQuaternion(s.orientation.x(), s.orientation.y(), s.orientation.z(), s.orientation.w()),
        btVector3(s.position.x(), s.position.y(), s.position.z()));
    btRigidBody* b = make(std::move(shape), s.mass, t, s.friction, s.restitution);
    b->setLinearVelocity(
        btVector3(s.linearVelocity.x(), s.linearVelocity.y(), s.linearVelocity.z()));
    b->setAngularVelocity(
        btVector3(s.angularVelocity.x(), s.angularVelocity.y(), s.angularVelocity.z()));
    if (!sleep_) b->setActivationState(DISABLE_DEACTIVATION);
    if (!s.collides)
      b->setCollisionFlags(b->getCollisionFlags() | btCollisionObject::CF_NO_CONTACT_RESPONSE);
    dynamic_.push_back(b);
    return static_cast<int>(dynamic_.size()) - 1;
  }
  // Bullet keeps applied forces for every internal substep and clears them after the step.
  void addForce(int body, const Vec3& f) override {
    dynamic_[body]->activate();
    dynamic_[body]->applyCentralForce(btVector3(f.x(), f.y(), f.z()));
  }
  void joinBall(int a, int b, const Vec3& anchor) override {
    btRigidBody& B = *dynamic_[b];
    const btVector3 at(anchor.x(), anchor.y(), anchor.z());
    const btVector3 inB = B.getCenterOfMassTransform().inverse() * at;
    if (a < 0) {
      constraints_.push_back(std::make_unique<btPoint2PointConstraint>(B, inB));
    } else {
      btRigidBody& A = *dynamic_[a];
      const btVector3 inA = A.getCenterOfMassTransform().inverse() * at;
      constraints_.push_back(std::make_unique<btPoint2PointConstraint>(A, B, inA, inB));
    }
    world_.addConstraint(constraints_.back().get(), true);  // no contacts between the two
  }
  void step() override { world_.stepSimulation(s_.dt, s_.substeps, s_.dt / s_.substeps); }
  Vec3 position(int body) const override {
    const btVector3& o = dynamic_[body]->getWorldTransform().getOrigin();
    return Vec3(o.x(), o.y(), o.z());
  }
  Quat orientation(int body) const override {
    const btQuaternion q = dynamic_[body]->getWorldTransform().getRotation();
    return Quat(q.w(), q.x(), q.y(), q.z());
  }
  Vec3 linearVelocity(int body) const override {
    const btVector3& v = dynamic_[body]->getLinearVelocity();
    return Vec3(v.x(), v.y(), v.z());
  }
  Vec3 angularVelocity(int body) const override {
    const btVector3& w = dynamic_[body]->getAngularVelocity();
    return Vec3(w.x(), w.y(), w.z());
  }

 private:
  btRigidBody* make(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& t,
                    double friction, double restitution) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    motions_.push_back(std::make_unique<btDefaultMotionState>(t));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions_.back().get(), shape.get(),
                                                  inertia);
    info.m_friction = friction;
    info.m_restitution = restitution;
    shapes_.push_back(std::move(shape));
    bodies_.push_back(std::make_unique<btRigidBody>(info));
    world_.addRigidBody(bodies_.back().get());
    return bodies_.back().get();
  }

  sweep::Settings s_;
  bool sleep_;
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_{&config_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<btRigidBody*> dynamic_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
};

}  // namespace

sweep::Engine bulletEngine() {
  return sweep::engineOf<BulletSim>(
      "bullet", {1.0 / 60.0, 1, 10}, [](const std::string& scene, bool quick) {
        if (quick) return sweep::product({60, 240}, {1}, {10});
        if (scene == "pile") return sweep::product(sweep::kPileRatesHz, {1}, {5, 10, 20});
        return sweep::product({30, 60, 120, 240, 480}, {1, 4}, {5, 10, 20, 50});
      });
}

}  // namespace grip::peers
