// Internal: the state of a RigidBodySystem, shared by the stages of its step (the contact
// manager, the islands, the solver stages and the body motion, each in its own file).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "contact_solver.h"
#include "inertia/collision/broad_phase.h"
#include "inertia/core/error.h"
#include "inertia/dynamics/multibody.h"
#include "inertia/dynamics/rigid_body_system.h"
#include "inertia/ode/step.h"
#include "islands.h"
#include "joint_constraint.h"
#include "joint_trees.h"
#include "lcp_contact.h"

namespace inertia::detail {

// The angular momentum R I R^T w of a body with local inertia I turned by R, as three
// matrix-vector products (no 3x3 product temporaries; GCC 12 at -O1 with the sanitizers also
// warned, falsely, about those in Eigen).
inline Vec3 worldMomentum(const Mat3& R, const Mat3& inertiaLocal, const Vec3& w) {
  return R * (inertiaLocal * (R.transpose() * w));
}

// Below this tangential speed (m/s) a contact sticks and static friction applies.
inline constexpr Real kStickSpeed = Real(0.01);

struct BodyRecord {
  std::uint32_t generation = 1;
  bool alive = false;
  BodyType type = BodyType::Dynamic;
  Transform pose;  // of the origin
  Vec3 localCom = Vec3::Zero();
  Vec3 com = Vec3::Zero();  // world
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
  bool wasFree = false;          // flew free last step: `momentum` is current
  Vec3 momentum = Vec3::Zero();  // world angular momentum of a free body (kg m^2/s)
  Real sleepTime = 0;
  Real extent = 0;     // farthest shape point from the centre of mass (m)
  Real minExtent = 1;  // smallest half size of a shape (m)
  std::vector<std::uint32_t> shapes;
  std::vector<std::uint32_t> joints;  // the joints attached to it (slots)
  std::string name;
  // A driven body (multibody.h): its group and its member index there; -1 for a rigid body.
  int group = -1;
  int member = -1;

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
  CollisionFilter filter;
  int proxy = BroadPhase::kNull;  // none for planes
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
  Vec3 angularImpulse = Vec3::Zero();  // rolling + spinning, world
  Real approach = 0;                   // fastest normal approach at the step's start (m/s, >= 0)
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
// One worker's output, alone on its cache lines: neighbouring chunks are filled by different
// workers, and their vectors' headers change with every push.
template <class T>
struct alignas(64) ChunkOf {
  std::vector<T> items;
};

struct alignas(64) NarrowChunk {
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
inline bool singleManifold(ShapeType t) {
  return t != ShapeType::Mesh && t != ShapeType::HeightField && t != ShapeType::Compound;
}

inline std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | std::uint64_t(b);
}

inline auto contactKey(const ContactInfo& c) {
  return std::make_tuple(c.shapeA.index, c.shapeB.index, c.manifold.subShapeA,
                         c.manifold.subShapeB);
}

// How far a body may move in a step (m): translation plus rotation of its farthest point.
inline Real motionBound(const BodyRecord& b, Real dt) {
  return (b.v.norm() + b.w.norm() * b.extent) * dt;
}

inline bool isBullet(const BodyRecord& b, Real dt, const ContactTuning& tuning) {
  if (b.type == BodyType::Static) return false;
  return b.bullet || motionBound(b, dt) > tuning.bulletFraction * b.minExtent;
}

// The broad-phase type of a body's proxies (its tree, and which pairs it forms).
inline ProxyType proxyType(BodyType t) {
  return t == BodyType::Static      ? ProxyType::Static
         : t == BodyType::Kinematic ? ProxyType::Kinematic
                                    : ProxyType::Dynamic;
}

// A group of driven bodies and the response that moves them (multibody.h).
struct MultibodyGroup {
  MultibodyResponse* response = nullptr;  // null when the slot is free
  std::vector<std::uint32_t> members;     // body slots, by member index
  // Self-collision: each member's parent member (-1 at a root); empty when the members never
  // collide with each other.
  std::vector<int> parents;
  // Whether members i and j (i != j) may collide: with self-collision on, unless one is the
  // other's parent (a joint's two links touch by construction).
  bool membersCollide(int i, int j) const {
    return !parents.empty() && parents[std::size_t(i)] != j && parents[std::size_t(j)] != i;
  }
};

// One side of a contact that touches a driven body: a solver body (-1 for a static one), or a
// point of a group.
struct MultibodySide {
  int body = -1;
  int group = -1;
};

struct MultibodyPoint {
  std::array<int, 2> handle{-1, -1};  // per side, the group's point (a driven side)
  Vec3 rA = Vec3::Zero();             // anchors from the rigid sides' centres of mass (m)
  Vec3 rB = Vec3::Zero();
  Real separation = 0;  // at the step's start (m)
  Real normalMass = 0;
  std::array<Real, 2> tangentMass{};
  Real normalImpulse = 0;
  std::array<Real, 2> tangentImpulse{};
  Real maxNormalImpulse = 0;
  Real relativeVelocity = 0;  // normal velocity at the step's start (m/s)
};

struct MultibodyContact {
  int contactIndex = 0;
  MultibodySide a, b;
  Vec3 normal = Vec3::UnitY();
  std::array<Vec3, 2> tangent{Vec3::UnitX(), Vec3::UnitZ()};
  std::array<MultibodyPoint, 4> points{};
  int pointCount = 0;
  Real friction = 0;
  Real restitution = 0;
  Softness softness{};
};

// A joint with a driven body on a side: a loop closed through an articulation's links (a
// four-bar linkage, a body hung from or welded to a robot's hand, two branches of one tree).
// Its locked rows (the joint's own, lockedRows) keep the anchors and frames together, solved as
// one block beside the driven contacts through each side's 6 x 6 response
// (multibody_contacts.h). A driven side's reference point is its anchor; a rigid side's, its
// centre of mass.
struct MultibodyJoint {
  std::uint32_t joint = 0;
  MultibodySide a, b;
  std::array<int, 2> handle{-1, -1};  // per side, the group's frame (a driven side)
  Vec3 rA = Vec3::Zero();             // anchors from the rigid sides' centres of mass (m)
  Vec3 rB = Vec3::Zero();
  // The joint's frames: a rigid side's at the step's start (world), a driven side's in its
  // member's frame.
  Quat frameA = Quat::Identity();
  Quat frameB = Quat::Identity();
  Vec3 separation = Vec3::Zero();  // anchor B - anchor A at the step's start (m)
  Vec3 fallbackAxis = Vec3::UnitX();
  RowBlock rows;  // the locked rows now, their errors, and the accumulated impulses
  Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> mass;  // K^+ (refreshJoint)
  int stamp = -1;  // the position update `rows` and `mass` were made for (JointPass)
};

struct RigidBodyData {
  std::vector<BodyRecord> bodies;
  std::vector<ShapeRecord> shapes;
  // Every slot below these is alive: the search for the first free slot starts here, so that
  // creating n bodies costs O(n), not O(n^2) (100,000 bodies took minutes).
  std::uint32_t firstFreeBody = 0, firstFreeShape = 0, firstFreeJoint = 0;
  // The broad phase's proxies carry their shape's index; planes are unbounded and kept apart.
  BroadPhase broadPhase{{.tree = {.margin = Real(0.05), .displacementMultiplier = 2}}};
  std::vector<std::uint32_t> planes;  // shape indices of planes
  std::vector<ContactInfo> contacts;
  std::vector<ContactExtra> extras;
  std::vector<ContactEvent> beginEvents;
  std::vector<ContactEvent> endEvents;
  DynamicsTimes times;
  int liveBodies = 0;
  std::vector<JointRecord> joints;
  int liveJoints = 0;
  std::vector<JointEvent> jointEvents;  // the joints that broke in the last step
  std::vector<MultibodyGroup> multibodies;
  std::vector<MultibodyContact> multibodyContacts;  // this step's contacts on driven bodies
  std::vector<MultibodyJoint> multibodyJoints;      // this step's joints on driven bodies

  // Scratch, reused from step to step.
  std::vector<int> awakeProxies;  // the proxies of the awake bodies
  // The broad phase's candidate pairs (sorted), kept from step to step: a pair stays while the
  // fat boxes overlap, and only proxies whose fat box changed are queried for new ones.
  // Creating, destroying or teleporting proxies sets `pairsDirty`, and the next step queries
  // every proxy of a non-static body again.
  std::vector<ProxyPair> treePairs;
  std::vector<ProxyPair> mergedPairs;
  bool pairsDirty = true;
  std::vector<ProxyPair> proxyPairs;
  std::vector<ChunkOf<ProxyPair>> pairChunks;  // the parallel queries' output
  std::vector<Aabb> proxyBoxes;  // per shape slot: the new bounds of an awake body's proxy
  // Per shape slot: 1 when an awake body's proxy must go through BroadPhase::moveProxy (to be
  // reinserted, or refused); 0 when the broad phase keeps it (BroadPhase::keeps).
  std::vector<std::uint8_t> proxyMoves;
  using ShapePair = std::pair<std::uint32_t, std::uint32_t>;
  std::vector<ShapePair> pairs;
  std::vector<ShapePair> planePairs;                // scratch: the planes' pairs before the merge
  std::vector<ChunkOf<ShapePair>> shapePairChunks;  // the parallel filters' output
  std::vector<std::pair<std::uint32_t, std::uint32_t>> mergedShapePairs;  // scratch of the merge
  // Per shape slot, refreshed at each step's start: what the pair filter and the narrow phase
  // read of a shape and its body for every candidate pair, in a small record instead of the
  // shape's and body's large ones (the pile's 45,000 pairs a step missed the cache on those).
  struct ShapeFrame {
    Transform pose;                // world pose of the shape
    Material material;             // for the contacts' constraints
    std::uint32_t generation = 0;  // the shape's
    std::uint32_t body = 0;
    std::uint32_t bodyGeneration = 0;
    ShapeType type = ShapeType::Sphere;
    BodyType bodyType = BodyType::Static;
    bool awake = false;
    bool fast = false;       // its body is continuous this step (BodyRecord::fast)
    bool jointed = false;    // its body has an enabled joint whose bodies do not collide
    int group = -1;          // its body's multibody group (BodyRecord::group)
    CollisionFilter filter;  // ShapeRecord::filter
    Real radius = std::numeric_limits<Real>::infinity();  // ShapeRecord::radius
  };
  std::vector<ShapeFrame> frames;
  std::vector<ContactManifold> manifolds;  // collide()'s scratch when the chunks run in sequence
  std::vector<ContactInfo> previous;
  std::vector<ContactExtra> previousExtras;
  std::vector<std::uint32_t> order;
  std::vector<std::size_t> touchingNow, touchingBefore;  // scratch of the contact events
  std::vector<ContactInfo> sortedContacts;               // scratch of the sort by key
  std::vector<ContactExtra> sortedExtras;
  std::vector<ContactConstraint> constraints;
  std::vector<SolverBody> solverBodies;
  std::vector<NarrowChunk> chunks;
  std::vector<std::size_t> chunkOffsets;  // where each chunk's contacts go in `contacts`
  detail::ConstraintColoring coloring;
  detail::ContactBundles bundles;
  std::vector<int> solverIndex;  // per body slot, -1 when not in the solver
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
  UnionFind island;                     // per body slot: the islands for sleeping and waking
  std::vector<GraphEdge> contactEdges;  // per constraint: its solver bodies
  std::vector<JointConstraint> jointConstraints;  // this step's joints (in colour order)
  std::vector<GraphEdge> jointEdges;              // per joint edge: its solver bodies
  std::vector<std::uint32_t> edgeJoints;          // per joint edge: its JointRecord index
  JointTrees jointTrees;                          // this step's trees of ball joints
  std::vector<GraphEdge> lcpEdges;                // the contacts' edges, then the joints'
  ConstraintIslands lcpIslands;                   // the LCP solvers' islands of this step
  LcpWorkspace lcp;
  std::vector<std::uint8_t> islandAwake;
  std::vector<Real> islandSleep;
  std::vector<ode::Workspace<Real>> workspaces;  // per body slot (Verlet keeps history)

  BodyRecord& body(BodyId id) {
    require(isValidBody(id), "RigidBodySystem: invalid body id (index " + std::to_string(id.index) +
                                 ", generation " + std::to_string(id.generation) + ")");
    return bodies[id.index];
  }
  ShapeRecord& shape(ShapeId id) {
    require(isValidShape(id),
            "RigidBodySystem: invalid shape id (index " + std::to_string(id.index) + ")");
    return shapes[id.index];
  }
  bool isValidBody(BodyId id) const {
    return !id.isNull() && id.index < bodies.size() && bodies[id.index].alive &&
           bodies[id.index].generation == id.generation;
  }
  JointRecord& joint(JointId id) {
    require(isValidJoint(id), "RigidBodySystem: invalid joint id (index " +
                                  std::to_string(id.index) + ", generation " +
                                  std::to_string(id.generation) + ")");
    return joints[id.index];
  }
  bool isValidJoint(JointId id) const {
    return !id.isNull() && id.index < joints.size() && joints[id.index].alive &&
           joints[id.index].generation == id.generation;
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

  // Whether an enabled joint between body slots a and b keeps them from colliding.
  bool jointPrevents(std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t ji : bodies[a].joints) {
      const JointRecord& j = joints[ji];
      if (j.enabled && !j.collideConnected && (j.bodyA == b || j.bodyB == b)) return true;
    }
    return false;
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

/// A joint's frame on `body` (kWorldBody: the frame is the world's) in world coordinates.
inline Transform worldFrame(const RigidBodyData& D, std::uint32_t body, const Transform& frame) {
  return body == kWorldBody ? frame : D.bodies[body].pose * frame;
}

/// Whether a joint has a driven body (an articulation's link) on a side: it is solved as a
/// MultibodyJoint, not in the constraint graph.
inline bool drivenJoint(const RigidBodyData& D, const JointRecord& j) {
  return D.bodies[j.bodyB].group >= 0 || (j.bodyA != kWorldBody && D.bodies[j.bodyA].group >= 0);
}

}  // namespace inertia::detail
