// Drops a ball on a plane with an installed grip and checks it came to rest on the plane.
#include <grip/grip.hpp>

#include <cmath>
#include <cstdio>

int main() {
  grip::World world;
  grip::BodyDef ground;
  ground.type = grip::BodyType::Static;
  ground.shape = grip::Shape::plane(grip::Vec3::UnitY(), 0.0);
  world.createBody(ground);
  grip::BodyDef ball;
  ball.shape = grip::Shape::sphere(0.1);
  ball.position = grip::Vec3(0, 1, 0);
  const grip::BodyId id = world.createBody(ball);
  for (int i = 0; i < 120; ++i) world.step(1.0 / 60.0);
  const double y = world.pose(id).p.y();
  std::printf("ball rests at y = %.4f m\n", y);
  return std::abs(y - 0.1) < 0.005 ? 0 : 1;
}
