// A few steps of a small random world: a ground, up to six bodies of random shapes, sizes,
// poses and velocities, and a particle system with an emitter, gravity and an obstacle, at a
// random time step and substep count. The API may refuse settings (InvalidArgument); a world
// it accepted must stay finite: no NaN in a body's state or a particle's.
#include <algorithm>
#include <vector>

#include "fuzz_input.h"
#include "inertia/core/error.h"
#include "inertia/world/world.h"
#include "random_shape.h"

using namespace inertia;

namespace {

// Sizes from 0 (1e-8 m and up after the scale): the API refuses shapes whose mass properties
// Real cannot hold (kMinMassProperty); those light small bodies that it accepts must land.
constexpr Real kMinSize = 0;
// Up to 100 m for primitives. Hull points and shape offsets come from Input::real, whose
// special values reach 1e5 m whatever the scale: bodies far longer than thick, on purpose
// (fuzz/README.md, findings).
constexpr Real kMaxSize = Real(1e2);

Shape makeShape(fuzz::Input& in, Real scale) {
  const auto len = [&] { return std::clamp(scale * in.size(), kMinSize, kMaxSize); };
  return fuzz::randomShape(
      in, len, [] { return 8u; }, std::min(scale, kMaxSize));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::Input in(data, size);
  constexpr Real kSteps[] = {Real(1.0 / 60), Real(1e-5), Real(0.1), Real(1.0 / 240)};
  WorldSettings ws;
  ws.dt = kSteps[in.pick(4)];
  ws.substeps = 1 + int(in.pick(8));
  ws.gravity = in.pick(4) == 0 ? in.vec(20) : Vec3(0, Real(-9.81), 0);
  ws.threads = 1;
  ws.sleeping = in.byte() & 1;
  try {
    World world(ws);
    const BodyId ground = world.createBody({.type = BodyType::Static});
    if (in.byte() & 1)
      world.addShape(ground, Plane{Vec3(0, 1, 0), 0});
    else
      world.addShape(ground, Box{Vec3(50, 1, 50)}, {}, Transform{Vec3(0, -1, 0)});
    const Real scale = Real(std::pow(10.0, int(in.pick(5)) - 2));  // 1e-2 .. 1e2 m
    std::vector<BodyId> bodies;
    const unsigned n = in.pick(7);
    for (unsigned i = 0; i < n; ++i) {
      BodySettings bs;
      bs.type = in.pick(5) == 0 ? BodyType::Kinematic : BodyType::Dynamic;
      bs.position = in.vec(2 * scale) + Vec3(0, scale, 0);
      bs.orientation = in.rotation();
      bs.linearVelocity = in.vec(50);
      bs.angularVelocity = in.vec(20);
      bs.bullet = in.byte() & 1;
      const BodyId b = world.createBody(bs);
      Material m;
      m.density = Real(std::pow(10.0, 1 + 3 * in.pick(3) / 2.0));
      m.restitution = Real(in.pick(5)) / 4;
      m.friction = Real(in.pick(5)) / 4;
      world.addShape(b, makeShape(in, scale), m);
      if (in.pick(3) == 0) {
        const Shape second = makeShape(in, scale);
        world.addShape(b, second, m, in.pose(scale));
      }
      bodies.push_back(b);
    }
    std::optional<ParticleSystemId> ps;
    if (in.byte() & 1) {
      ParticleSystemSettings pss;
      pss.capacity = 1 + in.pick(200);
      pss.particleCollisions = in.byte() & 1;
      pss.collideWithBodies = in.byte() & 1;
      ps = world.createParticleSystem(pss);
      ParticleSystem& sys = world.particleSystem(*ps);
      EmitterSettings e;
      e.pose = Transform{in.vec(scale) + Vec3(0, scale, 0)};
      e.rate = Real(in.pick(4)) * 1000;
      e.burst = in.pick(64);
      e.direction = in.vec();
      if (!(e.direction.norm() > 0)) e.direction = Vec3::UnitY();
      e.spread = Real(in.pick(4));
      e.speed = {0, Real(in.pick(4)) * 100};
      e.size = {0, Real(0.01) * scale};
      sys.addEmitter(e);
      sys.addField(ForceField{GravityField{}});
      sys.addObstacle(Obstacle{Collider(makeShape(in, scale)), in.pose(scale)});
    }
    for (int step = 0; step < 5; ++step) {
      world.step(ws.dt);
      for (BodyId b : bodies) {
        const Transform t = world.transform(b);
        INERTIA_FUZZ_FINITE(t.p);
        INERTIA_FUZZ_FINITE(t.q);
        INERTIA_FUZZ_FINITE(world.linearVelocity(b));
        INERTIA_FUZZ_FINITE(world.angularVelocity(b));
      }
      if (ps)
        for (Real x : world.particleSystem(*ps).pool().positions()) INERTIA_FUZZ_FINITE(x);
    }
  } catch (const InvalidArgument&) {
    return 0;  // refused at the API boundary, with a message
  }
  return 0;
}
