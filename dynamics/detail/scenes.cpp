#include "dynamics/scenes.hpp"

namespace grip::scenes {

BodyId addGround(World& w, double staticFriction, double dynamicFriction) {
  BodyDef g;
  g.type = BodyType::Static;
  g.shape = Shape::plane(Vec3::UnitY(), 0.0);
  g.material.staticFriction = staticFriction;
  g.material.dynamicFriction = dynamicFriction;
  g.name = "ground";
  return w.createBody(g);
}

std::vector<BodyId> addBoxStack(World& w, int count, double size, double mass, const Vec3& base) {
  std::vector<BodyId> ids;
  const ShapePtr cube = Shape::box(Vec3::Constant(size / 2));
  for (int i = 0; i < count; ++i) {
    BodyDef d;
    d.shape = cube;
    d.mass = mass;
    d.position = base + Vec3(0, size / 2 + size * i, 0);
    d.name = "stack" + std::to_string(i);
    ids.push_back(w.createBody(d));
  }
  return ids;
}

std::vector<BodyId> addBoxPile(World& w, int count) {
  std::vector<BodyId> ids;
  const ShapePtr cube = Shape::box(Vec3::Constant(0.1));
  for (int i = 0; i < count; ++i) {
    const int x = i % 10, z = (i / 10) % 10, layer = i / 100;
    BodyDef d;
    d.shape = cube;
    d.mass = 1.0;
    const double stagger = (layer % 2) * 0.1;
    d.position = Vec3(x * 0.25 - 1.125 + stagger, 0.15 + layer * 0.25, z * 0.25 - 1.125 + stagger);
    d.orientation = Quat(Eigen::AngleAxisd(0.1 * (i % 7), Vec3(1, 2, 3).normalized()));
    ids.push_back(w.createBody(d));
  }
  return ids;
}

std::vector<BodyId> addJengaTower(World& w, int layers) {
  const double len = 0.075, height = 0.015, width = 0.025;
  const ShapePtr alongX = Shape::box(Vec3(0.5 * len, 0.5 * height, 0.5 * width));
  const ShapePtr alongZ = Shape::box(Vec3(0.5 * width, 0.5 * height, 0.5 * len));
  std::vector<BodyId> ids;
  for (int layer = 0; layer < layers; ++layer) {
    const double y = 0.5 * height + layer * height;
    const bool inX = layer % 2 == 0;
    for (int k = -1; k <= 1; ++k) {
      BodyDef d;
      d.shape = inX ? alongX : alongZ;
      d.mass = 0.014;
      d.position = inX ? Vec3(0.0, y, k * width) : Vec3(k * width, y, 0.0);
      d.material.staticFriction = 0.4;
      d.material.dynamicFriction = 0.35;
      d.name = "box";
      ids.push_back(w.createBody(d));
    }
  }
  return ids;
}

std::vector<BodyId> addChain(World& w, int links, const Vec3& top, double linkMass, double endMass,
                             bool joined) {
  CollisionFilter apart;
  apart.group = -1;
  BodyDef anchor;
  anchor.type = BodyType::Static;
  anchor.shape = Shape::box(Vec3::Constant(0.05));
  anchor.position = top;
  anchor.filter = apart;
  BodyId above = w.createBody(anchor);
  const ShapePtr rod = Shape::capsule(0.02, 0.05);  // along its y, turned to lie along x
  std::vector<BodyId> ids;
  for (int k = 0; k < links; ++k) {
    BodyDef d;
    d.shape = rod;
    d.position = top + Vec3(0.1 * (k + 1), 0.0, 0.0);
    d.orientation = Quat(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitZ()));
    d.mass = k == links - 1 ? endMass : linkMass;
    d.filter = apart;
    const BodyId link = w.createBody(d);
    if (joined) {
      JointDef j;
      j.type = JointType::Ball;
      j.a = above, j.b = link;
      j.anchor = top + Vec3(0.1 * k + 0.05, 0.0, 0.0);
      w.createJoint(j);
    }
    ids.push_back(link);
    above = link;
  }
  return ids;
}

}  // namespace grip::scenes
