// The rigid-body pipeline of a step (Box2D v3's order, in 3D):
//   1. broad phase: move the proxies of awake bodies (boxes swept over the step for fast
//      bodies), collect candidate pairs from the dynamic AABB tree, plus the static planes;
//   2. narrow phase: collide() each pair with a speculative margin; warm-start impulses are
//      matched to the previous step's points by (shapes, sub-shapes, feature id);
//   3. islands: union-find over touching pairs; an island with one awake body wakes whole;
//   4. solve: bodies without contacts fly free with the chosen ode method and the exact
//      momentum-conserving rotation splitting; the others go through the contact solver
//      (soft step, pgs, or a direct LCP per island: lcp_contact.h) in `substeps` substeps;
//   5. finalise: poses from the solver's motion, sleep timers, island sleep, contact events.
#include "inertia/dynamics/rigid_body_system.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include "contact_solver.h"
#include "integrate.h"
#include "lcp_contact.h"
#include "inertia/collision/dynamic_tree.h"
#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/geometry/bounds.h"
#include "inertia/geometry/mass.h"
#include "inertia/ode/step.h"

namespace inertia {

using detail::ContactConstraint;
using detail::SolverBody;

namespace {

// The angular momentum R I R^T w of a body with local inertia I turned by R, as three
// matrix-vector products (no 3x3 product temporaries; GCC 12 at -O1 with the sanitizers also
// warned, falsely, about those in Eigen).
Vec3 worldMomentum(const Mat3& R, const Mat3& inertiaLocal, const Vec3& w) {
  return R * (inertiaLocal * (R.transpose() * w));
}

struct SolverEntry {
  SolverType type;
  std::string_view name;
};
constexpr std::array<SolverEntry, 4> kSolvers{{{SolverType::SoftStep, "soft_step"},
                                               {SolverType::Pgs, "pgs"},
                                               {SolverType::LcpDantzig, "lcp_dantzig"},
                                               {SolverType::LcpLemke, "lcp_lemke"}}};

// Below this tangential speed (m/s) a contact sticks and static friction applies.
constexpr Real kStickSpeed = Real(0.01);

struct BodyRecord {
  std::uint32_t generation = 1;
  bool alive = false;
  BodyType type = BodyType::Dynamic;
  Transform pose;                  // of the origin
  Vec3 localCom = Vec3::Zero();
  Vec3 com = Vec3::Zero();         // world
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  Real mass = 0;
  Real invMass = 0;
  Mat3 inertiaLocal = Mat3::Zero();
  bool isotropic = false;  // inertiaLocal is exactly c * identity: no gyroscopic torque
  Mat3 invInertiaLocal = Mat3::Zero();
  Quat principalAxes = Quat::Identity();  // principal frame -> body frame
  Vec3 principalMoments = Vec3::Ones();
  Real linearDamping = 0;
  Real angularDamping = 0;
  Real gravityScale = 1;
  Real maxLinearSpeed = 400;
  Real maxAngularSpeed = 200;
  Real massOverride = 0;
  Vec3 inertiaOverride = Vec3::Zero();
  bool allowSleep = true;
  bool bullet = false;
  bool fast = false;  // continuous this step (isBullet, set by the broad phase for the narrow)
  bool awake = true;
  bool wasFree = false;     // flew free last step: `momentum` is current
  Vec3 momentum = Vec3::Zero();  // world angular momentum of a free body (kg m^2/s)
  Real sleepTime = 0;
  Real extent = 0;     // farthest shape point from the centre of mass (m)
  Real minExtent = 1;  // smallest half size of a shape (m)
  std::vector<std::uint32_t> shapes;
  std::string name;

  Mat3 invInertiaWorld() const {
    const Mat3 R = pose.q.toRotationMatrix();
    return R * invInertiaLocal * R.transpose();
  }
};

struct ShapeRecord {
  std::uint32_t generation = 1;
  bool alive = false;
  std::uint32_t body = 0;
  Collider collider{Shape(Sphere{1})};
  Transform local;
  bool atOrigin = true;  // local is the identity
  Material material;
  int proxy = DynamicTree::kNull;  // none for planes
  // A sphere about the shape's origin that holds the shape (m); infinite for a plane.
  Real radius = std::numeric_limits<Real>::infinity();
};

// Per contact, what the public ContactInfo does not carry: the friction state for warm starts.
struct ContactExtra {
  // Zeroed here: `{}` leaves Eigen vectors uninitialised (a new contact warm-started pgs
  // friction from garbage).
  ContactExtra() {
    tangentImpulse.fill(Vec3::Zero());
    localA.fill(Vec3::Zero());
    localB.fill(Vec3::Zero());
  }
  std::array<Vec3, 4> tangentImpulse;  // world vectors, reprojected on the new tangents
  Vec3 angularImpulse = Vec3::Zero();     // rolling + spinning, world
  Real approach = 0;  // fastest normal approach at the step's start (m/s, >= 0)
  bool touching = false;
  // Manifold reuse: B's shape pose in A's shape frame when the manifold was computed, and the
  // manifold in the shapes' frames (normal and points in A's, points on B in B's).
  bool reusable = false;
  Transform relative{};
  Vec3 localNormal = Vec3::UnitY();
  std::array<Vec3, 4> localA;
  std::array<Vec3, 4> localB;
  // The impulses are last step's already (a reused manifold, whose points are last step's):
  // the warm start's matching by feature ids skips it.
  bool carried = false;

  /// Last step's record for its reused manifold: keeps the manifold reuse fields and the
  /// impulses, and resets the rest as a new record has them.
  ContactExtra& reuse() {
    approach = 0;
    touching = false;
    carried = true;
    return *this;
  }
};

// What the narrow phase found for one chunk of pairs.
struct NarrowChunk {
  std::vector<ContactInfo> contacts;
  std::vector<ContactExtra> extras;
  std::vector<ContactManifold> manifolds;  // scratch for collide()
};

// Where a chunk of pairs appends its contacts: its own NarrowChunk when chunks run in parallel,
// the step's lists when they run in sequence.
struct NarrowOut {
  std::vector<ContactInfo>& contacts;
  std::vector<ContactExtra>& extras;
  std::vector<ContactManifold>& manifolds;  // scratch for collide()
};

// Pairs of these shapes make at most one manifold, so it can be carried along as a whole.
bool singleManifold(ShapeType t) {
  return t != ShapeType::Mesh && t != ShapeType::HeightField && t != ShapeType::Compound;
}

std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | std::uint64_t(b);
}

auto contactKey(const ContactInfo& c) {
  return std::make_tuple(c.shapeA.index, c.shapeB.index, c.manifold.subShapeA,
                         c.manifold.subShapeB);
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
            std::string("ContactTuning::") + field + (positive ? " must be finite and > 0"
                                                               : " must be finite and >= 0"));
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

struct RigidBodySystem::Data {
  std::vector<BodyRecord> bodies;
  std::vector<ShapeRecord> shapes;
  DynamicTree tree{DynamicTreeSettings{.margin = Real(0.05), .displacementMultiplier = 2}};
  std::vector<std::uint32_t> planes;  // shape indices of planes (unbounded: not in the tree)
  std::vector<ContactInfo> contacts;
  std::vector<ContactExtra> extras;
  std::vector<ContactEvent> beginEvents;
  std::vector<ContactEvent> endEvents;
  DynamicsTimes times;
  int liveBodies = 0;

  // Scratch, reused from step to step.
  std::vector<int> moved;     // proxies of the awake bodies
  std::vector<int> enlarged;  // those whose fat box changed this step
  // The tree's candidate pairs (proxy ids, sorted), kept from step to step: a pair stays while
  // the fat boxes overlap, and only proxies whose fat box changed are queried for new ones.
  // Creating, destroying or teleporting proxies sets `pairsDirty`, and the next step queries
  // every proxy of a non-static body again.
  std::vector<std::pair<int, int>> treePairs;
  std::vector<std::pair<int, int>> mergedPairs;
  bool pairsDirty = true;
  std::vector<std::pair<int, int>> proxyPairs;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> mergedShapePairs;  // scratch of the merge
  // Per shape slot, refreshed at each step's start: what the pair filter and the narrow phase
  // read of a shape and its body for every candidate pair, in a small record instead of the
  // shape's and body's large ones (the pile's 45,000 pairs a step missed the cache on those).
  struct ShapeFrame {
    Transform pose;  // world pose of the shape
    Material material;  // for the contacts' constraints
    std::uint32_t generation = 0;  // the shape's
    std::uint32_t body = 0;
    std::uint32_t bodyGeneration = 0;
    ShapeType type = ShapeType::Sphere;
    BodyType bodyType = BodyType::Static;
    bool awake = false;
    bool fast = false;  // its body is continuous this step (BodyRecord::fast)
    Real radius = std::numeric_limits<Real>::infinity();  // ShapeRecord::radius
  };
  std::vector<ShapeFrame> frames;
  std::vector<ContactManifold> manifolds;  // collide()'s scratch when the chunks run in sequence
  std::vector<ContactInfo> previous;
  std::vector<ContactExtra> previousExtras;
  std::vector<std::uint32_t> order;
  std::vector<std::size_t> touchingNow, touchingBefore;  // scratch of the contact events
  std::vector<ContactInfo> sortedContacts;  // scratch of the sort by key
  std::vector<ContactExtra> sortedExtras;
  std::vector<ContactConstraint> constraints;
  std::vector<SolverBody> solverBodies;
  std::vector<NarrowChunk> chunks;
  detail::ConstraintColoring coloring;
  detail::ContactBundles bundles;
  std::vector<int> solverIndex;     // per body slot, -1 when not in the solver
  std::vector<std::uint32_t> solverToBody;
  std::vector<Quat> startRotation;  // per solver body
  std::vector<Vec3> startCom;
  // Per solver body, what a substep's velocity and position updates need from its record, so
  // that the substeps read a small array instead of the bodies' large records.
  struct SubstepMotion {
    Vec3 dv = Vec3::Zero();  // h (gravity + force / m)
    Vec3 dw = Vec3::Zero();  // h I^-1 torque
    Real linearFactor = 1;   // 1 / (1 + h linear damping)
    Real angularFactor = 1;
    Real maxLinearSpeed = 0;
    Real maxAngularSpeed = 0;
    bool dynamic = false;
    bool gyroscopic = false;  // not c * identity: the implicit gyroscopic step applies
  };
  std::vector<SubstepMotion> motion;
  std::vector<std::uint32_t> island;  // union-find parents per body slot
  std::vector<std::uint8_t> islandAwake;
  std::vector<Real> islandSleep;
  std::vector<ode::Workspace<Real>> workspaces;  // per body slot (Verlet keeps history)

  BodyRecord& body(BodyId id) {
    require(isValidBody(id), "RigidBodySystem: invalid body id (index " + std::to_string(id.index) +
                                 ", generation " + std::to_string(id.generation) + ")");
    return bodies[id.index];
  }
  ShapeRecord& shape(ShapeId id) {
    require(isValidShape(id), "RigidBodySystem: invalid shape id (index " +
                                  std::to_string(id.index) + ")");
    return shapes[id.index];
  }
  bool isValidBody(BodyId id) const {
    return !id.isNull() && id.index < bodies.size() && bodies[id.index].alive &&
           bodies[id.index].generation == id.generation;
  }
  bool isValidShape(ShapeId id) const {
    return !id.isNull() && id.index < shapes.size() && shapes[id.index].alive &&
           shapes[id.index].generation == id.generation;
  }
  BodyId bodyId(std::uint32_t i) const { return {i, bodies[i].generation}; }
  ShapeId shapeId(std::uint32_t i) const { return {i, shapes[i].generation}; }
  // Most shapes sit at their body's origin: their pose is the body's, bit for bit, without
  // composing (the narrow phase asks twice per pair).
  Transform shapePose(const ShapeRecord& s) const {
    return s.atOrigin ? bodies[s.body].pose : bodies[s.body].pose * s.local;
  }

  void updateMass(BodyRecord& b);
  void refreshProxies(BodyRecord& b);
  void dropContacts(std::uint32_t shape);
  void wake(BodyRecord& b) {
    if (b.type == BodyType::Static) return;
    b.awake = true;
    b.sleepTime = 0;
  }
};

void RigidBodySystem::Data::updateMass(BodyRecord& b) {
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
    b.invInertiaLocal = b.inertiaLocal.inverse();
    // Principal axes for the free-rotation splitting (a proper rotation).
    Eigen::SelfAdjointEigenSolver<Mat3> eig(b.inertiaLocal);
    Mat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    b.principalAxes = Quat(axes).normalized();
    b.principalMoments = eig.eigenvalues().cwiseMax(Real(1e-12) * eig.eigenvalues().maxCoeff());
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

void RigidBodySystem::Data::refreshProxies(BodyRecord& b) {
  for (std::uint32_t si : b.shapes) {
    ShapeRecord& s = shapes[si];
    if (s.proxy == DynamicTree::kNull) continue;
    tree.destroyProxy(s.proxy);
    s.proxy = tree.createProxy(worldBounds(s.collider.shape(), shapePose(s)), si);
    pairsDirty = true;
  }
}

void RigidBodySystem::Data::dropContacts(std::uint32_t shape) {
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
  std::uint32_t index = 0;
  while (index < D.bodies.size() && D.bodies[index].alive) ++index;
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
  for (std::uint32_t si : b.shapes) {
    ShapeRecord& s = D.shapes[si];
    if (s.proxy != DynamicTree::kNull) D.tree.destroyProxy(s.proxy);
    s.proxy = DynamicTree::kNull;
    D.pairsDirty = true;
    s.alive = false;
    ++s.generation;
    D.planes.erase(std::remove(D.planes.begin(), D.planes.end(), si), D.planes.end());
    D.dropContacts(si);
  }
  b.shapes.clear();
  b.alive = false;
  ++b.generation;
  --D.liveBodies;
}

bool RigidBodySystem::isValid(BodyId id) const { return d_->isValidBody(id); }
bool RigidBodySystem::isValid(ShapeId id) const { return d_->isValidShape(id); }

ShapeId RigidBodySystem::addShape(BodyId body, const Shape& shape, const Material& material,
                                  const Transform& local) {
  return addShape(body, Collider(shape), material, local);
}

ShapeId RigidBodySystem::addShape(BodyId bodyId, const Collider& collider,
                                  const Material& material, const Transform& local) {
  Data& D = *d_;
  BodyRecord& b = D.body(bodyId);
  validate(material);
  require(allFinite(local.p) && allFinite(local.q) && std::abs(local.q.norm() - 1) < Real(1e-3),
          "RigidBodySystem::addShape: the local transform must be finite with a unit quaternion");
  const ShapeType type = collider.type();
  if (type == ShapeType::Plane || type == ShapeType::HeightField)
    require(b.type == BodyType::Static,
            std::string("RigidBodySystem::addShape: a ") +
                (type == ShapeType::Plane ? "plane" : "height field") +
                " can only be attached to a static body");
  // Fails (InvalidArgument) for open meshes and other shapes without a volume.
  if (b.type == BodyType::Dynamic) (void)massProperties(collider.shape(), material.density);

  std::uint32_t index = 0;
  while (index < D.shapes.size() && D.shapes[index].alive) ++index;
  if (index == D.shapes.size()) D.shapes.emplace_back();
  ShapeRecord& s = D.shapes[index];
  s.alive = true;
  s.body = bodyId.index;
  s.collider = collider;
  s.local = {local.p, local.q.normalized()};
  s.atOrigin = s.local.p == Vec3::Zero() && s.local.q.coeffs() == Quat::Identity().coeffs();
  s.material = material;
  s.proxy = DynamicTree::kNull;
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
    s.proxy = D.tree.createProxy(worldBounds(collider.shape(), D.shapePose(s)), index);
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
  if (s.proxy != DynamicTree::kNull) D.tree.destroyProxy(s.proxy);
  s.proxy = DynamicTree::kNull;
  D.pairsDirty = true;
  D.planes.erase(std::remove(D.planes.begin(), D.planes.end(), id.index), D.planes.end());
  D.dropContacts(id.index);
  b.shapes.erase(std::remove(b.shapes.begin(), b.shapes.end(), id.index), b.shapes.end());
  s.alive = false;
  ++s.generation;
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
BodyType RigidBodySystem::type(BodyId id) const { return d_->body(id).type; }
std::string_view RigidBodySystem::name(BodyId id) const { return d_->body(id).name; }
bool RigidBodySystem::isAwake(BodyId id) const { return d_->body(id).awake; }
BodyId RigidBodySystem::body(ShapeId id) const { return d_->bodyId(d_->shape(id).body); }

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
  require(b.type == BodyType::Kinematic, "RigidBodySystem::moveKinematic: the body is not kinematic");
  const Quat q = target.q.normalized();
  const Vec3 targetCom = target.p + q * b.localCom;
  b.v = (targetCom - b.com) / dt;
  b.w = rotationVector(q * b.pose.q.conjugate()) / dt;
  d_->wake(b);
}

void RigidBodySystem::applyForce(BodyId id, const Vec3& f, const Vec3& point) {
  require(allFinite(f) && allFinite(point), "RigidBodySystem::applyForce: force and point must be finite");
  BodyRecord& b = d_->body(id);
  if (b.type != BodyType::Dynamic) return;
  b.force += f;
  b.torque += (point - b.com).cross(f);
  d_->wake(b);
}

void RigidBodySystem::applyForceAtCenter(BodyId id, const Vec3& f) {
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
  require(allFinite(J) && allFinite(point), "RigidBodySystem::applyImpulse: impulse and point must be finite");
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
Transform RigidBodySystem::shapeTransform(ShapeId id) const {
  return d_->shapePose(d_->shape(id));
}
const Material& RigidBodySystem::material(ShapeId id) const { return d_->shape(id).material; }
const std::vector<ContactInfo>& RigidBodySystem::contacts() const { return d_->contacts; }
const DynamicTree& RigidBodySystem::broadPhaseTree() const { return d_->tree; }
const std::vector<ContactEvent>& RigidBodySystem::beginEvents() const { return d_->beginEvents; }
const std::vector<ContactEvent>& RigidBodySystem::endEvents() const { return d_->endEvents; }
const DynamicsTimes& RigidBodySystem::times() const { return d_->times; }

std::optional<WorldRayHit> RigidBodySystem::castRay(const Ray& ray) const {
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
  D.tree.rayCast(ray, [&](int proxy, Real maxFraction) -> Real {
    const Real limit = best ? std::min(maxFraction, best->hit.fraction) : maxFraction;
    consider(D.tree.userData(proxy), limit);
    return -1;  // keep going; `limit` already clips the exact tests
  });
  return best;
}

Real RigidBodySystem::kineticEnergy() const {
  Real e = 0;
  for (const BodyRecord& b : d_->bodies) {
    if (!b.alive || b.type != BodyType::Dynamic) continue;
    const Mat3 R = b.pose.q.toRotationMatrix();
    e += Real(0.5) * b.mass * b.v.squaredNorm() +
         Real(0.5) * b.w.dot(worldMomentum(R, b.inertiaLocal, b.w));
  }
  return e;
}

Vec3 RigidBodySystem::linearMomentum() const {
  Vec3 p = Vec3::Zero();
  for (const BodyRecord& b : d_->bodies)
    if (b.alive && b.type == BodyType::Dynamic) p += b.mass * b.v;
  return p;
}

Vec3 RigidBodySystem::angularMomentum(const Vec3& about) const {
  Vec3 L = Vec3::Zero();
  for (const BodyRecord& b : d_->bodies) {
    if (!b.alive || b.type != BodyType::Dynamic) continue;
    const Mat3 R = b.pose.q.toRotationMatrix();
    L += worldMomentum(R, b.inertiaLocal, b.w) + (b.com - about).cross(b.mass * b.v);
  }
  return L;
}

namespace {

// How far a body may move in a step (m): translation plus rotation of its farthest point.
Real motionBound(const BodyRecord& b, Real dt) {
  return (b.v.norm() + b.w.norm() * b.extent) * dt;
}

bool isBullet(const BodyRecord& b, Real dt, const ContactTuning& tuning) {
  if (b.type == BodyType::Static) return false;
  return b.bullet || motionBound(b, dt) > tuning.bulletFraction * b.minExtent;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

void RigidBodySystem::step(Real dt, const DynamicsSettings& s, tbb::task_arena* arena) {
  require(std::isfinite(dt) && dt > 0, "RigidBodySystem::step: dt must be finite and > 0 (s)");
  // One thread: the sequential paths, without the tasks' overhead and the chunks' copies (the
  // results are the same either way).
  if (arena && arena->max_concurrency() <= 1) arena = nullptr;
  using Clock = std::chrono::steady_clock;
  Data& D = *d_;
  const ContactTuning& tuning = s.contact;
  const std::uint32_t bodyCount = static_cast<std::uint32_t>(D.bodies.size());
  D.beginEvents.clear();
  D.endEvents.clear();

  // 1. Broad phase.
  auto t0 = Clock::now();
  D.moved.clear();
  D.enlarged.clear();
  D.frames.resize(D.shapes.size());
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive) continue;
    b.fast = isBullet(b, dt, tuning);
    for (std::uint32_t si : b.shapes)
      D.frames[si] = {D.shapePose(D.shapes[si]), D.shapes[si].material, D.shapes[si].generation,
                      bi, b.generation, D.shapes[si].collider.type(), b.type, b.awake, b.fast,
                      D.shapes[si].radius};
    if (b.type == BodyType::Static || !b.awake) continue;
    const bool bullet = b.fast;
    const Vec3 displacement = b.v * dt;
    for (std::uint32_t si : b.shapes) {
      ShapeRecord& sh = D.shapes[si];
      if (sh.proxy == DynamicTree::kNull) continue;
      Aabb box = worldBounds(sh.collider.shape(), D.frames[si].pose);
      if (bullet) {
        // Swept over the step, so a fast body meets what lies in its path.
        const Real spin = b.w.norm() * b.extent * dt;
        box = box.merged({box.lower + displacement, box.upper + displacement}).inflated(spin);
      }
      if (D.tree.moveProxy(sh.proxy, box.inflated(tuning.speculativeDistance), displacement))
        D.enlarged.push_back(sh.proxy);
      D.moved.push_back(sh.proxy);
    }
  }
  if (D.pairsDirty) {
    D.enlarged.clear();
    D.treePairs.clear();
    for (const ShapeRecord& sh : D.shapes)
      if (sh.alive && sh.proxy != DynamicTree::kNull && D.bodies[sh.body].type != BodyType::Static)
        D.enlarged.push_back(sh.proxy);
    D.pairsDirty = false;
  }
  D.tree.computePairs(D.enlarged, D.proxyPairs);
  // Last step's pairs whose fat boxes still overlap, joined with the new candidates.
  std::erase_if(D.treePairs, [&](const std::pair<int, int>& pq) {
    return !D.tree.fatAabb(pq.first).overlaps(D.tree.fatAabb(pq.second));
  });
  D.mergedPairs.clear();
  std::set_union(D.treePairs.begin(), D.treePairs.end(), D.proxyPairs.begin(),
                 D.proxyPairs.end(), std::back_inserter(D.mergedPairs));
  std::swap(D.treePairs, D.mergedPairs);
  D.pairs.clear();
  auto addPair = [&](std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    const Data::ShapeFrame& fa = D.frames[a];
    const Data::ShapeFrame& fb = D.frames[b];
    if (fa.body == fb.body) return;
    if (fa.bodyType != BodyType::Dynamic && fb.bodyType != BodyType::Dynamic) return;
    if (!fa.awake && !fb.awake) return;
    D.pairs.emplace_back(a, b);
  };
  for (const auto& [p, q] : D.treePairs) addPair(D.tree.userData(p), D.tree.userData(q));
  const std::size_t treeCount = D.pairs.size();
  for (std::uint32_t plane : D.planes) {
    const Plane& pl = *D.shapes[plane].collider.shape().getIf<Plane>();
    const Transform& planePose = D.frames[plane].pose;
    const Vec3 n = planePose.rotate(pl.normal);
    const Real offset = pl.offset + n.dot(planePose.p);
    for (int proxy : D.moved) {
      const Aabb& fat = D.tree.fatAabb(proxy);
      const Vec3 c = Real(0.5) * (fat.lower + fat.upper);
      const Vec3 e = Real(0.5) * (fat.upper - fat.lower);
      if (n.dot(c) - offset - n.cwiseAbs().dot(e) <= 0) addPair(plane, D.tree.userData(proxy));
    }
  }
  // Sorted by shape index. The tree's pairs come sorted by proxy id, which follows the shape
  // order unless proxies were recycled: usually only the plane pairs need sorting, and a
  // merge. (Sorting the whole list every step cost 12% of the pile scene.)
  const auto treeEnd = D.pairs.begin() + std::ptrdiff_t(treeCount);
  if (!std::is_sorted(D.pairs.begin(), treeEnd)) std::sort(D.pairs.begin(), treeEnd);
  std::sort(treeEnd, D.pairs.end());
  // Merged into a kept buffer (std::inplace_merge would allocate one every step).
  D.mergedShapePairs.clear();
  std::merge(D.pairs.begin(), treeEnd, treeEnd, D.pairs.end(),
             std::back_inserter(D.mergedShapePairs));
  std::swap(D.pairs, D.mergedShapePairs);
  D.pairs.erase(std::unique(D.pairs.begin(), D.pairs.end()), D.pairs.end());
  auto t1 = Clock::now();
  D.times.broadPhase += std::chrono::duration<double>(t1 - t0).count();

  // 2. Narrow phase.
  const bool reuse = tuning.reuseDistance > 0 && tuning.reuseAngle > 0;
  const Real reuseDistance2 = tuning.reuseDistance * tuning.reuseDistance;
  const Real reuseCosine = std::cos(Real(0.5) * tuning.reuseAngle);  // |q . q'| = cos(angle / 2)
  std::swap(D.previous, D.contacts);
  std::swap(D.previousExtras, D.extras);
  D.contacts.clear();
  D.extras.clear();
  // The pairs in fixed chunks (boundaries independent of the thread count), each collided into
  // its own buffers on the arena, then joined in chunk order: the same contacts in the same
  // order whatever the number of threads.
  constexpr std::size_t kPairChunk = 32;
  const std::size_t chunkCount = (D.pairs.size() + kPairChunk - 1) / kPairChunk;
  if (D.chunks.size() < chunkCount) D.chunks.resize(chunkCount);
  // Appends chunk `chunk`'s contacts to out.contacts and out.extras.
  auto collideChunk = [&](std::size_t chunk, NarrowOut out) {
    const std::size_t first = chunk * kPairChunk;
    const std::size_t last = std::min(first + kPairChunk, D.pairs.size());
    auto previous = std::lower_bound(
        D.previous.begin(), D.previous.end(),
        std::make_tuple(D.pairs[first].first, D.pairs[first].second, 0u, 0u),
        [](const ContactInfo& p, const auto& k) { return contactKey(p) < k; });
    for (std::size_t pi = first; pi < last; ++pi) {
      const auto [a, b] = D.pairs[pi];
      const Data::ShapeFrame& fa = D.frames[a];
      const Data::ShapeFrame& fb = D.frames[b];
      ContactSettings cs;
      cs.speculativeDistance = tuning.speculativeDistance;
      if (fa.fast || fb.fast) {
        const BodyRecord& ba = D.bodies[fa.body];
        const BodyRecord& bb = D.bodies[fb.body];
        cs.speculativeDistance +=
            ((bb.v - ba.v).norm() + ba.w.norm() * ba.extent + bb.w.norm() * bb.extent) * dt;
      }
      // The shapes' bounding spheres farther apart than the speculative distance: no contact,
      // without the narrow phase. A third of a resting rain's box pairs whose fat boxes
      // overlap end here. (A plane's infinite radius never passes.)
      const Real reach = fa.radius + fb.radius + cs.speculativeDistance;
      if ((fb.pose.p - fa.pose.p).squaredNorm() > reach * reach) continue;
      const Transform& poseA = fa.pose;
      const Transform& poseB = fb.pose;
      // The pair's ids, made only for a pair that has a manifold.
      const auto newContact = [&]() -> ContactInfo& {
        ContactInfo& info = out.contacts.emplace_back();
        info.bodyA = {fa.body, fa.bodyGeneration};
        info.bodyB = {fb.body, fb.bodyGeneration};
        info.shapeA = {a, fa.generation};
        info.shapeB = {b, fb.generation};
        return info;
      };
      // A sphere's manifold is one point query (two spheres: their centres), cheaper than
      // carrying one along.
      const bool convex = singleManifold(fa.type) && singleManifold(fb.type);
      const bool cacheable = reuse && cs.speculativeDistance == tuning.speculativeDistance &&
                             convex && fa.type != ShapeType::Sphere &&
                             fb.type != ShapeType::Sphere;
      // B's pose in A's, computed only for a pair with last step's manifold or a new one (most
      // of a rain's candidate pairs have neither).
      const auto relativePose = [&] { return poseA.inverse() * poseB; };
      if (cacheable) {
        // Last step's manifold of this pair, if its features still hold. The pairs and last
        // step's contacts are both sorted by shapes: one walk through the latter per chunk.
        const auto key = std::make_tuple(a, b, 0u, 0u);
        while (previous != D.previous.end() && contactKey(*previous) < key) ++previous;
        const auto it = previous;
        if (it != D.previous.end() && contactKey(*it) == key &&
            it->bodyA == BodyId{fa.body, fa.bodyGeneration}) {
          const ContactExtra& pe =
              D.previousExtras[static_cast<std::size_t>(it - D.previous.begin())];
          const Transform relative = relativePose();
          if (pe.reusable && (relative.p - pe.relative.p).squaredNorm() < reuseDistance2 &&
              std::abs(relative.q.dot(pe.relative.q)) > reuseCosine) {
            ContactInfo& info = newContact();
            info.manifold = it->manifold;
            info.normalImpulses = it->normalImpulses;
            ContactManifold& m = info.manifold;
            // Up to nine vectors to rotate: as matrices, each costs less than a quaternion
            // rotation.
            const Mat3 rotationA = poseA.q.toRotationMatrix();
            const Mat3 rotationB = poseB.q.toRotationMatrix();
            m.normal = rotationA * pe.localNormal;
            for (int k = 0; k < m.pointCount; ++k) {
              ContactPoint& p = m.points[static_cast<std::size_t>(k)];
              p.pointA = rotationA * pe.localA[static_cast<std::size_t>(k)] + poseA.p;
              p.pointB = rotationB * pe.localB[static_cast<std::size_t>(k)] + poseB.p;
              p.separation = (p.pointB - p.pointA).dot(m.normal);
            }
            // Last step's record carries the manifold's frames and the impulses.
            out.extras.emplace_back(pe).reuse();
            continue;
          }
        }
      }
      const auto add = [&](const ContactManifold& m) {
        newContact().manifold = m;
        ContactExtra& e = out.extras.emplace_back();
        if (cacheable) {
          e.reusable = true;
          e.relative = relativePose();
          e.localNormal = poseA.q.conjugate() * m.normal;
          for (int k = 0; k < m.pointCount; ++k) {
            const ContactPoint& p = m.points[static_cast<std::size_t>(k)];
            e.localA[static_cast<std::size_t>(k)] = poseA.applyInverse(p.pointA);
            e.localB[static_cast<std::size_t>(k)] = poseB.applyInverse(p.pointB);
          }
        }
      };
      const Collider& ca = D.shapes[a].collider;
      const Collider& cb = D.shapes[b].collider;
      if (convex) {
        // One manifold at most, without the vector.
        ContactManifold m;
        if (collideConvex(ca, poseA, cb, poseB, cs, m) && m.pointCount > 0) add(m);
        continue;
      }
      out.manifolds.clear();
      collide(ca, poseA, cb, poseB, cs, out.manifolds);
      for (const ContactManifold& m : out.manifolds)
        if (m.pointCount > 0) add(m);
    }
  };
  if (arena && chunkCount > 1) {
    arena->execute([&] {
      tbb::parallel_for(std::size_t(0), chunkCount, [&](std::size_t c) {
        NarrowChunk& chunk = D.chunks[c];
        chunk.contacts.clear();
        chunk.extras.clear();
        collideChunk(c, {chunk.contacts, chunk.extras, chunk.manifolds});
      });
    });
    for (std::size_t c = 0; c < chunkCount; ++c) {
      D.contacts.insert(D.contacts.end(), D.chunks[c].contacts.begin(), D.chunks[c].contacts.end());
      D.extras.insert(D.extras.end(), D.chunks[c].extras.begin(), D.chunks[c].extras.end());
    }
  } else {
    // In sequence the chunks append straight to the step's lists, in the same order.
    for (std::size_t c = 0; c < chunkCount; ++c)
      collideChunk(c, {D.contacts, D.extras, D.manifolds});
  }
  // Contacts between bodies that did not move (asleep or static) keep last step's state.
  for (std::size_t i = 0; i < D.previous.size(); ++i) {
    const ContactInfo& c = D.previous[i];
    // The cheap test first: most of last step's contacts have an awake body. (Body slots are
    // never freed, so the index is in range even for a destroyed body.)
    if (D.bodies[c.bodyA.index].awake || D.bodies[c.bodyB.index].awake) continue;
    if (!D.isValidShape(c.shapeA) || !D.isValidShape(c.shapeB)) continue;
    D.contacts.push_back(c);
    D.extras.push_back(D.previousExtras[i]);
  }
  // A deterministic order: by shapes, then sub-shapes. The pairs come sorted, so only the
  // kept contacts of resting bodies or a compound's manifolds can leave it unsorted.
  const auto byKey = [](const ContactInfo& x, const ContactInfo& y) {
    return contactKey(x) < contactKey(y);
  };
  if (!std::is_sorted(D.contacts.begin(), D.contacts.end(), byKey)) {
    D.order.resize(D.contacts.size());
    std::iota(D.order.begin(), D.order.end(), 0u);
    std::stable_sort(D.order.begin(), D.order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return byKey(D.contacts[x], D.contacts[y]);
    });
    D.sortedContacts.clear();
    D.sortedExtras.clear();
    for (std::uint32_t i : D.order) {
      D.sortedContacts.push_back(D.contacts[i]);
      D.sortedExtras.push_back(D.extras[i]);
    }
    D.contacts.swap(D.sortedContacts);
    D.extras.swap(D.sortedExtras);
  }
  // Warm start: match each point to last step's by (shapes, sub-shapes, feature id), in one
  // walk through both sorted lists.
  auto previous = D.previous.begin();
  for (std::size_t i = 0; i < D.contacts.size(); ++i) {
    ContactInfo& c = D.contacts[i];
    ContactExtra& e = D.extras[i];
    e.touching = false;
    for (int k = 0; k < c.manifold.pointCount; ++k)
      e.touching = e.touching || c.manifold.points[k].separation <= tuning.linearSlop;
    if (std::exchange(e.carried, false)) continue;
    const auto key = contactKey(c);
    while (previous != D.previous.end() && contactKey(*previous) < key) ++previous;
    const auto it = previous;
    if (it == D.previous.end() || contactKey(*it) != key || it->bodyA != c.bodyA) continue;
    const ContactExtra& pe = D.previousExtras[static_cast<std::size_t>(it - D.previous.begin())];
    bool carried = false;
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      for (int j = 0; j < it->manifold.pointCount; ++j) {
        if (it->manifold.points[j].id != c.manifold.points[k].id) continue;
        c.normalImpulses[k] = it->normalImpulses[j];
        e.tangentImpulse[k] = pe.tangentImpulse[j];
        carried = true;
      }
    }
    if (carried) e.angularImpulse = pe.angularImpulse;
  }
  auto t2 = Clock::now();
  D.times.narrowPhase += std::chrono::duration<double>(t2 - t1).count();

  // 3. Islands: union-find over contacts between dynamic bodies; one awake body (or a moving
  // kinematic body touching it) keeps its whole island awake.
  D.island.resize(bodyCount);
  std::iota(D.island.begin(), D.island.end(), 0u);
  D.islandAwake.assign(bodyCount, 0);
  for (const ContactInfo& c : D.contacts) {
    const BodyRecord& ba = D.bodies[c.bodyA.index];
    const BodyRecord& bb = D.bodies[c.bodyB.index];
    if (ba.type == BodyType::Dynamic && bb.type == BodyType::Dynamic) {
      const std::uint32_t ra = findRoot(D.island, c.bodyA.index);
      const std::uint32_t rb = findRoot(D.island, c.bodyB.index);
      if (ra != rb) D.island[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    const BodyRecord& b = D.bodies[bi];
    if (b.alive && b.type == BodyType::Dynamic && b.awake) D.islandAwake[findRoot(D.island, bi)] = 1;
  }
  for (const ContactInfo& c : D.contacts) {
    const BodyRecord& ba = D.bodies[c.bodyA.index];
    const BodyRecord& bb = D.bodies[c.bodyB.index];
    auto moving = [](const BodyRecord& k) {
      return k.type == BodyType::Kinematic && k.awake && (!k.v.isZero() || !k.w.isZero());
    };
    if (moving(ba) && bb.type == BodyType::Dynamic) D.islandAwake[findRoot(D.island, c.bodyB.index)] = 1;
    if (moving(bb) && ba.type == BodyType::Dynamic) D.islandAwake[findRoot(D.island, c.bodyA.index)] = 1;
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive || b.type != BodyType::Dynamic || b.awake) continue;
    if (D.islandAwake[findRoot(D.island, bi)]) D.wake(b);
  }

  // 4. Solver bodies: awake dynamic and kinematic bodies in a contact; the rest fly free.
  D.solverIndex.assign(bodyCount, -1);
  D.solverBodies.clear();
  D.solverToBody.clear();
  D.startRotation.clear();
  D.startCom.clear();
  auto solverSlot = [&](std::uint32_t bi) -> int {
    BodyRecord& b = D.bodies[bi];
    if (b.type == BodyType::Static) return -1;
    if (D.solverIndex[bi] < 0) {
      D.solverIndex[bi] = static_cast<int>(D.solverBodies.size());
      SolverBody sb;
      sb.v = b.v;
      sb.w = b.w;
      sb.invMass = b.invMass;
      sb.invInertia = b.invInertiaWorld();
      D.solverBodies.push_back(sb);
      D.solverToBody.push_back(bi);
      D.startRotation.push_back(b.pose.q);
      D.startCom.push_back(b.com);
    }
    return D.solverIndex[bi];
  };
  D.constraints.clear();
  const bool lcp = s.solver.type == SolverType::LcpDantzig || s.solver.type == SolverType::LcpLemke;
  const Real h = dt / Real(s.substeps);
  const Real hertz = std::min(tuning.hertz, Real(0.25) / h);
  const detail::Softness soft = detail::makeSoft(hertz, tuning.dampingRatio, h);
  const detail::Softness staticSoft = detail::makeSoft(2 * hertz, tuning.dampingRatio, h);
  for (std::size_t ci = 0; ci < D.contacts.size(); ++ci) {
    ContactInfo& info = D.contacts[ci];
    const BodyRecord& ba = D.bodies[info.bodyA.index];
    const BodyRecord& bb = D.bodies[info.bodyB.index];
    const bool aActive = ba.type == BodyType::Dynamic && ba.awake;
    const bool bActive = bb.type == BodyType::Dynamic && bb.awake;
    if (!aActive && !bActive) continue;
    ContactConstraint& c = D.constraints.emplace_back();
    c.contactIndex = static_cast<int>(ci);
    c.bodyA = solverSlot(info.bodyA.index);
    c.bodyB = solverSlot(info.bodyB.index);
    const Material& ma = D.frames[info.shapeA.index].material;
    const Material& mb = D.frames[info.shapeB.index].material;
    const Real staticFriction = combine(s.combine.friction, ma.friction, mb.friction);
    const Real slidingFriction = combine(s.combine.friction, ma.sliding(), mb.sliding());
    c.restitution = combine(s.combine.restitution, ma.restitution, mb.restitution);
    c.rolling = combine(s.combine.rollingFriction, ma.rollingFriction, mb.rollingFriction);
    c.spinning = combine(s.combine.spinningFriction, ma.spinningFriction, mb.spinningFriction);
    c.softness = (ba.invMass == 0 || bb.invMass == 0) ? staticSoft : soft;
    c.normal = info.manifold.normal;
    c.pointCount = info.manifold.pointCount;
    // Friction axes: along the sliding direction when sliding (as Jolt does), so the disc
    // clamp of the two rows' impulse opposes the sliding velocity even though the rows'
    // effective masses differ; otherwise a basis of the normal alone.
    // The anchors and the points' relative velocities first: the slip direction needs them all.
    std::array<Vec3, 4> dvs;
    Vec3 slip = Vec3::Zero();
    for (int k = 0; k < c.pointCount; ++k) {
      const ContactPoint& cp = info.manifold.points[static_cast<std::size_t>(k)];
      detail::ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
      const Vec3 mid = Real(0.5) * (cp.pointA + cp.pointB);
      p.rA = mid - ba.com;
      p.rB = mid - bb.com;
      dvs[std::size_t(k)] = bb.v + bb.w.cross(p.rB) - ba.v - ba.w.cross(p.rA);
      slip += dvs[std::size_t(k)];
    }
    slip -= slip.dot(c.normal) * c.normal;
    const Real slipNorm = slip.norm() / Real(c.pointCount);
    if (slipNorm > kStickSpeed) {
      c.tangent[0] = slip.normalized();
      c.tangent[1] = c.normal.cross(c.tangent[0]);
    } else {
      c.tangent = detail::tangentBasis(c.normal);
    }
    const ContactExtra& extra = D.extras[ci];
    Real tangentialSpeed2 = 0;  // the largest, squared
    for (int k = 0; k < c.pointCount; ++k) {
      const ContactPoint& cp = info.manifold.points[static_cast<std::size_t>(k)];
      detail::ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
      p.adjustedSeparation = cp.separation - (p.rB - p.rA).dot(c.normal);
      p.normalImpulse = info.normalImpulses[static_cast<std::size_t>(k)];
      for (int t = 0; t < 2; ++t)
        p.tangentImpulse[t] = extra.tangentImpulse[static_cast<std::size_t>(k)].dot(c.tangent[t]);
      const Vec3& dv = dvs[std::size_t(k)];
      p.relativeVelocity = dv.dot(c.normal);
      tangentialSpeed2 =
          std::max(tangentialSpeed2, (dv - p.relativeVelocity * c.normal).squaredNorm());
    }
    c.friction =
        tangentialSpeed2 < kStickSpeed * kStickSpeed ? staticFriction : slidingFriction;
    for (int t = 0; t < 2; ++t) c.rollingImpulse[t] = extra.angularImpulse.dot(c.tangent[t]);
    c.spinningImpulse = extra.angularImpulse.dot(c.normal);
  }
  if (lcp) {
    for (ContactConstraint& c : D.constraints) {
      const SolverBody none{};
      const SolverBody& a = c.bodyA >= 0 ? D.solverBodies[static_cast<std::size_t>(c.bodyA)] : none;
      const SolverBody& b = c.bodyB >= 0 ? D.solverBodies[static_cast<std::size_t>(c.bodyB)] : none;
      detail::computeMasses(c, a, b);
    }
  } else {
    // The bundles compute the masses themselves, eight constraints at a time.
    detail::colorConstraints(D.constraints, D.solverBodies, D.coloring);
    D.bundles.build(D.constraints, D.solverBodies, D.coloring);
  }
  auto t3 = Clock::now();
  D.times.narrowPhase += std::chrono::duration<double>(t3 - t2).count();

  // 5. Substeps.
  const bool softStep = s.solver.type == SolverType::SoftStep;
  const detail::LcpMethod lcpMethod = s.solver.type == SolverType::LcpLemke
                                          ? detail::LcpMethod::Lemke
                                          : detail::LcpMethod::Dantzig;
  detail::BiasMode mode;
  mode.soft = softStep;
  mode.invH = 1 / h;
  mode.pushVelocity = tuning.pushVelocity;
  mode.baumgarte = tuning.baumgarte;
  mode.linearSlop = tuning.linearSlop;
  detail::BiasMode relax = mode;
  relax.useBias = false;
  double integrationTime = 0;
  D.motion.resize(D.solverBodies.size());
  for (std::size_t k = 0; k < D.solverBodies.size(); ++k) {
    const BodyRecord& b = D.bodies[D.solverToBody[k]];
    Data::SubstepMotion& m = D.motion[k];
    m.dynamic = b.type == BodyType::Dynamic;
    m.dv = h * (b.gravityScale * s.gravity + b.invMass * b.force);
    m.dw = h * (D.solverBodies[k].invInertia * b.torque);
    m.linearFactor = 1 / (1 + h * b.linearDamping);
    m.angularFactor = 1 / (1 + h * b.angularDamping);
    m.maxLinearSpeed = b.maxLinearSpeed;
    m.maxAngularSpeed = b.maxAngularSpeed;
    // w x (I w) vanishes for a sphere's or a cube's inertia (c * identity); the implicit step
    // would only add its rounding.
    m.gyroscopic = !b.isotropic;
  }
  for (int sub = 0; sub < s.substeps; ++sub) {
    auto ti = Clock::now();
    // Velocities of the constrained bodies: gravity, forces, damping, implicit gyroscopic term.
    for (std::size_t k = 0; k < D.solverBodies.size(); ++k) {
      const Data::SubstepMotion& m = D.motion[k];
      SolverBody& sb = D.solverBodies[k];
      if (!m.dynamic) continue;
      sb.v += m.dv;
      sb.v *= m.linearFactor;
      sb.w += m.dw;
      if (m.gyroscopic) {
        const Quat q = (sb.dq * D.startRotation[k]).normalized();
        sb.w = detail::implicitGyroscopic(q, D.bodies[D.solverToBody[k]].inertiaLocal, sb.w, h);
      }
      sb.w *= m.angularFactor;
    }
    integrationTime += std::chrono::duration<double>(Clock::now() - ti).count();
    if (lcp) {
      // Direct LCP per island in place of the iterations (lcp_contact.h).
      detail::updateApproach(D.constraints, D.solverBodies);
      detail::solveContactsLcp(D.constraints, D.solverBodies, mode, lcpMethod,
                               s.solver.iterations);
    } else {
      D.bundles.updateApproach(D.solverBodies);
      D.bundles.warmStart(D.solverBodies, arena);
      for (int it = 0; it < s.solver.iterations; ++it)
        D.bundles.solve(D.solverBodies, mode, arena);
    }
    ti = Clock::now();
    for (std::size_t k = 0; k < D.solverBodies.size(); ++k) {
      const Data::SubstepMotion& m = D.motion[k];
      SolverBody& sb = D.solverBodies[k];
      const Real vn = sb.v.norm();
      if (vn > m.maxLinearSpeed) sb.v *= m.maxLinearSpeed / vn;
      const Real wn = sb.w.norm();
      if (wn > m.maxAngularSpeed) sb.w *= m.maxAngularSpeed / wn;
      sb.dp += h * sb.v;
      sb.dq = integrateRotation(sb.dq, sb.w, h);
      sb.dR = sb.dq.toRotationMatrix();
    }
    integrationTime += std::chrono::duration<double>(Clock::now() - ti).count();
    if (!lcp) D.bundles.updateMotion(D.solverBodies);
    if (softStep) {
      for (int it = 0; it < s.solver.relaxIterations; ++it)
        D.bundles.solve(D.solverBodies, relax, arena);
    }
  }
  if (lcp) {
    detail::applyRestitution(D.constraints, D.solverBodies, tuning.restitutionThreshold);
  } else {
    D.bundles.applyRestitution(D.solverBodies, tuning.restitutionThreshold, arena);
    D.bundles.store(D.constraints);
  }

  // Store the impulses for the next step's warm start and for the user.
  for (const ContactConstraint& c : D.constraints) {
    ContactInfo& info = D.contacts[static_cast<std::size_t>(c.contactIndex)];
    ContactExtra& extra = D.extras[static_cast<std::size_t>(c.contactIndex)];
    // A contact that pushed during the step touched, even if it began speculative; its
    // approach speed is the one measured just before the impact (updateApproach).
    extra.approach = 0;
    for (int k = 0; k < c.pointCount; ++k) {
      const detail::ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
      if (p.maxNormalImpulse > 0) extra.touching = true;
      extra.approach = std::max(extra.approach, -p.relativeVelocity);
      info.normalImpulses[static_cast<std::size_t>(k)] = p.normalImpulse;
      extra.tangentImpulse[static_cast<std::size_t>(k)] =
          p.tangentImpulse[0] * c.tangent[0] + p.tangentImpulse[1] * c.tangent[1];
    }
    extra.angularImpulse = c.rollingImpulse[0] * c.tangent[0] + c.rollingImpulse[1] * c.tangent[1] +
                           c.spinningImpulse * c.normal;
  }
  auto t4 = Clock::now();
  D.times.solver += std::chrono::duration<double>(t4 - t3).count() - integrationTime;

  // 6. Finalise: write back the solver's motion; free bodies fly with the chosen method.
  const Real sleepSpeed = tuning.sleepSpeed;
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (!b.alive || b.type == BodyType::Static || !b.awake) continue;
    const int k = D.solverIndex[bi];
    if (k >= 0) {
      const SolverBody& sb = D.solverBodies[static_cast<std::size_t>(k)];
      b.v = sb.v;
      b.w = sb.w;
      b.com = D.startCom[static_cast<std::size_t>(k)] + sb.dp;
      b.pose.q = (sb.dq * D.startRotation[static_cast<std::size_t>(k)]).normalized();
      b.wasFree = false;
    } else if (b.type == BodyType::Kinematic) {
      b.com += dt * b.v;
      b.pose.q = integrateRotationExact(b.pose.q, b.w, dt);
    } else {
      // Free flight: the linear motion by the world's ode method (exact for constant
      // acceleration with rk4 or velocity Verlet), the rotation by the momentum-conserving
      // splitting.
      const Vec3 accel = b.gravityScale * s.gravity + b.invMass * b.force;
      const Real c = b.linearDamping;
      auto a = [&](Real, const auto&, const auto& v, auto out) { out = accel - c * Vec3(v); };
      auto dadv = [c](Real, const auto&, const auto&, const auto& dir, auto out) {
        out = -c * dir;
      };
      ode::SecondOrderSystem system{a, ode::ZeroJacobian{}, dadv};
      ode::Workspace<Real>& ws = D.workspaces[bi];
      if (!b.wasFree) ws.resetHistory();
      Vec3 x = b.com;
      Vec3 v = b.v;
      // Carried from step to step while the body flies free, so that rounding in the
      // conversions between w and L does not accumulate.
      const Mat3 R = b.pose.q.toRotationMatrix();
      Vec3 L = b.wasFree ? b.momentum : worldMomentum(R, b.inertiaLocal, b.w);
      Quat principal = b.pose.q * b.principalAxes;
      for (int sub = 0; sub < s.substeps; ++sub) {
        ode::step(s.integrator, system, Real(0), h, x, v, ws);
        L += h * b.torque;
        L *= 1 / (1 + h * b.angularDamping);
        if (b.isotropic)
          // I = c 1 (a sphere, a cube): w = L / c keeps its axis, and the flow is one exact
          // rotation, one sine and cosine where the splitting takes five.
          principal = integrateRotationExact(principal, L / b.inertiaLocal(0, 0), h);
        else
          detail::splitFreeRotation(principal, b.principalMoments, L, h);
      }
      b.com = x;
      b.v = v;
      b.pose.q = (principal * b.principalAxes.conjugate()).normalized();
      if (b.isotropic) {
        b.w = L / b.inertiaLocal(0, 0);
      } else {
        const Vec3 Lb = principal.conjugate() * L;
        b.w = principal * Vec3(Lb.array() / b.principalMoments.array());
      }
      b.momentum = L;
      b.wasFree = true;
      const Real vn = b.v.norm();
      if (vn > b.maxLinearSpeed) b.v *= b.maxLinearSpeed / vn;
      const Real wn = b.w.norm();
      if (wn > b.maxAngularSpeed) {
        b.w *= b.maxAngularSpeed / wn;
        b.wasFree = false;
      }
    }
    b.pose.p = b.com - b.pose.q * b.localCom;
    b.force.setZero();
    b.torque.setZero();
    // Sleep timers: the speed of the farthest point bounds how fast anything on the body moves.
    const Real speed = std::max(b.v.norm(), b.w.norm() * b.extent);
    if (!s.sleeping || !b.allowSleep || b.type == BodyType::Kinematic || speed > sleepSpeed)
      b.sleepTime = 0;
    else
      b.sleepTime += dt;
  }
  // Islands whose every body has rested long enough fall asleep together.
  if (s.sleeping) {
    D.islandSleep.assign(bodyCount, std::numeric_limits<Real>::infinity());
    for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
      const BodyRecord& b = D.bodies[bi];
      if (!b.alive || b.type != BodyType::Dynamic) continue;
      Real& m = D.islandSleep[findRoot(D.island, bi)];
      m = std::min(m, b.sleepTime);
    }
    for (const ContactInfo& c : D.contacts) {  // touching a moving kinematic body: stay awake
      for (auto [k, o] : {std::pair{c.bodyA.index, c.bodyB.index}, std::pair{c.bodyB.index, c.bodyA.index}}) {
        const BodyRecord& kin = D.bodies[k];
        if (kin.type == BodyType::Kinematic && (!kin.v.isZero() || !kin.w.isZero()) &&
            D.bodies[o].type == BodyType::Dynamic)
          D.islandSleep[findRoot(D.island, o)] = 0;
      }
    }
    for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
      BodyRecord& b = D.bodies[bi];
      if (!b.alive || b.type != BodyType::Dynamic || !b.awake) continue;
      if (D.islandSleep[findRoot(D.island, bi)] >= tuning.timeToSleep) {
        b.awake = false;
        b.v.setZero();
        b.w.setZero();
      }
    }
  }
  for (std::uint32_t bi = 0; bi < bodyCount; ++bi) {
    BodyRecord& b = D.bodies[bi];
    if (b.alive && b.type == BodyType::Kinematic)
      b.awake = !b.v.isZero() || !b.w.isZero();
  }
  auto t5 = Clock::now();
  D.times.integration += std::chrono::duration<double>(t5 - t4).count() + integrationTime;

  // 7. Contact events: pairs of shapes touching now and not before, and the reverse.
  auto touchingPairs = [](const std::vector<ContactInfo>& cs, const std::vector<ContactExtra>& es,
                          std::vector<std::size_t>& out) {
    out.clear();
    for (std::size_t i = 0; i < cs.size(); ++i) {
      if (!es[i].touching) continue;
      if (!out.empty() && cs[out.back()].shapeA == cs[i].shapeA && cs[out.back()].shapeB == cs[i].shapeB)
        continue;
      out.push_back(i);
    }
  };
  std::vector<std::size_t>& now = D.touchingNow;
  std::vector<std::size_t>& before = D.touchingBefore;
  touchingPairs(D.contacts, D.extras, now);
  touchingPairs(D.previous, D.previousExtras, before);
  auto pairOf = [](const ContactInfo& c) { return pairKey(c.shapeA.index, c.shapeB.index); };
  auto event = [&](const ContactInfo& c, Real approach) {
    ContactEvent e;
    e.bodyA = c.bodyA;
    e.bodyB = c.bodyB;
    e.shapeA = c.shapeA;
    e.shapeB = c.shapeB;
    e.normal = c.manifold.normal;
    const ContactPoint& p = c.manifold.points[0];
    e.point = Real(0.5) * (p.pointA + p.pointB);
    e.approachSpeed = approach;
    return e;
  };
  std::size_t i = 0, j = 0;
  while (i < now.size() || j < before.size()) {
    const std::uint64_t a = i < now.size() ? pairOf(D.contacts[now[i]]) : ~std::uint64_t(0);
    const std::uint64_t b = j < before.size() ? pairOf(D.previous[before[j]]) : ~std::uint64_t(0);
    if (a == b) {
      ++i;
      ++j;
    } else if (a < b) {
      D.beginEvents.push_back(event(D.contacts[now[i]], D.extras[now[i]].approach));
      ++i;
    } else {
      const ContactInfo& c = D.previous[before[j]];
      if (D.isValidShape(c.shapeA) && D.isValidShape(c.shapeB)) D.endEvents.push_back(event(c, 0));
      ++j;
    }
  }
}

}  // namespace inertia
