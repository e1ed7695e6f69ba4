// The rigid-body pipeline of a step (Box2D v3's order, in 3D):
//   1. broad phase: move the proxies of awake bodies (boxes swept over the step for fast
//      bodies), collect candidate pairs from the broad phase's trees, plus the static planes;
//   2. narrow phase: collide() each pair with a speculative margin; warm-start impulses are
//      matched to the previous step's points by (shapes, sub-shapes, feature id);
//   3. islands: union-find over touching pairs; an island with one awake body wakes whole;
//   4. solve: bodies without contacts fly free with the chosen ode method and the exact
//      momentum-conserving rotation splitting; the others go through the contact solver
//      (soft step, pgs, or a direct LCP per island: lcp_contact.h) in `substeps` substeps;
//   5. finalise: poses from the solver's motion, sleep timers, island sleep, contact events.
// Each stage is a function in its own file (contact_manager, islands, solver_stages,
// body_motion); this file keeps the body and shape API and calls the stages in order on the
// step's workers (step_workers.h).
#include "inertia/dynamics/rigid_body_system.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>

#include "body_motion.h"
#include "contact_manager.h"
#include "core/thread_pool_impl.h"
#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/geometry/bounds.h"
#include "inertia/geometry/mass.h"
#include "inertia/ode/step.h"
#include "islands.h"
#include "rigid_body_data.h"
#include "solver_stages.h"
#include "step_workers.h"

namespace inertia {

using Data = detail::RigidBodyData;
using detail::BodyRecord;
using detail::ContactExtra;
using detail::proxyType;
using detail::ShapeRecord;
using detail::worldMomentum;

namespace {

struct SolverEntry {
  SolverType type;
  std::string_view name;
};
constexpr std::array<SolverEntry, 4> kSolvers{{{SolverType::SoftStep, "soft_step"},
                                               {SolverType::Pgs, "pgs"},
                                               {SolverType::LcpDantzig, "lcp_dantzig"},
                                               {SolverType::LcpLemke, "lcp_lemke"}}};

// Eigen's 3x3 inverse divides the cofactors by the determinant, the cube of the inertia's
// scale: in float it underflows to zero below about 2e-13 kg m^2 (a sphere of water 0.3 mm
// across) and the inverse is infinite or NaN. Scaled by a power of two near its largest
// entry first, and the result back: exact, so the same bits wherever nothing underflowed.
Mat3 inverseInertia(const Mat3& inertia) {
  int exponent = 0;
  std::frexp(inertia.cwiseAbs().maxCoeff(), &exponent);
  const Real scale = std::ldexp(Real(1), -exponent);
  return (inertia * scale).inverse() * scale;
}

// Whether `inverse` answers for `inertia` within kInverseResidual: |I I^-1 - 1|, about eps
// times the condition number.
bool holds(const Mat3& inertia, const Mat3& inverse) {
  return inverse.allFinite() &&
         (inertia * inverse - Mat3::Identity()).cwiseAbs().maxCoeff() <= kInverseResidual;
}

// A dynamic shape whose mass or principal moments Real cannot hold with room to spare (a
// sphere of 10 nm: its inertia's inverse overflows float) is refused here, not left to turn
// NaN in the solver.
void requireSimulable(const MassProperties& props) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(props.inertia, Eigen::EigenvaluesOnly);
  const Vec3 moments = eig.eigenvalues();
  if (simulableMassProperty(props.mass) && simulableMassProperty(moments.minCoeff()) &&
      simulableMassProperty(moments.maxCoeff()))
    return;
  char text[320];
  std::snprintf(text, sizeof(text),
                "RigidBodySystem::addShape: the shape's mass (%.3g kg) or a principal moment of "
                "inertia (%.3g .. %.3g kg m^2) is outside %s, what Real can simulate: size or "
                "density too small or too large",
                double(props.mass), double(moments.minCoeff()), double(moments.maxCoeff()),
                massPropertyRange().c_str());
  throw InvalidArgument(text);
}

}  // namespace

std::string_view solverName(SolverType type) {
  for (const auto& s : kSolvers)
    if (s.type == type) return s.name;
  return "unknown";
}

bool solverFromName(std::string_view name, SolverType& out) {
  for (const auto& s : kSolvers)
    if (s.name == name) {
      out = s.type;
      return true;
    }
  return false;
}

std::string_view solverNames() { return "soft_step, pgs, lcp_dantzig, lcp_lemke"; }

void validate(const ContactTuning& t) {
  auto check = [](Real x, bool positive, const char* field) {
    require(std::isfinite(x) && (positive ? x > 0 : x >= 0),
            std::string("ContactTuning::") + field +
                (positive ? " must be finite and > 0" : " must be finite and >= 0"));
  };
  check(t.hertz, true, "hertz");
  check(t.dampingRatio, false, "dampingRatio");
  check(t.pushVelocity, true, "pushVelocity");
  check(t.restitutionThreshold, false, "restitutionThreshold");
  check(t.linearSlop, false, "linearSlop");
  check(t.baumgarte, false, "baumgarte");
  require(t.baumgarte <= 1, "ContactTuning::baumgarte must be <= 1");
  check(t.speculativeDistance, false, "speculativeDistance");
  check(t.bulletFraction, true, "bulletFraction");
  check(t.reuseDistance, false, "reuseDistance");
  check(t.reuseAngle, false, "reuseAngle");
  check(t.sleepSpeed, false, "sleepSpeed");
  check(t.timeToSleep, true, "timeToSleep");
}

void Data::updateMass(BodyRecord& b) {
  b.wasFree = false;
  b.localCom = Vec3::Zero();
  b.extent = 0;
  b.minExtent = std::numeric_limits<Real>::infinity();
  std::vector<MassProperties> parts;
  for (std::uint32_t si : b.shapes) {
    const ShapeRecord& s = shapes[si];
    if (b.type == BodyType::Dynamic)
      parts.push_back(transformed(massProperties(s.collider.shape(), s.material.density), s.local));
  }
  if (b.type != BodyType::Dynamic) {
    b.mass = b.invMass = 0;
    b.inertiaLocal = b.invInertiaLocal = Mat3::Zero();
    b.isotropic = false;
  } else {
    MassProperties props;
    if (parts.empty()) {
      // No shapes: a unit mass with the inertia of a 0.5 m sphere (Box2D defaults to 1 kg).
      props.mass = 1;
      props.inertia = Mat3::Identity() * Real(0.1);
    } else {
      props = combine(parts);
    }
    if (b.massOverride > 0) {
      props.inertia *= b.massOverride / props.mass;
      props.mass = b.massOverride;
    }
    if (!b.inertiaOverride.isZero()) props.inertia = b.inertiaOverride.asDiagonal();
    b.mass = props.mass;
    b.invMass = 1 / props.mass;
    b.localCom = props.centerOfMass;
    b.inertiaLocal = Real(0.5) * (props.inertia + props.inertia.transpose());
    b.isotropic = b.inertiaLocal == Mat3::Identity() * b.inertiaLocal(0, 0);
    b.invInertiaLocal = inverseInertia(b.inertiaLocal);
    // Principal axes for the free-rotation splitting (a proper rotation).
    Eigen::SelfAdjointEigenSolver<Mat3> eig(b.inertiaLocal);
    Vec3 moments = eig.eigenvalues();
    // A tensor conditioned beyond what Real inverts (kInverseResidual, body.h): a body far
    // longer than thick, as a fuzzed hull 100 km from a thin cylinder. The test is on the
    // moments, not only on the local inverse: a thin cylinder's tensor is diagonal in its frame
    // and inverts exactly there, but the world's R diag(1/I) R^T rounds eps / I_min into every
    // entry. Its smallest moments are raised to a quarter of that condition, here once, so that
    // the tensor, its inverse, the gyroscopic step and the free rotation all answer for the
    // same body.
    constexpr Real kEps = std::numeric_limits<Real>::epsilon();
    if (!holds(b.inertiaLocal, b.invInertiaLocal) ||
        !(moments.minCoeff() * kInverseResidual > kEps * moments.maxCoeff())) {
      moments = moments.cwiseMax(4 * kEps / kInverseResidual * moments.maxCoeff());
      b.inertiaLocal = eig.eigenvectors() * moments.asDiagonal() * eig.eigenvectors().transpose();
      b.inertiaLocal = Real(0.5) * (b.inertiaLocal + b.inertiaLocal.transpose());
      b.invInertiaLocal = inverseInertia(b.inertiaLocal);
    }
    Mat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    b.principalAxes = Quat(axes).normalized();
    b.principalMoments = moments.cwiseMax(Real(1e-12) * moments.maxCoeff());
  }
  for (std::uint32_t si : b.shapes) {
    const ShapeRecord& s = shapes[si];
    if (s.collider.type() == ShapeType::Plane) continue;
    const Aabb box = transformAabb(localBounds(s.collider.shape()), s.local);
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner((c & 1) ? box.upper.x() : box.lower.x(),
                        (c & 2) ? box.upper.y() : box.lower.y(),
                        (c & 4) ? box.upper.z() : box.lower.z());
      b.extent = std::max(b.extent, (corner - b.localCom).norm());
    }
    b.minExtent = std::min(b.minExtent, Real(0.5) * (box.upper - box.lower).minCoeff());
  }
  if (!std::isfinite(b.minExtent)) b.minExtent = 1;
  b.minExtent = std::max(b.minExtent, Real(1e-3));
  b.com = b.pose.apply(b.localCom);
}

void Data::refreshProxies(BodyRecord& b) {
  for (std::uint32_t si : b.shapes) {
    ShapeRecord& s = shapes[si];
    if (s.proxy == BroadPhase::kNull) continue;
    broadPhase.destroyProxy(s.proxy);
    s.proxy = broadPhase.createProxy(worldBounds(s.collider.shape(), shapePose(s)),
                                     proxyType(bodies[s.body].type), si);
    pairsDirty = true;
  }
}

void Data::dropContacts(std::uint32_t shape) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    if (contacts[i].shapeA.index == shape || contacts[i].shapeB.index == shape) continue;
    contacts[out] = contacts[i];
    extras[out] = extras[i];
    ++out;
  }
  contacts.resize(out);
  extras.resize(out);
}

RigidBodySystem::RigidBodySystem() : d_(std::make_unique<Data>()) {}
RigidBodySystem::~RigidBodySystem() = default;
RigidBodySystem::RigidBodySystem(const RigidBodySystem& o) : d_(std::make_unique<Data>(*o.d_)) {}
RigidBodySystem& RigidBodySystem::operator=(const RigidBodySystem& o) {
  if (this != &o) d_ = std::make_unique<Data>(*o.d_);
  return *this;
}
RigidBodySystem::RigidBodySystem(RigidBodySystem&&) noexcept = default;
RigidBodySystem& RigidBodySystem::operator=(RigidBodySystem&&) noexcept = default;

BodyId RigidBodySystem::createBody(const BodySettings& settings) {
  validate(settings);
  Data& D = *d_;
  std::uint32_t index = D.firstFreeBody;
  while (index < D.bodies.size() && D.bodies[index].alive) ++index;
  D.firstFreeBody = index + 1;
  if (index == D.bodies.size()) {
    D.bodies.emplace_back();
    D.workspaces.emplace_back();
  }
  BodyRecord& b = D.bodies[index];
  const std::uint32_t generation = b.generation;
  b = BodyRecord{};
  b.generation = generation;
  b.alive = true;
  b.type = settings.type;
  b.pose = {settings.position, settings.orientation.normalized()};
  if (settings.type != BodyType::Static) {
    b.v = settings.linearVelocity;
    b.w = settings.angularVelocity;
  }
  b.linearDamping = settings.linearDamping;
  b.angularDamping = settings.angularDamping;
  b.gravityScale = settings.gravityScale;
  b.maxLinearSpeed = settings.maxLinearSpeed;
  b.maxAngularSpeed = settings.maxAngularSpeed;
  b.massOverride = settings.mass;
  b.inertiaOverride = settings.inertia;
  b.allowSleep = settings.allowSleep;
  b.bullet = settings.bullet;
  b.awake = settings.type != BodyType::Static;
  b.name = settings.name;
  D.workspaces[index] = ode::Workspace<Real>{};
  D.updateMass(b);
  ++D.liveBodies;
  return {index, generation};
}

void RigidBodySystem::destroyBody(BodyId id) {
  Data& D = *d_;
  BodyRecord& b = D.body(id);
  require(b.group < 0,
          "RigidBodySystem::destroyBody: the body is a link of a multibody group "
          "(remove the group first)");
  for (std::uint32_t si : b.shapes) {
    ShapeRecord& s = D.shapes[si];
    if (s.proxy != BroadPhase::kNull) D.broadPhase.destroyProxy(s.proxy);
    s.proxy = BroadPhase::kNull;
    D.pairsDirty = true;
    s.alive = false;
    ++s.generation;
    D.firstFreeShape = std::min(D.firstFreeShape, si);
    D.planes.erase(std::remove(D.planes.begin(), D.planes.end(), si), D.planes.end());
    D.dropContacts(si);
  }
  b.shapes.clear();
  // Its joints go with it (a copy: destroyJoint edits the list).
  for (const std::uint32_t ji : std::vector<std::uint32_t>(b.joints))
    destroyJoint({ji, D.joints[ji].generation});
  b.alive = false;
  ++b.generation;
  D.firstFreeBody = std::min(D.firstFreeBody, id.index);
  --D.liveBodies;
}

bool RigidBodySystem::isValid(BodyId id) const { return d_->isValidBody(id); }
bool RigidBodySystem::isValid(ShapeId id) const { return d_->isValidShape(id); }

ShapeId RigidBodySystem::addShape(BodyId body, const Shape& shape, const Material& material,
                                  const Transform& local) {
  return addShape(body, Collider(shape), material, local);
}

ShapeId RigidBodySystem::addShape(BodyId bodyId, const Collider& collider, const Material& material,
                                  const Transform& local) {
  Data& D = *d_;
  BodyRecord& b = D.body(bodyId);
  validate(material);
  require(allFinite(local.p) && allFinite(local.q) && std::abs(local.q.norm() - 1) < Real(1e-3),
          "RigidBodySystem::addShape: the local transform must be finite with a unit quaternion");
  const ShapeType type = collider.type();
  if (type == ShapeType::Plane || type == ShapeType::HeightField)
    require(b.type == BodyType::Static, std::string("RigidBodySystem::addShape: a ") +
                                            (type == ShapeType::Plane ? "plane" : "height field") +
                                            " can only be attached to a static body");
  // Fails (InvalidArgument) for open meshes and other shapes without a volume.
  if (b.type == BodyType::Dynamic)
    requireSimulable(massProperties(collider.shape(), material.density));

  std::uint32_t index = D.firstFreeShape;
  while (index < D.shapes.size() && D.shapes[index].alive) ++index;
  D.firstFreeShape = index + 1;
  if (index == D.shapes.size()) D.shapes.emplace_back();
  ShapeRecord& s = D.shapes[index];
  s.alive = true;
  s.body = bodyId.index;
  s.collider = collider;
  s.local = {local.p, local.q.normalized()};
  s.atOrigin = s.local.p == Vec3::Zero() && s.local.q.coeffs() == Quat::Identity().coeffs();
  s.material = material;
  s.filter = {};
  s.proxy = BroadPhase::kNull;
  s.radius = std::numeric_limits<Real>::infinity();
  if (type != ShapeType::Plane) {
    // The farthest corner of the local bounds, rounded up by a few ulps.
    const Aabb box = localBounds(collider.shape());
    s.radius = box.lower.cwiseAbs().cwiseMax(box.upper.cwiseAbs()).norm() *
               (1 + 8 * std::numeric_limits<Real>::epsilon());
  }
  if (type == ShapeType::Plane) {
    D.planes.push_back(index);
  } else {
    s.proxy = D.broadPhase.createProxy(worldBounds(collider.shape(), D.shapePose(s)),
                                       proxyType(b.type), index);
    D.pairsDirty = true;
  }
  b.shapes.push_back(index);
  D.updateMass(b);
  D.wake(b);
  return {index, s.generation};
}

void RigidBodySystem::removeShape(ShapeId id) {
  Data& D = *d_;
  ShapeRecord& s = D.shape(id);
  BodyRecord& b = D.bodies[s.body];
  if (s.proxy != BroadPhase::kNull) D.broadPhase.destroyProxy(s.proxy);
  s.proxy = BroadPhase::kNull;
  D.pairsDirty = true;
  D.planes.erase(std::remove(D.planes.begin(), D.planes.end(), id.index), D.planes.end());
  D.dropContacts(id.index);
  b.shapes.erase(std::remove(b.shapes.begin(), b.shapes.end(), id.index), b.shapes.end());
  s.alive = false;
  ++s.generation;
  D.firstFreeShape = std::min(D.firstFreeShape, id.index);
  D.updateMass(b);
  D.wake(b);
}

Transform RigidBodySystem::transform(BodyId id) const { return d_->body(id).pose; }
Vec3 RigidBodySystem::centerOfMass(BodyId id) const { return d_->body(id).com; }
Vec3 RigidBodySystem::linearVelocity(BodyId id) const { return d_->body(id).v; }
Vec3 RigidBodySystem::angularVelocity(BodyId id) const { return d_->body(id).w; }
Real RigidBodySystem::mass(BodyId id) const { return d_->body(id).mass; }
Mat3 RigidBodySystem::inertiaWorld(BodyId id) const {
  const BodyRecord& b = d_->body(id);
  const Mat3 R = b.pose.q.toRotationMatrix();
  return R * b.inertiaLocal * R.transpose();
}
Mat3 RigidBodySystem::inverseInertiaWorld(BodyId id) const {
  return d_->body(id).invInertiaWorld();
}
BodyType RigidBodySystem::type(BodyId id) const { return d_->body(id).type; }
std::string_view RigidBodySystem::name(BodyId id) const { return d_->body(id).name; }
bool RigidBodySystem::isAwake(BodyId id) const { return d_->body(id).awake; }
BodyId RigidBodySystem::body(ShapeId id) const { return d_->bodyId(d_->shape(id).body); }

// Pairs are filtered as the broad phase hands them on, every step: the new filter holds from
// the next step. The body wakes, so that a sleeping pair the filter now lets touch is found,
// and so do the bodies the shape touches (a static shape's body cannot wake), so that what it
// no longer holds up falls.
void RigidBodySystem::setFilter(ShapeId id, const CollisionFilter& filter) {
  Data& D = *d_;
  ShapeRecord& s = D.shape(id);
  if (s.filter == filter) return;
  s.filter = filter;
  D.wake(D.bodies[s.body]);
  for (const ContactInfo& c : D.contacts)
    if (c.shapeA.index == id.index || c.shapeB.index == id.index) {
      D.wake(D.bodies[D.shapes[c.shapeA.index].body]);
      D.wake(D.bodies[D.shapes[c.shapeB.index].body]);
    }
}
CollisionFilter RigidBodySystem::filter(ShapeId id) const { return d_->shape(id).filter; }

void RigidBodySystem::setTransform(BodyId id, const Transform& pose) {
  require(allFinite(pose.p) && allFinite(pose.q) && pose.q.norm() > Real(1e-6),
          "RigidBodySystem::setTransform: the pose must be finite with a non-zero quaternion");
  Data& D = *d_;
  BodyRecord& b = D.body(id);
  b.pose = {pose.p, pose.q.normalized()};
  b.com = b.pose.apply(b.localCom);
  b.wasFree = false;
  D.refreshProxies(b);
  D.wake(b);
}

void RigidBodySystem::setLinearVelocity(BodyId id, const Vec3& v) {
  require(allFinite(v), "RigidBodySystem::setLinearVelocity: the velocity must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type == BodyType::Static) return;
  b.v = v;
  d_->wake(b);
}

void RigidBodySystem::setAngularVelocity(BodyId id, const Vec3& w) {
  require(allFinite(w), "RigidBodySystem::setAngularVelocity: the velocity must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type == BodyType::Static) return;
  b.w = w;
  b.wasFree = false;
  d_->wake(b);
}

void RigidBodySystem::moveKinematic(BodyId id, const Transform& target, Real dt) {
  require(std::isfinite(dt) && dt > 0, "RigidBodySystem::moveKinematic: dt must be finite and > 0");
  require(allFinite(target.p) && allFinite(target.q) && target.q.norm() > Real(1e-6),
          "RigidBodySystem::moveKinematic: the target must be finite");
  BodyRecord& b = d_->body(id);
  require(b.type == BodyType::Kinematic,
          "RigidBodySystem::moveKinematic: the body is not kinematic");
  const Quat q = target.q.normalized();
  const Vec3 targetCom = target.p + q * b.localCom;
  b.v = (targetCom - b.com) / dt;
  b.w = rotationVector(q * b.pose.q.conjugate()) / dt;
  d_->wake(b);
}

void RigidBodySystem::applyForce(BodyId id, const Vec3& f, const Vec3& point) {
  require(allFinite(f) && allFinite(point),
          "RigidBodySystem::applyForce: force and point must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type != BodyType::Dynamic) return;
  b.force += f;
  b.torque += (point - b.com).cross(f);
  d_->wake(b);
}

void RigidBodySystem::applyForceAtCenter(BodyId id, const Vec3& f) {
  require(allFinite(f), "RigidBodySystem::applyForceAtCenter: the force must be finite");
  applyForce(id, f, d_->body(id).com);
}

void RigidBodySystem::applyTorque(BodyId id, const Vec3& t) {
  require(allFinite(t), "RigidBodySystem::applyTorque: the torque must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type != BodyType::Dynamic) return;
  b.torque += t;
  d_->wake(b);
}

void RigidBodySystem::applyImpulse(BodyId id, const Vec3& J, const Vec3& point) {
  require(allFinite(J) && allFinite(point),
          "RigidBodySystem::applyImpulse: impulse and point must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type != BodyType::Dynamic) return;
  b.v += b.invMass * J;
  b.w += b.invInertiaWorld() * (point - b.com).cross(J);
  b.wasFree = false;
  d_->wake(b);
}

void RigidBodySystem::applyAngularImpulse(BodyId id, const Vec3& L) {
  require(allFinite(L), "RigidBodySystem::applyAngularImpulse: the impulse must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type != BodyType::Dynamic) return;
  b.w += b.invInertiaWorld() * L;
  b.wasFree = false;
  d_->wake(b);
}

void RigidBodySystem::wake(BodyId id) { d_->wake(d_->body(id)); }

int RigidBodySystem::addMultibody(MultibodyResponse* response, std::span<const BodyId> members,
                                  std::span<const int> selfCollisionParents) {
  require(response != nullptr, "RigidBodySystem::addMultibody: the response is null");
  require(selfCollisionParents.empty() || selfCollisionParents.size() == members.size(),
          "RigidBodySystem::addMultibody: one parent per member, or none");
  for (const int parent : selfCollisionParents)
    require(parent >= -1 && parent < int(members.size()),
            "RigidBodySystem::addMultibody: a parent is not a member index");
  Data& D = *d_;
  for (const BodyId id : members) {
    const BodyRecord& b = D.body(id);
    require(b.type == BodyType::Dynamic && b.group < 0,
            "RigidBodySystem::addMultibody: a member is not a dynamic body outside any group");
    require(b.joints.empty(), "RigidBodySystem::addMultibody: a member has joints");
  }
  std::size_t g = 0;
  while (g < D.multibodies.size() && D.multibodies[g].response) ++g;
  if (g == D.multibodies.size()) D.multibodies.emplace_back();
  detail::MultibodyGroup& group = D.multibodies[g];
  group.response = response;
  group.members.clear();
  group.parents.assign(selfCollisionParents.begin(), selfCollisionParents.end());
  for (std::size_t m = 0; m < members.size(); ++m) {
    BodyRecord& b = D.body(members[m]);
    b.group = static_cast<int>(g);
    b.member = static_cast<int>(m);
    b.allowSleep = false;
    D.wake(b);
    group.members.push_back(members[m].index);
  }
  // The members' pairs with each other go (or stay, where they collide).
  D.pairsDirty = true;
  return static_cast<int>(g);
}

void RigidBodySystem::setMultibodyResponse(int group, MultibodyResponse* response) {
  Data& D = *d_;
  require(response != nullptr, "RigidBodySystem::setMultibodyResponse: the response is null");
  require(group >= 0 && std::size_t(group) < D.multibodies.size() &&
              D.multibodies[std::size_t(group)].response,
          "RigidBodySystem::setMultibodyResponse: no group " + std::to_string(group));
  D.multibodies[std::size_t(group)].response = response;
}

void RigidBodySystem::removeMultibody(int group) {
  Data& D = *d_;
  require(group >= 0 && std::size_t(group) < D.multibodies.size() &&
              D.multibodies[std::size_t(group)].response,
          "RigidBodySystem::removeMultibody: no group " + std::to_string(group));
  detail::MultibodyGroup& g = D.multibodies[std::size_t(group)];
  for (std::uint32_t bi : g.members) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive || b.group != group) continue;
    b.group = -1;
    b.member = -1;
  }
  g = detail::MultibodyGroup{};
  D.pairsDirty = true;
}

void RigidBodySystem::setDrivenState(BodyId id, const Transform& pose, const Vec3& originVelocity,
                                     const Vec3& angularVelocity) {
  BodyRecord& b = d_->body(id);
  require(b.group >= 0, "RigidBodySystem::setDrivenState: the body is not driven");
  b.pose = {pose.p, pose.q.normalized()};
  b.com = b.pose.apply(b.localCom);
  b.w = angularVelocity;
  b.v = originVelocity + angularVelocity.cross(b.com - b.pose.p);
}

int RigidBodySystem::bodyCount() const { return d_->liveBodies; }

int RigidBodySystem::contactCount() const {
  int n = 0;
  for (const ContactExtra& e : d_->extras) n += e.touching ? 1 : 0;
  return n;
}

std::vector<BodyId> RigidBodySystem::bodies() const {
  std::vector<BodyId> ids;
  for (std::uint32_t i = 0; i < d_->bodies.size(); ++i)
    if (d_->bodies[i].alive) ids.push_back(d_->bodyId(i));
  return ids;
}

std::vector<ShapeId> RigidBodySystem::shapes(BodyId id) const {
  std::vector<ShapeId> ids;
  for (std::uint32_t si : d_->body(id).shapes) ids.push_back(d_->shapeId(si));
  return ids;
}

const Collider& RigidBodySystem::collider(ShapeId id) const { return d_->shape(id).collider; }
Transform RigidBodySystem::shapeTransform(ShapeId id) const { return d_->shapePose(d_->shape(id)); }
const Material& RigidBodySystem::material(ShapeId id) const { return d_->shape(id).material; }
const std::vector<ContactInfo>& RigidBodySystem::contacts() const { return d_->contacts; }
std::vector<BroadPhaseNode> RigidBodySystem::broadPhaseNodes() const {
  std::vector<BroadPhaseNode> nodes;
  for (const DynamicTree* tree : {&d_->broadPhase.staticTree(), &d_->broadPhase.dynamicTree()})
    tree->forEachNode([&](const Aabb& box, int height) { nodes.push_back({box, height}); });
  return nodes;
}
const std::vector<ContactEvent>& RigidBodySystem::beginEvents() const { return d_->beginEvents; }
const std::vector<ContactEvent>& RigidBodySystem::endEvents() const { return d_->endEvents; }
const DynamicsTimes& RigidBodySystem::times() const { return d_->times; }

std::optional<WorldRayHit> RigidBodySystem::castRay(const Ray& ray) const {
  require(allFinite(ray.origin), "RigidBodySystem::castRay: the ray's origin must be finite");
  require(allFinite(ray.direction) && !ray.direction.isZero(0),
          "RigidBodySystem::castRay: the ray's direction must be finite and non-zero");
  require(ray.maxFraction >= 0, "RigidBodySystem::castRay: the ray's maxFraction must be >= 0");
  const Data& D = *d_;
  std::optional<WorldRayHit> best;
  auto consider = [&](std::uint32_t si, Real maxFraction) {
    const ShapeRecord& s = D.shapes[si];
    Ray clipped = ray;
    clipped.maxFraction = maxFraction;
    if (auto hit = inertia::castRay(s.collider, D.shapePose(s), clipped)) {
      // Ties go to the lower shape index, so the answer does not depend on the tree's shape.
      if (!best || hit->fraction < best->hit.fraction ||
          (hit->fraction == best->hit.fraction && si < best->shape.index)) {
        best = WorldRayHit{D.bodyId(s.body), D.shapeId(si), *hit};
      }
    }
  };
  for (std::uint32_t si : D.planes) consider(si, ray.maxFraction);
  D.broadPhase.rayCast(ray, [&](int proxy, Real maxFraction) -> Real {
    const Real limit = best ? std::min(maxFraction, best->hit.fraction) : maxFraction;
    consider(D.broadPhase.userData(proxy), limit);
    return -1;  // keep going; `limit` already clips the exact tests
  });
  return best;
}

Real RigidBodySystem::kineticEnergy() const {
  Real e = 0;
  for (const BodyRecord& b : d_->bodies) {
    if (!b.alive || b.type != BodyType::Dynamic || b.group >= 0) continue;
    const Mat3 R = b.pose.q.toRotationMatrix();
    e += Real(0.5) * b.mass * b.v.squaredNorm() +
         Real(0.5) * b.w.dot(worldMomentum(R, b.inertiaLocal, b.w));
  }
  return e;
}

Vec3 RigidBodySystem::linearMomentum() const {
  Vec3 p = Vec3::Zero();
  for (const BodyRecord& b : d_->bodies)
    if (b.alive && b.type == BodyType::Dynamic && b.group < 0) p += b.mass * b.v;
  return p;
}

Vec3 RigidBodySystem::angularMomentum(const Vec3& about) const {
  Vec3 L = Vec3::Zero();
  for (const BodyRecord& b : d_->bodies) {
    if (!b.alive || b.type != BodyType::Dynamic || b.group >= 0) continue;
    const Mat3 R = b.pose.q.toRotationMatrix();
    L += worldMomentum(R, b.inertiaLocal, b.w) + (b.com - about).cross(b.mass * b.v);
  }
  return L;
}

void RigidBodySystem::step(Real dt, const DynamicsSettings& s, ThreadPool* pool) {
  detail::StepWorkers::run(pool ? &pool->impl().arena : nullptr,
                           [&](detail::StepWorkers& workers) { step(dt, s, workers); });
}

void RigidBodySystem::step(Real dt, const DynamicsSettings& s, detail::StepWorkers& workers) {
  require(std::isfinite(dt) && dt > 0, "RigidBodySystem::step: dt must be finite and > 0 (s)");
  using Clock = std::chrono::steady_clock;
  Data& D = *d_;
  D.beginEvents.clear();
  D.endEvents.clear();
  D.jointEvents.clear();
  const auto t0 = Clock::now();
  detail::capStartSpeeds(D, workers);
  detail::updateBroadPhase(D, dt, s.contact, workers);
  const auto t1 = Clock::now();
  // The islands beside the warm start's matching, the contact events beside the bodies'
  // motion: each pair shares no data.
  detail::updateContacts(D, dt, s.contact, workers, &detail::buildIslands);
  detail::prepareContacts(D, s, dt, workers);
  const auto t2 = Clock::now();
  const double integration = detail::solveSubsteps(D, s, dt, workers);
  const auto t3 = Clock::now();
  detail::finalizeBodies(D, s, dt, workers, &detail::reportContactEvents);
  detail::sleepIslands(D, s);
  const auto t4 = Clock::now();
  D.times.broadPhase += std::chrono::duration<double>(t1 - t0).count();
  D.times.narrowPhase += std::chrono::duration<double>(t2 - t1).count();
  D.times.solver += std::chrono::duration<double>(t3 - t2).count() - integration;
  D.times.integration += std::chrono::duration<double>(t4 - t3).count() + integration;
}

}  // namespace inertia
