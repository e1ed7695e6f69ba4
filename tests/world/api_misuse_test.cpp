// Issue 21, API misuse: every public function of World, RigidBodySystem (bodies, shapes,
// joints), ParticleSystem and Deformable given stale or invalid ids, NaN, infinities, negative
// and zero sizes. Each must throw InvalidArgument whose message names the argument (or the id
// kind); nothing may crash, and the world must still step to finite values afterwards.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "inertia/core/error.h"
#include "inertia/deformable/generators.h"
#include "inertia/world/world.h"

namespace inertia {
namespace {

const Real kNaN = std::numeric_limits<Real>::quiet_NaN();
const Real kInf = std::numeric_limits<Real>::infinity();

struct Misuse {
  std::string what;  // the call, for the failure message
  std::function<void()> call;
  std::string named;  // a piece of the message that names the argument
};

// Runs every call: each must throw InvalidArgument mentioning `named`. Returns the count.
int expectAllRefused(const std::vector<Misuse>& calls) {
  int refused = 0;
  for (const Misuse& m : calls) {
    try {
      m.call();
      ADD_FAILURE() << m.what << ": accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(m.named), std::string::npos)
          << m.what << ": message '" << e.what() << "' does not name '" << m.named << "'";
      ++refused;
    } catch (const std::exception& e) {
      ADD_FAILURE() << m.what << ": threw something other than InvalidArgument: " << e.what();
    }
  }
  return refused;
}

// The bad values of each kind a caller may pass.
const Vec3 kBadVectors[] = {Vec3(kNaN, 0, 0), Vec3(0, kInf, 0), Vec3(0, 0, -kInf)};
const Real kBadSizes[] = {kNaN, kInf, -1, 0};

struct Fixture {
  World world{{.threads = 1}};
  BodyId ground, box, stale;
  ShapeId staleShape;
  JointId hinge, staleJoint;
  ParticleSystemId particles, staleParticles;
  DeformableId rope, staleRope;

  Fixture() {
    ground = world.createBody({.type = BodyType::Static});
    world.addShape(ground, Plane{Vec3::UnitY(), 0});
    box = world.createBody({.position = Vec3(0, 1, 0)});
    world.addShape(box, Box{Vec3::Constant(Real(0.5))});
    stale = world.createBody({});
    staleShape = world.addShape(stale, Sphere{1});
    world.destroyBody(stale);
    hinge = world.createJoint(HingeJointSettings{.bodyA = {}, .bodyB = box});
    staleJoint = world.createJoint(BallJointSettings{.bodyA = {}, .bodyB = box});
    world.destroyJoint(staleJoint);
    particles = world.createParticleSystem({.capacity = 100});
    staleParticles = world.createParticleSystem({});
    world.destroyParticleSystem(staleParticles);
    rope = world.createDeformable({}, inertia::rope({}));
    staleRope = world.createDeformable({}, inertia::rope({}));
    world.destroyDeformable(staleRope);
  }
};

TEST(ApiMisuse, StaleAndInvalidIdsAreRefusedEverywhere) {
  Fixture f;
  RigidBodySystem& rb = f.world.rigidBodies();
  const BodyId never{77, 1};
  std::vector<Misuse> calls;
  for (BodyId id : {f.stale, never, BodyId{}}) {
    const auto add = [&](std::string what, std::function<void()> call) {
      calls.push_back({what, std::move(call), "body id"});
    };
    add("destroyBody", [&, id] { f.world.destroyBody(id); });
    add("addShape", [&, id] { f.world.addShape(id, Sphere{1}); });
    add("transform", [&, id] { (void)f.world.transform(id); });
    add("linearVelocity", [&, id] { (void)f.world.linearVelocity(id); });
    add("angularVelocity", [&, id] { (void)f.world.angularVelocity(id); });
    add("centerOfMass", [&, id] { (void)rb.centerOfMass(id); });
    add("mass", [&, id] { (void)rb.mass(id); });
    add("inertiaWorld", [&, id] { (void)rb.inertiaWorld(id); });
    add("type", [&, id] { (void)rb.type(id); });
    add("name", [&, id] { (void)rb.name(id); });
    add("isAwake", [&, id] { (void)rb.isAwake(id); });
    add("setTransform", [&, id] { rb.setTransform(id, Transform{}); });
    add("setLinearVelocity", [&, id] { rb.setLinearVelocity(id, Vec3::Zero()); });
    add("setAngularVelocity", [&, id] { rb.setAngularVelocity(id, Vec3::Zero()); });
    add("moveKinematic", [&, id] { rb.moveKinematic(id, Transform{}, 1); });
    add("applyForce", [&, id] { rb.applyForce(id, Vec3::Zero(), Vec3::Zero()); });
    add("applyForceAtCenter", [&, id] { rb.applyForceAtCenter(id, Vec3::Zero()); });
    add("applyTorque", [&, id] { rb.applyTorque(id, Vec3::Zero()); });
    add("applyImpulse", [&, id] { rb.applyImpulse(id, Vec3::Zero(), Vec3::Zero()); });
    add("applyAngularImpulse", [&, id] { rb.applyAngularImpulse(id, Vec3::Zero()); });
    add("wake", [&, id] { rb.wake(id); });
    add("shapes", [&, id] { (void)rb.shapes(id); });
    add("createJoint",
        [&, id] { f.world.createJoint(BallJointSettings{.bodyA = {}, .bodyB = id}); });
    calls.back().named = "bodyB";
    EXPECT_FALSE(f.world.isValid(id));
  }
  for (ShapeId id : {f.staleShape, ShapeId{}, ShapeId{99, 1}}) {
    calls.push_back({"removeShape", [&, id] { rb.removeShape(id); }, "shape id"});
    calls.push_back({"body(shape)", [&, id] { (void)rb.body(id); }, "shape id"});
    calls.push_back({"collider", [&, id] { (void)rb.collider(id); }, "shape id"});
    calls.push_back({"shapeTransform", [&, id] { (void)rb.shapeTransform(id); }, "shape id"});
    calls.push_back({"material", [&, id] { (void)rb.material(id); }, "shape id"});
    EXPECT_FALSE(rb.isValid(id));
  }
  for (JointId id : {f.staleJoint, JointId{}, JointId{55, 1}}) {
    const auto add = [&](std::string what, std::function<void()> call) {
      calls.push_back({what, std::move(call), "joint id"});
    };
    add("destroyJoint", [&, id] { f.world.destroyJoint(id); });
    add("jointType", [&, id] { (void)rb.jointType(id); });
    add("jointName", [&, id] { (void)rb.jointName(id); });
    add("jointBodyA", [&, id] { (void)rb.jointBodyA(id); });
    add("jointBodyB", [&, id] { (void)rb.jointBodyB(id); });
    add("setJointEnabled", [&, id] { rb.setJointEnabled(id, false); });
    add("isJointEnabled", [&, id] { (void)rb.isJointEnabled(id); });
    add("isJointBroken", [&, id] { (void)rb.isJointBroken(id); });
    add("setJointMotor", [&, id] { rb.setJointMotor(id, std::nullopt); });
    add("setJointLimits", [&, id] { rb.setJointLimits(id, std::nullopt); });
    add("setJointSpring", [&, id] { rb.setJointSpring(id, std::nullopt); });
    add("setJointAxis", [&, id] { rb.setJointAxis(id, 0, {}); });
    add("jointForce", [&, id] { (void)rb.jointForce(id); });
    add("jointTorque", [&, id] { (void)rb.jointTorque(id); });
    add("jointCoordinate", [&, id] { (void)rb.jointCoordinate(id); });
    add("jointAxisCoordinate", [&, id] { (void)rb.jointAxisCoordinate(id, 0); });
    add("jointError", [&, id] { (void)rb.jointError(id); });
    add("jointAnchorA", [&, id] { (void)rb.jointAnchorA(id); });
    add("jointAnchorB", [&, id] { (void)rb.jointAnchorB(id); });
    add("jointFrameA", [&, id] { (void)rb.jointFrameA(id); });
    add("jointFrameB", [&, id] { (void)rb.jointFrameB(id); });
    add("jointAxis", [&, id] { (void)rb.jointAxis(id, 0); });
    EXPECT_FALSE(f.world.isValid(id));
  }
  for (ParticleSystemId id : {f.staleParticles, ParticleSystemId{}, ParticleSystemId{9, 1}}) {
    calls.push_back(
        {"particleSystem", [&, id] { (void)f.world.particleSystem(id); }, "particle system id"});
    calls.push_back({"destroyParticleSystem", [&, id] { f.world.destroyParticleSystem(id); },
                     "particle system id"});
  }
  for (DeformableId id : {f.staleRope, DeformableId{}, DeformableId{9, 1}}) {
    calls.push_back({"deformable", [&, id] { (void)f.world.deformable(id); }, "deformable id"});
    calls.push_back(
        {"destroyDeformable", [&, id] { f.world.destroyDeformable(id); }, "deformable id"});
  }
  EXPECT_EQ(expectAllRefused(calls), int(calls.size()));
  for (int i = 0; i < 10; ++i) f.world.step(Real(1) / 60);
  EXPECT_TRUE(f.world.transform(f.box).p.allFinite());
}

TEST(ApiMisuse, NonFiniteValuesAreRefusedEverywhere) {
  Fixture f;
  RigidBodySystem& rb = f.world.rigidBodies();
  const BodyId box = f.box;
  const JointId hinge = f.hinge;
  std::vector<Misuse> calls;
  for (const Vec3& v : kBadVectors) {
    const Quat q(v.x() + 1, v.y(), v.z(), 0);
    calls.push_back({"setTransform p", [&, v] { rb.setTransform(box, Transform{v}); }, "pose"});
    calls.push_back({"setTransform q",
                     [&, q] {
                       rb.setTransform(box, {Vec3::Zero(), q});
                     },
                     "pose"});
    calls.push_back(
        {"setLinearVelocity", [&, v] { rb.setLinearVelocity(box, v); }, "setLinearVelocity"});
    calls.push_back(
        {"setAngularVelocity", [&, v] { rb.setAngularVelocity(box, v); }, "setAngularVelocity"});
    calls.push_back({"applyForce f", [&, v] { rb.applyForce(box, v, Vec3::Zero()); }, "force"});
    calls.push_back({"applyForce p", [&, v] { rb.applyForce(box, Vec3::Zero(), v); }, "point"});
    calls.push_back(
        {"applyForceAtCenter", [&, v] { rb.applyForceAtCenter(box, v); }, "applyForceAtCenter"});
    calls.push_back({"applyTorque", [&, v] { rb.applyTorque(box, v); }, "applyTorque"});
    calls.push_back(
        {"applyImpulse i", [&, v] { rb.applyImpulse(box, v, Vec3::Zero()); }, "impulse"});
    calls.push_back({"applyImpulse p", [&, v] { rb.applyImpulse(box, Vec3::Zero(), v); }, "point"});
    calls.push_back(
        {"applyAngularImpulse", [&, v] { rb.applyAngularImpulse(box, v); }, "applyAngularImpulse"});
    calls.push_back(
        {"createBody position", [&, v] { f.world.createBody({.position = v}); }, "position"});
    calls.push_back({"createBody velocity", [&, v] { f.world.createBody({.linearVelocity = v}); },
                     "linearVelocity"});
    calls.push_back({"createBody angular", [&, v] { f.world.createBody({.angularVelocity = v}); },
                     "angularVelocity"});
    calls.push_back({"addShape local",
                     [&, v] { f.world.addShape(box, Sphere{1}, {}, Transform{v}); }, "local"});
    calls.push_back({"box half extents", [&, v] { f.world.addShape(box, Box{v}); }, "Box"});
    calls.push_back({"plane normal", [&, v] { f.world.addShape(f.ground, Plane{v, 0}); }, "Plane"});
    calls.push_back(
        {"hinge anchor",
         [&, v] { f.world.createJoint(HingeJointSettings{.bodyB = box, .anchorA = v}); },
         "anchor"});
    calls.push_back({"hinge axis",
                     [&, v] { f.world.createJoint(HingeJointSettings{.bodyB = box, .axisA = v}); },
                     "axis"});
    calls.push_back({"castRay origin",
                     [&, v] {
                       (void)f.world.castRay(Ray{v, Vec3::UnitX(), 1});
                     },
                     "origin"});
    if (v.sum() != kInf)  // an infinite ray is allowed
      calls.push_back({"castRay maxFraction",
                       [&, v] {
                         (void)f.world.castRay(Ray{Vec3::Zero(), Vec3::UnitX(), v.sum()});
                       },
                       "maxFraction"});
    calls.push_back({"castRay direction",
                     [&, v] {
                       (void)f.world.castRay(Ray{Vec3::Zero(), v, 1});
                     },
                     "direction"});
    calls.push_back({"world gravity", [v] { World w({.gravity = v}); }, "gravity"});
    calls.push_back(
        {"emitter position",
         [&, v] { f.world.particleSystem(f.particles).addEmitter({.pose = Transform{v}}); },
         "pose"});
    calls.push_back({"emitter direction",
                     [&, v] { f.world.particleSystem(f.particles).addEmitter({.direction = v}); },
                     "direction"});
    calls.push_back({"gravity field",
                     [&, v] { f.world.particleSystem(f.particles).addField({GravityField{v}}); },
                     "g"});
    calls.push_back({"deformable position",
                     [&, v] { f.world.deformable(f.rope).setPosition(0, v); }, "setPosition"});
    calls.push_back({"deformable velocity",
                     [&, v] { f.world.deformable(f.rope).setVelocity(0, v); }, "setVelocity"});
  }
  for (Real x : {kNaN, kInf, -kInf}) {
    calls.push_back({"step", [&, x] { f.world.step(x); }, "dt"});
    calls.push_back({"advance", [&, x] { f.world.advance(x); }, "frameTime"});
    calls.push_back({"moveKinematic dt", [&, x] { rb.moveKinematic(box, Transform{}, x); }, "dt"});
    calls.push_back(
        {"joint motor", [&, x] { rb.setJointMotor(hinge, JointMotor{.speed = x}); }, "motor"});
    calls.push_back({"joint limits",
                     [&, x] {
                       rb.setJointLimits(hinge, JointLimits{x, 1});
                     },
                     "limits"});
    calls.push_back({"joint spring",
                     [&, x] { rb.setJointSpring(hinge, JointSpring{.frequency = x}); }, "spring"});
    calls.push_back({"material friction",
                     [&, x] { f.world.addShape(box, Sphere{1}, Material{.friction = x}); },
                     "friction"});
    calls.push_back({"material restitution",
                     [&, x] { f.world.addShape(box, Sphere{1}, Material{.restitution = x}); },
                     "restitution"});
    calls.push_back(
        {"particle step", [&, x] { f.world.particleSystem(f.particles).step(x); }, "h"});
    calls.push_back({"deformable step", [&, x] { f.world.deformable(f.rope).step(x); }, "h"});
    calls.push_back({"emitter rate",
                     [&, x] { f.world.particleSystem(f.particles).addEmitter({.rate = x}); },
                     "rate"});
    calls.push_back({"body mass", [&, x] { f.world.createBody({.mass = x}); }, "mass"});
  }
  EXPECT_EQ(expectAllRefused(calls), int(calls.size()));
  for (int i = 0; i < 10; ++i) f.world.step(Real(1) / 60);
  EXPECT_TRUE(f.world.transform(f.box).p.allFinite());
}

TEST(ApiMisuse, NegativeAndZeroSizesAreRefusedEverywhere) {
  Fixture f;
  std::vector<Misuse> calls;
  for (Real s : kBadSizes) {
    const BodyId box = f.box;
    calls.push_back({"sphere radius", [&, s, box] { f.world.addShape(box, Sphere{s}); }, "Sphere"});
    calls.push_back({"capsule radius",
                     [&, s, box] {
                       f.world.addShape(box, Capsule{s, 1});
                     },
                     "Capsule"});
    calls.push_back({"capsule half height",
                     [&, s, box] {
                       f.world.addShape(box, Capsule{1, s});
                     },
                     "Capsule"});
    calls.push_back(
        {"box half extent", [&, s, box] { f.world.addShape(box, Box{Vec3(1, s, 1)}); }, "Box"});
    calls.push_back({"cylinder radius",
                     [&, s, box] {
                       f.world.addShape(box, Cylinder{s, 1});
                     },
                     "Cylinder"});
    calls.push_back({"cylinder half height",
                     [&, s, box] {
                       f.world.addShape(box, Cylinder{1, s});
                     },
                     "Cylinder"});
    calls.push_back({"density",
                     [&, s, box] { f.world.addShape(box, Sphere{1}, Material{.density = s}); },
                     "density"});
    calls.push_back({"world dt", [s] { World w({.dt = s}); }, "dt"});
    calls.push_back({"step dt", [&, s] { f.world.step(s); }, "dt"});
    calls.push_back({"deformable thickness",
                     [&, s] { f.world.createDeformable({.thickness = s}, rope({})); },
                     "thickness"});
    if (s != kInf)  // an infinite lifetime is allowed: immortal particles
      calls.push_back({"emitter lifetime",
                       [&, s] {
                         f.world.particleSystem(f.particles).addEmitter({.lifetime = {s, s}});
                       },
                       "lifetime"});
    calls.push_back({"emitter mass",
                     [&, s] {
                       f.world.particleSystem(f.particles).addEmitter({.mass = {s, s}});
                     },
                     "mass"});
  }
  for (int n : {0, -1})
    calls.push_back({"rope segments",
                     [&, n] { f.world.createDeformable({}, rope({.segments = n})); }, "segments"});
  calls.push_back({"world substeps 0", [] { World w({.substeps = 0}); }, "substeps"});
  calls.push_back({"world substeps -1", [] { World w({.substeps = -1}); }, "substeps"});
  calls.push_back({"world threads -1", [] { World w({.threads = -1}); }, "threads"});
  calls.push_back({"advance maxSteps 0", [&] { f.world.advance(1, 0); }, "maxSteps"});
  calls.push_back({"emitter rate < 0",
                   [&] { f.world.particleSystem(f.particles).addEmitter({.rate = -1}); }, "rate"});
  calls.push_back({"six-dof axis 6", [&] { f.world.rigidBodies().setJointAxis(f.hinge, 6, {}); },
                   "setJointAxis"});
  calls.push_back({"deformable vertex",
                   [&] { f.world.deformable(f.rope).setPosition(1000, Vec3::Zero()); }, "vertex"});
  calls.push_back({"body joined to itself",
                   [&] { f.world.createJoint(BallJointSettings{.bodyA = f.box, .bodyB = f.box}); },
                   "itself"});
  EXPECT_EQ(expectAllRefused(calls), int(calls.size()));
  for (int i = 0; i < 10; ++i) f.world.step(Real(1) / 60);
  EXPECT_TRUE(f.world.transform(f.box).p.allFinite());
}

}  // namespace
}  // namespace inertia
