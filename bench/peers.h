// The peer engines as the benchmarks build them, shared so that every benchmark sets Bullet
// and ODE up the same way: a scene body (one shape at its origin: plane, box, sphere or
// capsule, with density, friction and restitution) becomes the peer's body, and each world
// steps once per call with the settings the benchmarks' tables state.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>
#ifdef INERTIA_BENCH_ODE
#include <ode/ode.h>
#endif

#include "inertia/world/builders.h"
#include "inertia/world/world.h"

namespace inertia::bench {

using inertia::BodyDesc;
using inertia::Quat;
using inertia::Real;
using inertia::Vec3;

inline btVector3 bt(const Vec3& v) { return {btScalar(v.x()), btScalar(v.y()), btScalar(v.z())}; }
inline btQuaternion bt(const Quat& q) {
  return {btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())};
}

/// The only shape of a scene body (the peers are built from one shape at the origin).
inline const inertia::ShapeDesc& onlyShape(const BodyDesc& d) {
  if (d.shapes.size() != 1 || !d.shapes[0].local.p.isZero() ||
      !d.shapes[0].local.q.coeffs().isApprox(Quat::Identity().coeffs())) {
    std::fprintf(stderr, "bench peers: one shape at the body's origin only\n");
    std::exit(1);
  }
  return d.shapes[0];
}

/// The volume of a sphere, box or capsule (m^3), for the peers' masses.
inline double volume(const inertia::Shape& shape) {
  constexpr double pi = std::numbers::pi;
  if (const auto* s = shape.getIf<inertia::Sphere>())
    return 4.0 / 3.0 * pi * std::pow(double(s->radius), 3);
  if (const auto* b = shape.getIf<inertia::Box>()) return 8.0 * double(b->halfExtents.prod());
  if (const auto* c = shape.getIf<inertia::Capsule>()) {
    const double r = c->radius;
    return pi * r * r * 2 * double(c->halfHeight) + 4.0 / 3.0 * pi * r * r * r;
  }
  std::fprintf(stderr, "bench peers: sphere, box and capsule bodies only\n");
  std::exit(1);
}

/// Bullet: btDiscreteDynamicsWorld, btDbvtBroadphase, btSequentialImpulseConstraintSolver
/// (defaults), gravity -9.81 m/s^2 along y, dynamic bodies never deactivated. It owns what is
/// added to it.
class BulletWorld {
 public:
  BulletWorld() : dispatcher_(&config_), world_(&dispatcher_, &broadPhase_, &solver_, &config_) {
    world_.setGravity(btVector3(0, btScalar(-9.81), 0));
  }
  ~BulletWorld() {
    for (auto& c : constraints_) world_.removeConstraint(c.get());
    for (auto& b : bodies_) world_.removeRigidBody(b.get());
  }
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  /// A scene body: static (mass 0) or dynamic with density times the shape's volume.
  btRigidBody* add(const BodyDesc& d) {
    const inertia::ShapeDesc& s = onlyShape(d);
    const bool isStatic = d.settings.type == inertia::BodyType::Static;
    btCollisionShape* shape = nullptr;
    if (const auto* p = s.shape.getIf<inertia::Plane>())
      shape = new btStaticPlaneShape(bt(p->normal), btScalar(p->offset));
    else if (const auto* sp = s.shape.getIf<inertia::Sphere>())
      shape = new btSphereShape(btScalar(sp->radius));
    else if (const auto* b = s.shape.getIf<inertia::Box>())
      shape = new btBoxShape(bt(b->halfExtents));  // its 0.04 m margin inside the extents
    else if (const auto* c = s.shape.getIf<inertia::Capsule>())
      shape = new btCapsuleShape(btScalar(c->radius), btScalar(2 * c->halfHeight));  // along y
    else
      volume(s.shape);  // exits with the message
    const btScalar mass = isStatic ? 0 : btScalar(double(s.material.density) * volume(s.shape));
    return add(shape, mass,
               btTransform(bt(d.settings.orientation.normalized()), bt(d.settings.position)),
               s.material, s.filter);
  }
  /// A body of `shape` (taken over), static when `mass` is 0. A filter other than the default
  /// becomes Bullet's filter group and mask (the same rule: each one's bits meet the other's
  /// mask); Bullet has no group index, so `filter.group` must be 0.
  btRigidBody* add(btCollisionShape* shape, btScalar mass, const btTransform& pose,
                   const inertia::Material& m, const inertia::CollisionFilter& filter = {}) {
    shapes_.emplace_back(shape);
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    motions_.push_back(std::make_unique<btDefaultMotionState>(pose));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions_.back().get(), shape, inertia);
    // Bullet multiplies the two bodies' coefficients; sqrt on each gives the geometric mean,
    // Inertia's default rule.
    info.m_friction = btScalar(std::sqrt(double(m.friction)));
    info.m_restitution = btScalar(m.restitution);
    bodies_.push_back(std::make_unique<btRigidBody>(info));
    if (mass > 0) bodies_.back()->setActivationState(DISABLE_DEACTIVATION);
    if (filter == inertia::CollisionFilter{}) {
      world_.addRigidBody(bodies_.back().get());
    } else {
      if (filter.group != 0) {
        std::fprintf(stderr, "peers: Bullet has no collision group index\n");
        std::exit(1);
      }
      world_.addRigidBody(bodies_.back().get(), int(filter.category), int(filter.mask));
    }
    return bodies_.back().get();
  }
  void add(std::unique_ptr<btTypedConstraint> c, bool collideConnected) {
    world_.addConstraint(c.get(), !collideConnected);
    constraints_.push_back(std::move(c));
  }
  /// One step of `dt` seconds (maxSubSteps 0: exactly one).
  void step(Real dt) { world_.stepSimulation(btScalar(dt), 0); }

  /// The kinetic energy of a dynamic body (J).
  static double kineticEnergy(const btRigidBody& b) {
    const btVector3 v = b.getLinearVelocity(), w = b.getAngularVelocity();
    const btVector3 iw = b.getInvInertiaTensorWorld().inverse() * w;
    return 0.5 * double(1 / b.getInvMass()) * double(v.length2()) + 0.5 * double(w.dot(iw));
  }

 private:
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadPhase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
};

#ifdef INERTIA_BENCH_ODE
/// ODE (double): a hash space, contacts from dCollide (at most 4 per pair) as contact joints
/// with friction `mu` (dContactApprox1, ODE's Coulomb approximation) and no bounce, none
/// between bodies a joint connects; the world's default ERP 0.2 and CFM; dWorldQuickStep with
/// its default 20 iterations; auto-disable off.
class OdeWorld {
 public:
  explicit OdeWorld(double mu) : mu_(mu) {
    dWorldSetGravity(world, 0, -9.81, 0);
    dWorldSetAutoDisableFlag(world, 0);
  }
  ~OdeWorld() {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world);
  }
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  /// A scene body: its geom, and for a dynamic body its ODE body (null for a static one).
  dBodyID add(const BodyDesc& d) {
    const inertia::ShapeDesc& s = onlyShape(d);
    const double density = double(s.material.density);
    dMass mass;
    dGeomID geom = nullptr;
    dQuaternion offset = {1, 0, 0, 0};
    if (const auto* p = s.shape.getIf<inertia::Plane>()) {
      dCreatePlane(space_, p->normal.x(), p->normal.y(), p->normal.z(), p->offset);
      return nullptr;  // planes are placed by their equation
    } else if (const auto* sp = s.shape.getIf<inertia::Sphere>()) {
      geom = dCreateSphere(space_, sp->radius);
      dMassSetSphere(&mass, density, sp->radius);
    } else if (const auto* b = s.shape.getIf<inertia::Box>()) {
      const Vec3 size = 2 * b->halfExtents;  // ODE takes full side lengths
      geom = dCreateBox(space_, size.x(), size.y(), size.z());
      dMassSetBox(&mass, density, size.x(), size.y(), size.z());
    } else if (const auto* c = s.shape.getIf<inertia::Capsule>()) {
      // ODE's capsules lie along their z axis: turned -90 degrees about x onto the body's y.
      geom = dCreateCapsule(space_, c->radius, 2 * c->halfHeight);
      dMassSetCapsule(&mass, density, 2, c->radius, 2 * c->halfHeight);
      offset[0] = std::sqrt(0.5);
      offset[1] = -std::sqrt(0.5);
    } else {
      volume(s.shape);  // exits with the message
    }
    const Vec3& x = d.settings.position;
    const Quat q = d.settings.orientation.normalized();
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};  // ODE: w first
    if (d.settings.type == inertia::BodyType::Static) {
      dGeomSetPosition(geom, x.x(), x.y(), x.z());
      dGeomSetQuaternion(geom, dq);
      return nullptr;
    }
    const dBodyID body = dBodyCreate(world);
    dBodySetMass(body, &mass);
    dBodySetPosition(body, x.x(), x.y(), x.z());
    dBodySetQuaternion(body, dq);
    dGeomSetBody(geom, body);
    dGeomSetOffsetQuaternion(geom, offset);
    return body;
  }
  /// One step of `dt` seconds: collide, quick step, drop the contacts.
  void step(Real dt) {
    dSpaceCollide(space_, this, near);
    dWorldQuickStep(world, double(dt));
    dJointGroupEmpty(contacts_);
  }

  /// The kinetic energy of a body (J): the rotational part in the body's frame, w_b = R^T w,
  /// with R and I row-major 3 x 4.
  static double kineticEnergy(dBodyID b) {
    dMass m;
    dBodyGetMass(b, &m);
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* wv = dBodyGetAngularVel(b);
    const dReal* R = dBodyGetRotation(b);
    double wb[3], e = 0;
    for (int k = 0; k < 3; ++k) wb[k] = R[k] * wv[0] + R[4 + k] * wv[1] + R[8 + k] * wv[2];
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) e += wb[k] * m.I[4 * k + l] * wb[l];
    return 0.5 * m.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 0.5 * e;
  }

  dWorldID world = dWorldCreate();

 private:
  static void near(void* data, dGeomID g1, dGeomID g2) {
    OdeWorld& w = *static_cast<OdeWorld*>(data);
    const dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    if (b1 == nullptr && b2 == nullptr) return;  // two static geoms
    if (b1 != nullptr && b2 != nullptr && dAreConnectedExcluding(b1, b2, dJointTypeContact)) return;
    constexpr int kMax = 4;
    dContact contact[kMax] = {};
    const int n = dCollide(g1, g2, kMax, &contact[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      contact[i].surface.mode = dContactApprox1;
      contact[i].surface.mu = w.mu_;
      const dJointID j = dJointCreateContact(w.world, w.contacts_, &contact[i]);
      dJointAttach(j, b1, b2);
    }
  }

  double mu_;
  dSpaceID space_ = dHashSpaceCreate(nullptr);
  dJointGroupID contacts_ = dJointGroupCreate(0);
};
#endif

/// Inertia's mean ms per step in each phase over `steps` steps, "-" for a peer.
inline std::string phaseSplit(const inertia::PhaseTimes* phases, int steps) {
  if (phases == nullptr) return "-";
  const double ms = 1e3 / steps;
  char split[96];
  std::snprintf(split, sizeof split, "%.2f / %.2f / %.2f / %.2f", ms * phases->broadPhase,
                ms * phases->narrowPhase, ms * phases->solver, ms * phases->integration);
  return split;
}

}  // namespace inertia::bench
