// Reference scenes built once and shared by tests, benchmarks and the demo.
#pragma once

#include <vector>

#include "dynamics/world.hpp"

namespace grip::scenes {

// A static ground plane at y = 0 with the given friction.
BodyId addGround(World& w, double staticFriction = 0.6, double dynamicFriction = 0.5);

// A vertical stack of `count` cubes of edge `size` and `mass`, resting exactly on the ground.
std::vector<BodyId> addBoxStack(World& w, int count, double size = 0.1, double mass = 1.0,
                                const Vec3& base = Vec3::Zero());

// `count` cubes of edge 0.2 m dropped in a 10 x 10 grid of columns, layer above layer,
// slightly staggered so they tumble into a pile.
std::vector<BodyId> addBoxPile(World& w, int count);

// A Jenga tower of `layers` layers resting exactly on y = 0: three blocks of 75 x 15 x 25 mm
// (14 g, friction 0.4 / 0.35) a layer, crosswise, the bottom layer running along x; blocks in
// layer order, each layer from -z (or -x) to +z (or +x).
std::vector<BodyId> addJengaTower(World& w, int layers);

// A chain of `links` thin links (capsules of radius 2 cm, 10 cm between their joints, lying
// along +x) from a static anchor at `top`, each joined to the one before by a ball joint at
// their shared end; the last link weighs `endMass`, the others `linkMass`. Nothing in it
// collides with anything (collision group -1: the joints alone). Returns the links, the first
// one at the anchor. Link k's joints sit at (0, +-0.05, 0) in its frame (+ toward the anchor).
std::vector<BodyId> addChain(World& w, int links, const Vec3& top, double linkMass = 0.1,
                             double endMass = 0.1, bool joined = true);

}  // namespace grip::scenes
