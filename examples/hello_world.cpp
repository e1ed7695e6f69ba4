// The smallest Inertia program: a ball dropped on the ground, stepped at a fixed rate for ten
// seconds of frames. It bounces (restitution 0.5) and comes to rest on the ground.
#include <cstdio>

#include <inertia/inertia.h>

using namespace inertia;

int main() {
  World world({.gravity = {0, -9.81f, 0}, .dt = 1.0f / 60, .substeps = 4});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{{0, 1, 0}, 0}, Material{.friction = 0.6f});
  const BodyId ball = world.createBody({.position = {0, 5, 0}});
  world.addShape(ball, Sphere{0.5f}, Material{.density = 1000, .restitution = 0.5f});
  for (int frame = 0; frame < 600; ++frame) world.advance(1.0f / 60);  // fixed-step accumulator
  const Transform t = world.transform(ball);
  std::printf("simulated %.3f s in %lld steps; the ball rests at y = %.3f m\n", world.time(),
              (long long)world.stepCount(), double(t.p.y()));
  // At rest on the ground: the centre one radius up, within the contact slop.
  return world.time() > 9.9 && t.p.y() > 0.49f && t.p.y() < 0.51f ? 0 : 1;
}
