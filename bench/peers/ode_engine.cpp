// ODE behind the sweep's Sim interface.
#include <ode/ode.h>

#include <deque>

#include "peers/peers.hpp"

namespace grip::peers {

namespace {

// What a geom carries for the contact callback: the pair gets the products (ground: 1).
struct Surface {
  double friction = 1, restitution = 1;
};

class OdeSim final : public sweep::Sim {
 public:
  OdeSim(const sweep::SceneDef& sc, const sweep::Settings& s) : s_(s) {
    static const bool initialised = dInitODE2(0) != 0;  // once per process
    (void)initialised;
    // QuickStep visits its constraints in a random order drawn from ODE's global generator:
    // reseeded per world, every run of a setting is the same run (not the n-th draw).
    dRandSetSeed(0);
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, sc.gravity.x(), sc.gravity.y(), sc.gravity.z());
    if (s.iterations > 0) dWorldSetQuickStepNumIterations(world_, s.iterations);
    if (sc.ground) dGeomSetData(dCreatePlane(space_, 0, 1, 0, 0), &surfaces_.emplace_back());
  }
  ~OdeSim() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);  // and its geoms
    dWorldDestroy(world_);  // and its bodies
  }
  OdeSim(const OdeSim&) = delete;
  OdeSim& operator=(const OdeSim&) = delete;

  int add(const sweep::SolidDef& s) override {
    const dBodyID b = dBodyCreate(world_);
    dMass m;
    dGeomID g;
    if (s.sphere) {
      dMassSetSphereTotal(&m, s.mass, s.radius);
      g = dCreateSphere(space_, s.radius);
    } else {
      const Vec3 e = 2 * s.halfExtents;
      dMassSetBoxTotal(&m, s.mass, e.x(), e.y(), e.z());
      g = dCreateBox(space_, e.x(), e.y(), e.z());
    }
    dBodySetMass(b, &m);
    dGeomSetBody(g, b);
    if (!s.collides) dGeomSetCollideBits(g, 0), dGeomSetCategoryBits(g, 0);
    dGeomSetData(g, &surfaces_.emplace_back(Surface{s.friction, s.restitution}));
    dBodySetPosition(b, s.position.x(), s.position.y(), s.position.z());
    const dQuaternion q = {s.orientation.w(), s.orientation.x(), s.orientation.y(),
                           s.orientation.z()};
    dBodySetQuaternion(b, q);
    dBodySetLinearVel(b, s.linearVelocity.x(), s.linearVelocity.y(), s.linearVelocity.z());
    dBodySetAngularVel(b, s.angularVelocity.x(), s.angularVelocity.y(), s.angularVelocity.z());
    bodies_.push_back(b);
    forces_.push_back(Vec3::Zero());
    return static_cast<int>(bodies_.size()) - 1;
  }
  void joinBall(int a, int b, const Vec3& anchor) override {
    const dJointID j = dJointCreateBall(world_, nullptr);
    dJointAttach(j, a >= 0 ? bodies_[a] : nullptr, bodies_[b]);
    dJointSetBallAnchor(j, anchor.x(), anchor.y(), anchor.z());
  }
  // ODE clears forces after every dWorldStep: the force is re-applied for each substep.
  void addForce(int body, const Vec3& f) override { forces_[body] += f; }
  void step() override {
    const double h = s_.dt / s_.substeps;
    for (int k = 0; k < s_.substeps; ++k) {
      for (size_t i = 0; i < bodies_.size(); ++i)
        if (!forces_[i].isZero())
          dBodyAddForce(bodies_[i], forces_[i].x(), forces_[i].y(), forces_[i].z());
      dSpaceCollide(space_, this, &OdeSim::nearCallback);
      if (s_.iterations > 0)
        dWorldQuickStep(world_, h);
      else
        dWorldStep(world_, h);
      dJointGroupEmpty(contacts_);
    }
    for (Vec3& f : forces_) f.setZero();
  }
  Vec3 position(int body) const override { return vec(dBodyGetPosition(bodies_[body])); }
  Quat orientation(int body) const override {
    const dReal* q = dBodyGetQuaternion(bodies_[body]);
    return Quat(q[0], q[1], q[2], q[3]);
  }
  Vec3 linearVelocity(int body) const override { return vec(dBodyGetLinearVel(bodies_[body])); }
  Vec3 angularVelocity(int body) const override { return vec(dBodyGetAngularVel(bodies_[body])); }

 private:
  static Vec3 vec(const dReal* v) { return Vec3(v[0], v[1], v[2]); }

  static void nearCallback(void* data, dGeomID o1, dGeomID o2) {
    auto* self = static_cast<OdeSim*>(data);
    const dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    constexpr int kMax = 8;
    dContact c[kMax] = {};
    const int n = dCollide(o1, o2, kMax, &c[0].geom, sizeof(dContact));
    const auto* s1 = static_cast<const Surface*>(dGeomGetData(o1));
    const auto* s2 = static_cast<const Surface*>(dGeomGetData(o2));
    const double bounce = s1->restitution * s2->restitution;
    for (int i = 0; i < n; ++i) {
      c[i].surface.mode = dContactApprox1 | (bounce > 0 ? dContactBounce : 0);
      c[i].surface.mu = s1->friction * s2->friction;
      c[i].surface.bounce = bounce;
      c[i].surface.bounce_vel = 0.2;  // as Bullet's restitution threshold
      const dJointID j = dJointCreateContact(self->world_, self->contacts_, &c[i]);
      dJointAttach(j, b1, b2);
    }
  }

  sweep::Settings s_;
  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  std::deque<Surface> surfaces_;  // stable addresses for dGeomSetData
  std::vector<dBodyID> bodies_;
  std::vector<Vec3> forces_;
};

}  // namespace

sweep::Engine odeEngine() {
  return sweep::engineOf<OdeSim>(
      "ode", {1.0 / 60.0, 1, 20}, [](const std::string& scene, bool quick) {
        if (quick) return sweep::product({60, 240}, {1}, {20});
        // dWorldStep's direct solver is cubic in the rows of an island: not for the pile.
        if (scene == "pile") return sweep::product(sweep::kPileRatesHz, {1}, {10, 20, 40});
        return sweep::product({30, 60, 120, 240, 480}, {1}, {0, 5, 10, 20, 50});
      });
}

}  // namespace grip::peers
