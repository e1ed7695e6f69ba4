// A few steps of a small random world: a ground, up to six bodies of random shapes, sizes,
// poses and velocities, a particle system with an emitter, gravity and an obstacle, then an
// articulation (a random tree of up to five links), up to five joints of every type between
// the bodies, the links and the world, and a deformable (rope, cloth, soft box or sphere) with
// pins and an attachment, at a random time step and substep count. The API may refuse settings
// (InvalidArgument); a world it accepted must stay finite: no NaN in a body's state, a
// particle's, a link's coordinates or a vertex's.
//
// The articulation, joints and deformable are read after everything else, so inputs written
// before they were added (the committed corpus) still make the worlds they made, now without
// them (past the end every read gives zeros).
#include <algorithm>
#include <vector>

#include "fuzz_input.h"
#include "inertia/articulation/builders.h"
#include "inertia/core/error.h"
#include "inertia/deformable/generators.h"
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

std::optional<JointLimits> limits(fuzz::Input& in, Real scale) {
  if (in.pick(2) == 0) return std::nullopt;
  const Real lower = in.real(scale), upper = in.real(scale);
  return JointLimits{lower, upper};
}

std::optional<JointMotor> motor(fuzz::Input& in) {
  if (in.pick(2) == 0) return std::nullopt;
  JointMotor m;
  m.speed = in.real(10);
  m.maxForce = in.real(1000);
  if (in.pick(2) == 0) m.target = in.real(3);
  m.servoFrequency = in.real(10);
  return m;
}

std::optional<JointSpring> spring(fuzz::Input& in) {
  if (in.pick(2) == 0) return std::nullopt;
  JointSpring s;
  s.frequency = in.real(20);
  s.dampingRatio = in.real(2);
  s.rest = in.real(1);
  return s;
}

// Bodies to join: a null id (the world) or one of `bodies`.
BodyId pickBody(fuzz::Input& in, const std::vector<BodyId>& bodies) {
  const unsigned k = in.pick(unsigned(bodies.size()) + 1);
  return k == 0 ? BodyId{} : bodies[k - 1];
}

// One joint of a random type; the settings shared by every type are read first.
JointId addJoint(World& world, fuzz::Input& in, const std::vector<BodyId>& bodies, Real scale) {
  const unsigned type = in.pick(7);
  const BodyId a = pickBody(in, bodies), b = pickBody(in, bodies);
  const Vec3 anchorA = in.vec(scale), anchorB = in.vec(scale);
  const Vec3 axisA = in.vec(), axisB = in.vec();
  const Real breakForce = in.pick(4) == 0 ? in.real(1e4) : kUnbreakable;
  const bool collide = in.byte() & 1;
  // The settings every type shares, then the joint (reads nothing: the bytes' order stays).
  const auto create = [&](auto& j) {
    j.breakForce = breakForce;
    j.collideConnected = collide;
    return world.createJoint(j);
  };
  switch (type) {
    case 0: {
      BallJointSettings j{.bodyA = a,
                          .bodyB = b,
                          .anchorA = anchorA,
                          .anchorB = anchorB,
                          .axisA = axisA,
                          .axisB = axisB};
      if (in.pick(2) == 0) j.coneLimit = in.real(3);
      j.twistLimits = limits(in, 3);
      j.friction = in.real(10);
      return create(j);
    }
    case 1: {
      HingeJointSettings j{.bodyA = a,
                           .bodyB = b,
                           .anchorA = anchorA,
                           .anchorB = anchorB,
                           .axisA = axisA,
                           .axisB = axisB};
      j.limits = limits(in, 3);
      j.motor = motor(in);
      j.spring = spring(in);
      j.friction = in.real(10);
      return create(j);
    }
    case 2: {
      SliderJointSettings j{
          .bodyA = a, .bodyB = b, .anchorA = anchorA, .anchorB = anchorB, .axisA = axisA};
      j.limits = limits(in, scale);
      j.motor = motor(in);
      j.spring = spring(in);
      j.friction = in.real(10);
      return create(j);
    }
    case 3: {
      UniversalJointSettings j{.bodyA = a,
                               .bodyB = b,
                               .anchorA = anchorA,
                               .anchorB = anchorB,
                               .axisA = axisA,
                               .axisB = axisB};
      j.limitsA = limits(in, 3);
      j.limitsB = limits(in, 2);
      return create(j);
    }
    case 4: {
      WeldJointSettings j{.bodyA = a, .bodyB = b, .anchorA = anchorA, .anchorB = anchorB};
      j.spring = spring(in);
      return create(j);
    }
    case 5: {
      DistanceJointSettings j{.bodyA = a, .bodyB = b, .anchorA = anchorA, .anchorB = anchorB};
      j.length = in.real(scale);
      j.minLength = in.real(scale);
      j.maxLength = in.real(scale);
      j.spring = spring(in);
      return create(j);
    }
    default: {
      SixDofJointSettings j{.bodyA = a, .bodyB = b};
      j.frameA = in.pose(scale);
      j.frameB = in.pose(scale);
      for (JointAxis& axis : j.axes) {
        axis.locked = in.pick(3) == 0;
        axis.limits = limits(in, 3);
        axis.motor = motor(in);
        axis.spring = spring(in);
        axis.friction = in.real(10);
      }
      return create(j);
    }
  }
}

// A random tree of up to five links with a sphere on each, its base above the ground; its link
// bodies join `bodies` (joints to them close loops).
std::optional<ArticulationId> addArticulation(World& world, fuzz::Input& in,
                                              std::vector<BodyId>& bodies, Real scale) {
  if (in.pick(2) == 0) return std::nullopt;
  articulation::RandomTreeOptions options;
  options.links = 1 + int(in.pick(5));
  options.floatingBase = in.byte() & 1;
  options.armature = in.byte() & 1;
  options.seed = in.byte();
  WorldArticulationSettings settings;
  settings.name = "tree";
  settings.model = articulation::randomTree<Real>(options);
  for (int link = 0; link < options.links; ++link)
    settings.shapes.push_back(
        {.link = link,
         .shape = Sphere{std::clamp(Real(0.1) * scale * in.size(), Real(1e-3), Real(10))}});
  settings.base = Transform{in.vec(scale) + Vec3(0, 2 * scale, 0), in.rotation()};
  if (in.byte() & 1) articulation::randomState(settings.model, in.byte(), settings.q, settings.qd);
  const ArticulationId id = world.createArticulation(settings);
  for (int link = 0; link < options.links; ++link) bodies.push_back(world.linkBody(id, link));
  return id;
}

MassSpringModel deformableModel(fuzz::Input& in, Real scale) {
  const Transform pose{in.vec(scale) + Vec3(0, scale, 0), in.rotation()};
  const Real size = std::clamp(scale * in.size(), Real(1e-3), Real(100));
  constexpr Real kStiffness[] = {10, 1e3, 1e5, 1e7};
  const SpringStiffness k{kStiffness[in.pick(4)], kStiffness[in.pick(4)], kStiffness[in.pick(4)]};
  const Real mass = Real(std::pow(10.0, int(in.pick(7)) - 3));  // 1 g .. 1 t
  const Real damping = in.pick(2) == 0 ? 0 : Real(in.pick(100));
  const int n = 1 + int(in.pick(5));
  switch (in.pick(4)) {
    case 0:
      return rope({.from = pose.p,
                   .to = pose.p + in.vec(size),
                   .segments = n,
                   .mass = mass,
                   .stiffness = k,
                   .damping = damping});
    case 1:
      return cloth({.pose = pose,
                    .size = {size, size},
                    .resolution = {n, n},
                    .mass = mass,
                    .stiffness = k,
                    .damping = damping});
    case 2:
      return softBox({.pose = pose,
                      .halfExtents = Vec3::Constant(size / 2),
                      .resolution = {n, n, n},
                      .mass = mass,
                      .stiffness = k,
                      .damping = damping});
    default:
      return softSphere({.pose = pose,
                         .radius = size,
                         .subdivisions = int(n > 2),
                         .mass = mass,
                         .stiffness = k,
                         .damping = damping});
  }
}

// A deformable with up to two pinned vertices and an attachment to one of `bodies`.
std::optional<DeformableId> addDeformable(World& world, fuzz::Input& in,
                                          const std::vector<BodyId>& bodies, Real scale) {
  if (in.pick(2) == 0) return std::nullopt;
  constexpr ode::Method kMethods[] = {ode::Method::BackwardEuler, ode::Method::SymplecticEuler,
                                      ode::Method::Rk4, ode::Method::ExplicitEuler};
  DeformableSettings settings;
  settings.integrator = kMethods[in.pick(4)];
  settings.thickness = std::clamp(Real(0.01) * scale * in.size(), Real(1e-5), Real(1));
  settings.friction = Real(in.pick(5)) / 4;
  settings.tearStrain = Real(in.pick(4)) / 2;
  settings.selfCollision = in.byte() & 1;
  settings.collideWithBodies = in.byte() & 1;
  MassSpringModel model = deformableModel(in, scale);
  const std::uint32_t vertices = std::uint32_t(model.masses.size());
  for (unsigned i = in.pick(3); i > 0; --i) model.pinned.push_back(in.byte() % vertices);
  const DeformableId id = world.createDeformable(settings, model);
  if (!bodies.empty() && in.pick(2) == 0) {
    Attachment a;
    a.vertex = in.byte() % vertices;
    a.body = bodies[in.pick(unsigned(bodies.size()))];
    a.anchor = in.vec(scale);
    a.stiffness = Real(std::pow(10.0, int(in.pick(7))));
    a.damping = Real(in.pick(10));
    try {
      world.deformable(id).addAttachment(a);
    } catch (const InvalidArgument&) {
      // refused with a message; the deformable stays, unattached
    }
  }
  return id;
}

void checkFinite(World& world, const std::vector<BodyId>& bodies,
                 std::optional<ParticleSystemId> ps, std::optional<ArticulationId> tree,
                 std::optional<DeformableId> deformable) {
  for (BodyId b : bodies) {
    const Transform t = world.transform(b);
    INERTIA_FUZZ_FINITE(t.p);
    INERTIA_FUZZ_FINITE(t.q);
    INERTIA_FUZZ_FINITE(world.linearVelocity(b));
    INERTIA_FUZZ_FINITE(world.angularVelocity(b));
  }
  if (ps)
    for (Real x : world.particleSystem(*ps).pool().positions()) INERTIA_FUZZ_FINITE(x);
  if (tree) {
    for (Real x : world.articulation(*tree).q()) INERTIA_FUZZ_FINITE(x);
    for (Real x : world.articulation(*tree).qd()) INERTIA_FUZZ_FINITE(x);
  }
  if (deformable) {
    for (Real x : world.deformable(*deformable).positions()) INERTIA_FUZZ_FINITE(x);
    for (Real x : world.deformable(*deformable).velocities()) INERTIA_FUZZ_FINITE(x);
  }
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
    // Each part may be refused on its own (a zero axis, a lower limit above the upper): the
    // world goes on without it.
    const auto tryAdd = [](auto add) {
      try {
        return add();
      } catch (const InvalidArgument&) {
        return decltype(add())();
      }
    };
    const std::optional<ArticulationId> tree =
        tryAdd([&] { return addArticulation(world, in, bodies, scale); });
    for (unsigned j = in.pick(6); j > 0; --j)
      tryAdd([&] { return addJoint(world, in, bodies, scale); });
    const std::optional<DeformableId> deformable =
        tryAdd([&] { return addDeformable(world, in, bodies, scale); });
    for (int step = 0; step < 5; ++step) {
      world.step(ws.dt);
      checkFinite(world, bodies, ps, tree, deformable);
    }
  } catch (const InvalidArgument&) {
    return 0;  // refused at the API boundary, with a message
  }
  return 0;
}
