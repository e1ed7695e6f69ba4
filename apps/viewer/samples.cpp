// The sample browser's list: scene files peeked at for their group, built-in samples made
// by the shared builders (samples.h).
#include "samples.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <system_error>

#include "inertia/articulation/builders.h"
#include "inertia/articulation/dynamics.h"
#include "inertia/articulation/kinematics.h"
#include "inertia/world/builders.h"

namespace inertia::viewer {

namespace {

namespace fs = std::filesystem;

// Bodies are filled field by field: nested designated initialisers of BodyDesc trip GCC 12's
// false -Wmaybe-uninitialized on BodySettings::name.
BodyDesc body(BodyType type, const Vec3& position, const Quat& orientation, const Shape& shape,
              const Material& material = {}) {
  BodyDesc b;
  b.settings.type = type;
  b.settings.position = position;
  b.settings.orientation = orientation;
  ShapeDesc& s = b.shapes.emplace_back();
  s.shape = shape;
  s.material = material;
  return b;
}

BodyDesc ground() {
  BodyDesc b = body(BodyType::Static, Vec3::Zero(), Quat::Identity(), Plane{Vec3::UnitY(), 0});
  b.settings.name = "ground";
  return b;
}

io::Scene sceneOf(std::vector<BodyDesc> bodies, const Vec3& eye, const Vec3& target) {
  io::Scene scene;
  scene.file = "builtin";
  scene.camera = io::Camera{.position = eye, .target = target, .fov = 45};
  scene.bodies.push_back(ground());
  for (BodyDesc& b : bodies) scene.bodies.push_back(std::move(b));
  return scene;
}

// Spheres dropped side by side, restitution 0 to 1 from left to right.
io::Scene restitutionRow() {
  std::vector<BodyDesc> bodies;
  for (int i = 0; i <= 5; ++i) {
    Material m;
    m.restitution = Real(i) / 5;
    bodies.push_back(body(BodyType::Dynamic, Vec3(Real(1.2) * Real(i - 3) + Real(0.6), 4, 0),
                          Quat::Identity(), Sphere{Real(0.4)}, m));
  }
  return sceneOf(std::move(bodies), Vec3(0, 3, 11), Vec3(0, 2, 0));
}

// Boxes on a 25-degree ramp, friction 0.1 to 0.7 (tan 25 deg = 0.47: the last two hold).
io::Scene frictionRamp() {
  const Real angle = Real(25) * std::numbers::pi_v<Real> / 180;
  const Quat tilt(Eigen::AngleAxis<Real>(angle, Vec3::UnitZ()));
  std::vector<BodyDesc> bodies;
  bodies.push_back(body(BodyType::Static, Vec3(0, 2, 0), tilt, Box{Vec3(6, Real(0.2), 4)}));
  bodies.back().settings.name = "ramp";
  for (int i = 0; i < 4; ++i) {
    const Vec3 local(3, Real(0.2) + Real(0.3), Real(-3) + Real(2) * Real(i));
    Material m;
    m.friction = Real(0.1) + Real(0.2) * Real(i);
    bodies.push_back(body(BodyType::Dynamic, Vec3(0, 2, 0) + tilt * local, tilt,
                          Box{Vec3::Constant(Real(0.3))}, m));
  }
  return sceneOf(std::move(bodies), Vec3(-7, 8, 13), Vec3(0, 2, 0));
}

// Joints: the jointed builders (pendulum, chain, ropeBridge, ragdoll) where they exist, the
// rest put together with ballJointAt/hingeJointAt/sliderJointAt. A ground plane, then the
// assembly (io::append shifts its joints past the ground).
io::Scene jointScene(const Assembly& a, const Vec3& eye, const Vec3& target) {
  io::Scene scene = sceneOf({}, eye, target);
  io::append(scene, a);
  return scene;
}

BodyDesc& tint(BodyDesc& b, const Vec3& rgb) {
  for (ShapeDesc& shape : b.shapes) shape.color = rgb;
  return b;
}

// Appends a body of one shape; returns its index.
int addPart(Assembly& a, BodyType type, const Vec3& position, const Quat& orientation,
            const Shape& shape, const Vec3& rgb, const Material& material = {}) {
  a.bodies.push_back(body(type, position, orientation, shape, material));
  tint(a.bodies.back(), rgb);
  return int(a.bodies.size()) - 1;
}

Quat about(const Vec3& axis, Real angle) {
  return Quat(Eigen::AngleAxis<Real>(angle, axis.normalized()));
}

const Vec3 kWood(Real(0.72), Real(0.52), Real(0.3)), kSteel(Real(0.7), Real(0.72), Real(0.78));
const Vec3 kRed(Real(0.85), Real(0.3), Real(0.2)), kBlue(Real(0.3), Real(0.55), Real(0.9));

// A static block behind a pivot on the world, to show where it is (the joints hold to the
// world, not to it).
void addMount(Assembly& a, const Vec3& pivot) {
  addPart(a, BodyType::Static, pivot - Vec3(0, 0, Real(0.2)), Quat::Identity(),
          Box{Vec3(Real(0.08), Real(0.08), Real(0.1))}, kSteel);
}

// A hinge pendulum released 1.2 rad from straight down.
io::Scene pendulumSample() {
  Assembly a = pendulum(
      {.pivot = Vec3(0, 3, 0), .length = Real(1.5), .bobRadius = Real(0.2), .angle = Real(1.2)});
  tint(a.bodies[0], kBlue);
  addMount(a, Vec3(0, 3, 0));
  return jointScene(a, Vec3(0, 2.5, 7), Vec3(0, 2, 0));
}

// Two rods on hinges about z, released horizontal: chaotic, and kept planar by the hinges.
io::Scene doublePendulum() {
  const Vec3 pivot(-1, 3.5, 0);
  const Quat along = about(Vec3::UnitZ(), -std::numbers::pi_v<Real> / 2);  // local y onto +x
  Assembly a;
  addPart(a, BodyType::Dynamic, pivot + Vec3(0.5, 0, 0), along, Capsule{Real(0.06), Real(0.5)},
          kBlue);
  addPart(a, BodyType::Dynamic, pivot + Vec3(1.4, 0, 0), along, Capsule{Real(0.06), Real(0.4)},
          kRed);
  a.joints.push_back({hingeJointAt(a, -1, 0, pivot, Vec3::UnitZ()), -1, 0});
  a.joints.push_back({hingeJointAt(a, 0, 1, pivot + Vec3(1, 0, 0), Vec3::UnitZ()), 0, 1});
  addMount(a, pivot);
  return jointScene(a, Vec3(0, 3, 7), Vec3(0, 2.5, 0));
}

// Sixteen capsules on ball joints released horizontal, a 2 kg sphere at the end: it falls,
// whips and swings.
io::Scene chainSample() {
  Assembly a = chain({.links = 16,
                      .top = Vec3(-2.4, 6, 0),
                      .direction = Vec3::UnitX(),
                      .linkRadius = Real(0.05),
                      .linkHalfHeight = Real(0.1),
                      .endMass = 2,
                      .endRadius = Real(0.2)});
  for (BodyDesc& b : a.bodies) tint(b, kSteel);
  tint(a.bodies.back(), kRed);
  return jointScene(a, Vec3(0, 3.5, 10), Vec3(0, 3, 0));
}

// Five steel balls on ball joints, the first released 0.7 rad out. The soft step's restitution
// passes an impact down a row of balls only one collision at a time: with the balls touching, or
// nearer than a step's travel (4.4 cm at 2.6 m/s and 1/60 s), it shares it out among them. So
// they hang 1.5 cm apart and the world steps at 1/240 s (one substep: the same solver rate).
io::Scene newtonsCradle() {
  const Material steel{.density = 7800, .friction = 0, .restitution = 1};
  Assembly a;
  for (int i = 0; i < 5; ++i) {
    append(a, pendulum({.pivot = Vec3(Real(0.315) * Real(i - 2), 2.5, 0),
                        .length = Real(1.5),
                        .bobRadius = Real(0.15),
                        .angle = i == 0 ? Real(-0.7) : Real(0),
                        .joint = JointType::Ball,
                        .material = steel,
                        .name = "cradle_" + std::to_string(i)}));
    tint(a.bodies.back(), kSteel);
  }
  // The frame the balls hang from (drawn only: the joints hold them to the world).
  addPart(a, BodyType::Static, Vec3(0, 2.55, 0), Quat::Identity(),
          Box{Vec3(Real(0.9), Real(0.05), Real(0.05))}, kWood);
  io::Scene scene = jointScene(a, Vec3(0, 2, 4.5), Vec3(0, 1.5, 0));
  scene.world.dt = Real(1.0 / 240);
  scene.world.substeps = 1;
  return scene;
}

// Static pillars under a rope bridge's posts (bodies ropeBridge puts after its planks).
void addPillars(Assembly& a, int planks) {
  for (int post : {planks, planks + 1}) {
    const Vec3 seam = a.bodies[std::size_t(post)].settings.position;
    const Real out = post == planks ? -1 : 1;
    addPart(a, BodyType::Static, Vec3(seam.x() + out * Real(0.3), seam.y() / 2 - Real(0.1), 0),
            Quat::Identity(), Box{Vec3(Real(0.25), seam.y() / 2 - Real(0.1), Real(0.8))}, kWood);
  }
}

// Sixteen planks on ball joints (a rope along either edge) between two posts; boxes and a
// ragdoll land on it.
io::Scene ropeBridgeSample() {
  Assembly a = ropeBridge({.planks = 16, .center = Vec3(0, 3, 0)});
  for (BodyDesc& b : a.bodies) tint(b, kWood);
  addPillars(a, 16);
  const Material light{.density = 300};
  for (int i = 0; i < 3; ++i)
    addPart(a, BodyType::Dynamic,
            Vec3(Real(-2.4) + Real(0.9) * Real(i), 4 + Real(0.6) * Real(i), 0), Quat::Identity(),
            Box{Vec3::Constant(Real(0.25))}, kRed, light);
  // Lying face down along the bridge, its head towards -x.
  append(a, ragdoll({.position = Vec3(Real(0.8), 5, 0),
                     .orientation = about(Vec3::UnitZ(), std::numbers::pi_v<Real> / 2) *
                                    about(Vec3::UnitY(), -std::numbers::pi_v<Real> / 2)}));
  for (std::size_t part = a.bodies.size() - kRagdollParts; part < a.bodies.size(); ++part)
    tint(a.bodies[part], kBlue);
  return jointScene(a, Vec3(0, 5, 10), Vec3(0, 2.5, 0));
}

// Ten steps, 0.3 m high and 0.45 m deep, below a landing; four ragdolls pushed off its edge,
// leaning forwards at different angles, tumble down.
io::Scene ragdollStairs() {
  Assembly a;
  constexpr int kSteps = 10;
  const Real rise = Real(0.3), run = Real(0.45), halfWidth = 2, landing = 4 * run;
  const Real start = -Real(kSteps) * run / 2;  // the landing's edge
  for (int k = 0; k < kSteps; ++k) {
    const Real h = Real(kSteps - k) * rise;
    const Real depth = k == 0 ? landing : run;
    const Real x = start + Real(k) * run - (k == 0 ? depth / 2 - run / 2 : 0);
    addPart(a, BodyType::Static, Vec3(x, h / 2, 0), Quat::Identity(),
            Box{Vec3(depth / 2, h / 2, halfWidth)}, k % 2 ? kWood : kSteel);
  }
  const Real top = Real(kSteps) * rise;
  for (int i = 0; i < 4; ++i) {
    const Real lean = Real(0.3) + Real(0.2) * Real(i);  // forwards: the head towards +x
    append(a, ragdoll({.position = Vec3(start - Real(0.6), top + Real(1.0),
                                        Real(0.9) * (Real(i) - Real(1.5))),
                       .orientation = about(Vec3::UnitY(), Real(0.3) * Real(i - 1)) *
                                      about(Vec3::UnitZ(), -lean),
                       .linearVelocity = Vec3(Real(2) + Real(0.4) * Real(i), 0, 0),
                       .name = "ragdoll_" + std::to_string(i)}));
    const Vec3 shirt = i % 2 ? kBlue : kRed;
    for (std::size_t part = a.bodies.size() - kRagdollParts; part < a.bodies.size(); ++part)
      tint(a.bodies[part], shirt);
  }
  return jointScene(a, Vec3(Real(2.5), Real(4.5), 8), Vec3(Real(-0.5), Real(1.3), 0));
}

// A bridge of 30 kg planks on hinges that break at 8 kN, and a 1 t crate dropped on it. The
// planks alone pull up to 4.3 kN on a seam as they drop from their arc into the catenary and
// settle (measured unbreakable, 5 s); the crate's landing pulls 75 kN.
io::Scene breakableBridge() {
  Assembly a = ropeBridge({.planks = 12,
                           .center = Vec3(0, 3, 0),
                           .joint = JointType::Hinge,
                           .breakForce = 8000,
                           .material = {.density = 500}});
  for (BodyDesc& b : a.bodies) tint(b, kWood);
  addPillars(a, 12);
  addPart(a, BodyType::Dynamic, Vec3(Real(0.6), Real(5.5), 0), about(Vec3::UnitY(), Real(0.3)),
          Box{Vec3::Constant(Real(0.4))}, kRed, {.density = 2000});
  return jointScene(a, Vec3(0, 4, 9), Vec3(0, 2, 0));
}

// Two doors on hinges about y: the left one's motor opens it against its upper limit and holds
// it there; a ball thrown at the right one swings it into its limit, and its spring (a door
// closer) shuts it again.
io::Scene hingedDoor() {
  Assembly a;
  const Box slab{Vec3(Real(0.5), 1, Real(0.04))}, post{Vec3(Real(0.05), Real(1.1), Real(0.05))};
  for (int side = 0; side < 2; ++side) {
    const Vec3 hinge(side == 0 ? Real(-2) : Real(0.5), Real(1.1), 0);
    const int frame = addPart(a, BodyType::Static, hinge - Vec3(Real(0.06), 0, 0), Quat::Identity(),
                              post, kSteel);
    const int door = addPart(a, BodyType::Dynamic, hinge + Vec3(Real(0.5), 0, 0), Quat::Identity(),
                             slab, side == 0 ? kBlue : kWood, {.density = 400});
    HingeJointSettings h = hingeJointAt(a, frame, door, hinge, Vec3::UnitY());
    if (side == 0) {
      h.limits = JointLimits{0, Real(1.5)};
      h.motor = JointMotor{.speed = Real(1.5), .maxForce = 40};
    } else {  // a door closer: a spring back to shut, against friction
      h.limits = JointLimits{Real(-1.2), Real(1.2)};
      h.spring = JointSpring{.frequency = Real(0.4), .dampingRatio = Real(0.3)};
      h.friction = 1;
    }
    a.joints.push_back({h, frame, door});
  }
  addPart(a, BodyType::Dynamic, Vec3(1, Real(1.2), 4), Quat::Identity(), Sphere{Real(0.2)}, kRed,
          {.density = 2000});
  a.bodies.back().settings.linearVelocity = Vec3(0, Real(1.5), -8);
  return jointScene(a, Vec3(-1, 3.5, 6), Vec3(0, 1, 0));
}

// A chassis on four wheels whose hinges' motors turn them at 5 rad/s (1.5 m/s), over two bumps
// and through a few light boxes.
io::Scene car() {
  Assembly a;
  const int chassis = addPart(a, BodyType::Dynamic, Vec3(-6, Real(0.6), 0), Quat::Identity(),
                              Box{Vec3(1, Real(0.15), Real(0.45))}, kRed, {.density = 300});
  const Quat wheelTurn = about(Vec3::UnitX(), std::numbers::pi_v<Real> / 2);  // local y onto z
  const Material rubber{.density = 800, .friction = 1};
  for (Real x : {Real(-0.7), Real(0.7)})
    for (Real z : {Real(-0.55), Real(0.55)}) {
      const Vec3 centre(-6 + x, Real(0.3), z);
      const int wheel =
          addPart(a, BodyType::Dynamic, centre, wheelTurn, Cylinder{Real(0.3), Real(0.08)},
                  Vec3::Constant(Real(0.15)), rubber);
      HingeJointSettings h = hingeJointAt(a, chassis, wheel, centre, Vec3::UnitZ());
      // Rolling towards +x turns a wheel clockwise seen from +z: negative about z.
      h.motor = JointMotor{.speed = -5, .maxForce = 60};
      a.joints.push_back({h, chassis, wheel});
    }
  for (Real x : {Real(-3), Real(-1)})
    addPart(a, BodyType::Static, Vec3(x, 0, 0), about(Vec3::UnitX(), std::numbers::pi_v<Real> / 2),
            Cylinder{Real(0.12), Real(1.2)}, kSteel);
  for (int i = 0; i < 6; ++i)
    addPart(a, BodyType::Dynamic,
            Vec3(Real(2.5) + Real(0.45) * Real(i % 2), Real(0.2 + 0.4 * (i / 2)),
                 Real(0.45) * Real(i % 3) - Real(0.45)),
            Quat::Identity(), Box{Vec3::Constant(Real(0.19))}, kWood, {.density = 100});
  return jointScene(a, Vec3(0, 3.5, 11), Vec3(0, 0.5, 0));
}

// A crank disc turned at 2 rad/s by its hinge's motor, a rod hinged to its pin at 0.45 m from
// the axle, and a piston on a slider along x: x = r cos t + sqrt(l^2 - r^2 sin^2 t).
io::Scene sliderCrank() {
  const Vec3 axle(-1, 2, 0);
  const Real r = Real(0.45), l = Real(1.5), z = Real(0.12);
  Assembly a;
  const int crank =
      addPart(a, BodyType::Dynamic, axle, about(Vec3::UnitX(), std::numbers::pi_v<Real> / 2),
              Cylinder{Real(0.6), Real(0.05)}, kSteel);
  const Vec3 pin = axle + Vec3(r, 0, z), wrist = axle + Vec3(r + l, 0, z);
  const int rod = addPart(a, BodyType::Dynamic, (pin + wrist) / 2, Quat::Identity(),
                          Box{Vec3(l / 2, Real(0.04), Real(0.04))}, kBlue);
  const int piston = addPart(a, BodyType::Dynamic, wrist, Quat::Identity(),
                             Box{Vec3(Real(0.2), Real(0.15), Real(0.15))}, kRed);
  HingeJointSettings drive = hingeJointAt(a, -1, crank, axle, Vec3::UnitZ());
  drive.motor = JointMotor{.speed = 2, .maxForce = 500};
  a.joints.push_back({drive, -1, crank});
  a.joints.push_back({hingeJointAt(a, crank, rod, pin, Vec3::UnitZ()), crank, rod});
  a.joints.push_back({hingeJointAt(a, rod, piston, wrist, Vec3::UnitZ()), rod, piston});
  a.joints.push_back({sliderJointAt(a, -1, piston, wrist, Vec3::UnitX()), -1, piston});
  return jointScene(a, Vec3(0, 3, 6), Vec3(0, 2, 0));
}

// A kinematic hub turning at 1.5 rad/s about y carries six chains on ball joints at its rim,
// each with a 2 kg seat: a chain swing ride, the seats flung out.
io::Scene kinematicDriver() {
  const Vec3 hubCentre(0, Real(4.5), 0);
  const Real rim = Real(1.5);
  Assembly a;
  const int hub = addPart(a, BodyType::Kinematic, hubCentre, Quat::Identity(),
                          Cylinder{rim, Real(0.08)}, kSteel);
  a.bodies[std::size_t(hub)].settings.angularVelocity = Vec3(0, Real(1.5), 0);
  addPart(a, BodyType::Static, Vec3(0, Real(2.2), 0), Quat::Identity(),
          Cylinder{Real(0.12), Real(2.2)}, kWood);  // the mast (drawn; the hub moves by itself)
  for (int i = 0; i < 6; ++i) {
    const Real angle = Real(i) * std::numbers::pi_v<Real> / 3;
    const Vec3 top =
        hubCentre + rim * Vec3(std::cos(angle), 0, std::sin(angle)) - Vec3(0, Real(0.08), 0);
    const int first = int(a.bodies.size());
    append(a, chain({.links = 6,
                     .top = top,
                     .linkRadius = Real(0.04),
                     .linkHalfHeight = Real(0.11),
                     .hangFromWorld = false,
                     .endMass = 2,
                     .endRadius = Real(0.15),
                     .name = "chain_" + std::to_string(i)}));
    for (std::size_t b = std::size_t(first); b < a.bodies.size(); ++b) tint(a.bodies[b], kSteel);
    tint(a.bodies.back(), i % 2 ? kRed : kBlue);
    a.joints.push_back({ballJointAt(a, hub, first, top), hub, first});
  }
  return jointScene(a, Vec3(0, 5, 10), Vec3(0, 3, 0));
}

// ---- Articulations -------------------------------------------------------------------------

namespace art = inertia::articulation;

// The 7-DOF arm (art::sevenDofArm, z up in its base frame) stood on the ground of the y-up
// world, and the moving target its hand follows: a circle in front of it.
const Transform kArmBase{
    Vec3(0, Real(0.06), 0),
    Quat(Eigen::AngleAxis<Real>(-std::numbers::pi_v<Real> / 2, Vec3::UnitX()))};
const Vec3 kArmTool(0, 0, Real(0.107));  // the hand's point in the last link's frame (m)
constexpr Real kTargetRate = Real(0.8);  // rad/s around the circle

Vec3 armTarget(double t, Vec3* velocity = nullptr) {
  const Real a = kTargetRate * Real(t);
  if (velocity) *velocity = Real(0.2) * kTargetRate * Vec3(0, std::cos(a), -std::sin(a));
  return Vec3(Real(0.45), Real(0.55) + Real(0.2) * std::sin(a), Real(0.2) * std::cos(a));
}

// Capsules from each link's origin to its child's joint (a sphere where they coincide), and the
// hand's sphere on the last.
std::vector<LinkShapeSettings> armShapes(const art::Model<Real>& model) {
  std::vector<LinkShapeSettings> shapes;
  const Real r = Real(0.055);
  for (int i = 0; i < model.linkCount(); ++i) {
    const Vec3 to = i + 1 < model.linkCount() ? Vec3(model.link(i + 1).Xtree.r) : kArmTool;
    LinkShapeSettings s{.link = i, .shape = Sphere{Real(0.065)}};
    if (to.norm() > Real(0.01)) {
      s.shape = Capsule{r, to.norm() / 2};
      s.pose = {to / 2, Quat::FromTwoVectors(Vec3::UnitY(), to)};
    }
    shapes.push_back(s);
  }
  shapes.push_back({.link = model.linkCount() - 1,
                    .shape = Sphere{Real(0.045)},
                    .pose = {kArmTool, Quat::Identity()}});
  return shapes;
}

// The arm in its ready pose on PD drives, and the target: a kinematic sphere that touches
// nothing (collision mask 0).
io::Scene armFollowingATarget() {
  io::ArticulationDesc arm;
  WorldArticulationSettings& s = arm.settings;
  s.name = "arm";
  s.model = art::sevenDofArm<Real>();
  s.shapes = armShapes(s.model);
  s.base = kArmBase;
  s.q = art::VectorX<Real>(7);
  s.q << 0, Real(-0.3), 0, Real(-2.2), 0, 2, Real(0.785);
  for (int i = 0; i < 7; ++i)
    s.model.setDrive(i, {.stiffness = i < 4 ? Real(800) : Real(200),
                         .damping = i < 4 ? Real(80) : Real(20),
                         .targetPosition = s.q(i)});
  BodyDesc target = body(BodyType::Kinematic, armTarget(0), Quat::Identity(), Sphere{Real(0.03)});
  target.settings.name = "target";
  target.shapes[0].filter.mask = 0;
  tint(target, kRed);
  io::Scene scene =
      sceneOf({target}, Vec3(Real(1.5), Real(0.9), Real(1.1)), Vec3(Real(0.25), Real(0.45), 0));
  scene.articulations.push_back(std::move(arm));
  return scene;
}

// Before each step: the target moves on; the hand's error and the target's velocity go
// through the arm's point Jacobian by damped least squares (dq = J^T (J J^T + l^2)^-1 dx) into
// the drives' targets, and the joints get gravity's torques (RNEA at rest) as feed-forward.
void followTarget(World& world) {
  BodyId target;
  for (BodyId b : world.rigidBodies().bodies())
    if (world.rigidBodies().name(b) == "target") target = b;
  const std::vector<ArticulationId> ids = world.articulations();
  if (target.isNull() || ids.empty()) return;
  const Real dt = world.settings().dt;
  Vec3 velocity;
  const Vec3 goal = armTarget(world.time() + double(dt), &velocity);
  world.rigidBodies().moveKinematic(target, {goal, Quat::Identity()}, dt);
  art::Articulation<Real>& arm = world.articulation(ids.front());
  const art::Model<Real>& model = arm.model();
  const art::VectorX<Real> q = arm.q();
  const int hand = model.linkCount() - 1;
  const Mat3 toBase = kArmBase.q.toRotationMatrix().transpose();
  const Vec3 error = toBase * (goal - kArmBase.p) - art::pointPosition(model, q, hand, kArmTool);
  const Eigen::Matrix<Real, 3, Eigen::Dynamic> J =
      art::pointJacobian(model, q, hand, kArmTool).bottomRows<3>();
  const Mat3 JJt = J * J.transpose() + Real(0.01) * Mat3::Identity();
  const art::VectorX<Real> dq = J.transpose() * JJt.ldlt().solve(error);
  const art::VectorX<Real> qd = J.transpose() * JJt.ldlt().solve(toBase * velocity);
  for (int i = 0; i < model.nv(); ++i)
    arm.setDriveTarget(i, std::clamp(q(i) + dq(i), model.lower()(i), model.upper()(i)), qd(i));
  arm.setJointForces(art::rnea(model, q, art::VectorX<Real>::Zero(model.nv()),
                               art::VectorX<Real>::Zero(model.nv())));
}

// The same eight-link pendulum twice, released 1.2 rad out: in reduced coordinates (an
// articulation of revolute joints, blue) and in maximal ones (spheres on hinge joints, steel),
// side by side. Equal masses and inertias; neither collides with itself.
io::Scene chainsSideBySide() {
  const int links = 8;
  const Real length = Real(0.3), mass = Real(0.5), radius = Real(0.06);
  const Real inertia = Real(0.4) * mass * radius * radius;
  const Vec3 pivot(0, Real(3.2), 0);
  io::ArticulationDesc tree;
  WorldArticulationSettings& s = tree.settings;
  s.name = "reduced";
  s.base = {pivot + Vec3(0, 0, Real(-0.4)), Quat::Identity()};
  for (int i = 0; i < links; ++i) {
    s.model.addLink({.name = "l" + std::to_string(i),
                     .parent = i - 1,
                     .joint = {.type = art::JointType::Revolute,
                               .originPosition = i == 0 ? Vec3::Zero() : Vec3(0, -length, 0),
                               .axis = Vec3::UnitZ()},
                     .inertia = {mass, Vec3(0, -length, 0), Mat3::Identity() * inertia}});
    s.shapes.push_back({.link = i,
                        .shape = Sphere{radius},
                        .pose = {Vec3(0, -length, 0), Quat::Identity()},
                        .material = {.friction = 0}});
  }
  s.q = art::VectorX<Real>::Zero(links);
  s.q(0) = Real(1.2);
  Assembly a;
  const Quat turn = about(Vec3::UnitZ(), Real(1.2));
  const Vec3 offset(0, 0, Real(0.4));
  Material steel{
      .density = mass / (Real(4.0 / 3.0) * std::numbers::pi_v<Real> * radius * radius * radius),
      .friction = 0};
  for (int i = 0; i < links; ++i) {
    const Vec3 at = pivot + offset + turn * Vec3(0, -length * Real(i + 1), 0);
    addPart(a, BodyType::Dynamic, at, turn, Sphere{radius}, kSteel, steel);
    a.bodies.back().shapes[0].filter.group = -1;  // the chain's spheres pass each other
    const Vec3 hinge = pivot + offset + turn * Vec3(0, -length * Real(i), 0);
    a.joints.push_back({hingeJointAt(a, i - 1, i, hinge, Vec3::UnitZ()), i - 1, i});
  }
  addMount(a, pivot + offset);
  io::Scene scene = jointScene(a, Vec3(Real(2.5), Real(2.2), Real(6)), Vec3(0, Real(2), 0));
  scene.articulations.push_back(std::move(tree));
  return scene;
}

}  // namespace

std::vector<Sample> builtinSamples() {
  std::vector<Sample> s;
  s.push_back({"Stacking", "Pyramid (10)",
               [] { return sceneOf(pyramid({.base = 10}), Vec3(0, 5, 20), Vec3(0, 4, 0)); }});
  s.push_back({"Stacking", "Tower (12)",
               [] { return sceneOf(tower({.height = 12}), Vec3(0, 6, 18), Vec3(0, 5, 0)); }});
  s.push_back({"Stacking", "Brick wall", [] {
                 return sceneOf(wall({.rows = 8, .columns = 10}), Vec3(0, 3, 14), Vec3(0, 2, 0));
               }});
  s.push_back({"Collision", "Box rain",
               [] { return sceneOf(rain({.count = 150}), Vec3(0, 10, 26), Vec3(0, 4, 0)); }});
  s.push_back({"Collision", "Capsule rain", [] {
                 return sceneOf(rain({.count = 120, .shape = Capsule{Real(0.3), Real(0.4)}}),
                                Vec3(0, 10, 26), Vec3(0, 4, 0));
               }});
  s.push_back({"Collision", "Sphere lattice", [] {
                 return sceneOf(grid({.counts = {6, 6, 6}, .origin = Vec3(-2.75, 1, -2.75)}),
                                Vec3(0, 8, 20), Vec3(0, 3, 0));
               }});
  s.push_back({"Contacts", "Restitution row", restitutionRow});
  s.push_back({"Contacts", "Friction ramp", frictionRamp});
  s.push_back({"Joints", "Pendulum", pendulumSample});
  s.push_back({"Joints", "Double pendulum", doublePendulum});
  s.push_back({"Joints", "Chain", chainSample});
  s.push_back({"Joints", "Newton's cradle", newtonsCradle});
  s.push_back({"Joints", "Rope bridge", ropeBridgeSample});
  s.push_back({"Joints", "Ragdolls on stairs", ragdollStairs});
  s.push_back({"Joints", "Breakable bridge", breakableBridge});
  s.push_back({"Joints", "Hinged doors", hingedDoor});
  s.push_back({"Joints", "Car", car});
  s.push_back({"Joints", "Slider-crank", sliderCrank});
  s.push_back({"Joints", "Kinematic driver", kinematicDriver});
  s.push_back({"Articulations", "Arm following a target", armFollowingATarget, {}, followTarget});
  s.push_back({"Articulations", "Reduced and maximal chains", chainsSideBySide});
  return s;
}

std::vector<Sample> sceneFileSamples(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".json") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Sample> samples;
  for (const fs::path& file : files) {
    // A peek, not a load: an unreadable or broken file still appears and reports its error
    // when chosen.
    std::string group = "Scenes";
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    const auto lists = [&j](const char* key) {
      return j.is_object() && j.contains(key) && j[key].is_array() && !j[key].empty();
    };
    if (lists("particle_systems"))
      group = "Particles";
    else if (lists("deformables"))
      group = "Deformables";
    samples.push_back({group, file.stem().string(), [file] { return io::loadScene(file); }, file});
  }
  return samples;
}

std::vector<Sample> allSamples(const std::optional<fs::path>& scenesDir) {
  std::vector<Sample> samples;
  if (scenesDir) samples = sceneFileSamples(*scenesDir);
  for (Sample& s : builtinSamples()) samples.push_back(std::move(s));
  return samples;
}

std::optional<std::size_t> findSample(const std::vector<Sample>& samples,
                                      const std::string& nameOrFile) {
  std::error_code ec;
  const fs::path wanted = fs::weakly_canonical(nameOrFile, ec);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].file.empty() && !ec) {
      std::error_code ec2;
      if (fs::weakly_canonical(samples[i].file, ec2) == wanted && !ec2) return i;
    }
  }
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].name == nameOrFile) return i;
  return std::nullopt;
}

std::optional<fs::path> findScenesDir(const std::optional<fs::path>& explicitDir,
                                      const fs::path& executable, const fs::path& sourceDir) {
  std::error_code ec;
  if (explicitDir) {
    if (fs::is_directory(*explicitDir, ec)) return *explicitDir;
    return std::nullopt;
  }
  if (!executable.empty()) {
    fs::path dir = executable.parent_path();
    for (int up = 0; up <= 4 && !dir.empty(); ++up, dir = dir.parent_path()) {
      if (fs::is_directory(dir / "scenes", ec)) return dir / "scenes";
      if (dir == dir.root_path()) break;
    }
  }
  if (!sourceDir.empty() && fs::is_directory(sourceDir / "scenes", ec)) return sourceDir / "scenes";
  return std::nullopt;
}

std::vector<std::string> sampleGroups(const std::vector<Sample>& samples) {
  std::vector<std::string> groups;
  for (const Sample& s : samples)
    if (std::find(groups.begin(), groups.end(), s.group) == groups.end()) groups.push_back(s.group);
  return groups;
}

}  // namespace inertia::viewer
