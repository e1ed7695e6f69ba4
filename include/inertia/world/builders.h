// Scene builders: the stacks, walls, piles and rains, and the jointed pendulums, chains,
// bridges and ragdolls, that tests, benchmarks, the scene-file generators and the viewer's
// samples share (one place, as Box2D's shared/ folder). They return plain descriptions, so a
// benchmark can build the same scene in a peer engine; the jointed ones also come as add*()
// functions that build them in a World and return their ids (joints need their bodies first).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "inertia/dynamics/body.h"
#include "inertia/dynamics/joint.h"
#include "inertia/geometry/shapes.h"
#include "inertia/world/world.h"

namespace inertia {

/// A shape of a body description.
struct ShapeDesc {
  Shape shape = Sphere{Real(0.5)};
  Material material{};
  Transform local{};  ///< Relative to the body's origin.
  CollisionFilter filter{};  ///< Which shapes it collides with (body.h).
  /// Drawing colour (rgb, 0..1) from the scene's "color"; the simulation ignores it.
  std::optional<Vec3> color{};
};

/// A body with its shapes, ready to add to a world.
struct BodyDesc {
  BodySettings settings{};
  std::vector<ShapeDesc> shapes;
};

/// Adds a described body to `world` (InvalidArgument as createBody / addShape).
BodyId addBody(World& world, const BodyDesc& desc);

/// A 2D-style pyramid (a wall) of boxes in the x-y plane: `base` boxes in the bottom row, one
/// fewer per row above, base (base + 1) / 2 in all. `origin` is the centre of the bottom face
/// of the bottom row; `gap` (m) separates neighbours in a row.
struct PyramidSettings {
  int base = 10;
  Vec3 halfExtents = Vec3::Constant(Real(0.5));
  Vec3 origin = Vec3::Zero();
  Real gap = 0;
  Material material{};
  std::string name = "pyramid";  ///< Its bodies are named NAME_ROW_I.
};
std::vector<BodyDesc> pyramid(const PyramidSettings& settings);

/// A single column of `height` boxes standing on `origin` (centre of the bottom face).
struct TowerSettings {
  int height = 10;
  Vec3 halfExtents = Vec3::Constant(Real(0.5));
  Vec3 origin = Vec3::Zero();
  Material material{};
  std::string name = "tower";  ///< Its bodies are named NAME_I.
};
std::vector<BodyDesc> tower(const TowerSettings& settings);

/// A brick wall of `rows` x `columns` boxes in the x-y plane, alternate rows shifted by half
/// a brick when `staggered`; `origin` is the centre of its bottom face.
struct WallSettings {
  int rows = 5;
  int columns = 10;
  Vec3 halfExtents = Vec3(Real(0.5), Real(0.25), Real(0.25));
  Vec3 origin = Vec3::Zero();
  bool staggered = true;
  Material material{};
  std::string name = "wall";  ///< Its bodies are named NAME_ROW_COLUMN.
};
std::vector<BodyDesc> wall(const WallSettings& settings);

/// counts.x x counts.y x counts.z copies of `shape` on a lattice of `spacing` (m), the first at
/// `origin`, y up (a pile when dropped). Orientation identity.
struct GridSettings {
  std::array<int, 3> counts{10, 10, 10};
  Vec3 spacing = Vec3::Constant(Real(1.1));
  Vec3 origin = Vec3::Zero();
  Shape shape = Sphere{Real(0.5)};
  Material material{};
  std::string name = "grid";  ///< Its bodies are named NAME_I.
};
std::vector<BodyDesc> grid(const GridSettings& settings);

/// `count` copies of `shape` at uniformly random positions in [lower, upper] with uniformly
/// random orientations (Shoemake's method), from a seeded generator (same seed, same scene).
struct RainSettings {
  int count = 100;
  Vec3 lower = Vec3(-5, 5, -5);
  Vec3 upper = Vec3(5, 15, 5);
  Shape shape = Box{Vec3::Constant(Real(0.5))};
  Material material{};
  std::uint64_t seed = 1;
  std::string name = "rain";  ///< Its bodies are named NAME_I.
};
std::vector<BodyDesc> rain(const RainSettings& settings);

/// The settings of any joint type.
using AnyJointSettings =
    std::variant<BallJointSettings, HingeJointSettings, SliderJointSettings, UniversalJointSettings,
                 WeldJointSettings, DistanceJointSettings, SixDofJointSettings>;

/// A joint of an Assembly: its settings, with the bodies given as indices into
/// Assembly::bodies (the settings' own bodyA and bodyB are ignored; addAssembly() fills them).
struct AssemblyJoint {
  AnyJointSettings settings = BallJointSettings{};
  int bodyA = -1;  ///< Index into Assembly::bodies; -1: the world (anchorA, axisA then world).
  int bodyB = 0;   ///< Index into Assembly::bodies.
};

/// Bodies and the joints between them (a chain, a bridge, a ragdoll) as plain data. Anchors and
/// axes are in each body's frame as joint.h says; every joint is satisfied (zero error) in the
/// bodies' described poses.
struct Assembly {
  std::vector<BodyDesc> bodies;
  std::vector<AssemblyJoint> joints;
};

/// What addAssembly() made, in the assembly's order.
struct AssemblyIds {
  std::vector<BodyId> bodies;
  std::vector<JointId> joints;
};

/// Adds the bodies, then the joints (InvalidArgument as createBody, addShape and createJoint,
/// and for a body index out of range).
AssemblyIds addAssembly(World& world, const Assembly& assembly);

/// Appends `from`'s bodies and joints to `to` (its joints' body indices shifted to match), so
/// that many chains or ragdolls make one scene.
void append(Assembly& to, const Assembly& from);

/// Joints placed in an assembly's described poses, for building one by hand: at a world point
/// (m), about or along a world axis (not zero; a ball joint's is its cone's and twist's),
/// between bodies `bodyA` (-1: the world) and `bodyB` of `assembly` (indices; InvalidArgument
/// when out of range). The anchors and axes come out in each body's frame, so the joint starts
/// satisfied, its angle, twist or position zero; the caller adds limits, motors and the rest,
/// then pushes {settings, bodyA, bodyB} to the joints.
BallJointSettings ballJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                              const Vec3& axis = Vec3::UnitX());
HingeJointSettings hingeJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                                const Vec3& axis);
SliderJointSettings sliderJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                                  const Vec3& axis);

/// A pendulum: a sphere whose centre hangs `length` below a pivot fixed to the world (gravity
/// along -y), on a hinge about `axis` or a ball joint, released `angle` from straight down.
struct PendulumSettings {
  Vec3 pivot = Vec3(0, 2, 0);  ///< (m, world)
  Real length = 1;             ///< Pivot to the bob's centre (m), > 0.
  Real bobRadius = Real(0.1);  ///< (m), > 0.
  /// Release angle from straight down (rad), a turn about `axis` (right-hand rule).
  Real angle = 0;
  Vec3 axis = Vec3::UnitZ();  ///< The hinge's axis and the release turn's (world; not zero).
  JointType joint = JointType::Hinge;  ///< Hinge or Ball.
  Material material{};
  std::string name = "pendulum";
};
/// One body (the bob) and one joint (bodyA the world).
Assembly pendulum(const PendulumSettings& settings);

struct Pendulum {
  BodyId bob;
  JointId joint;
};
Pendulum addPendulum(World& world, const PendulumSettings& settings);

/// `links` capsules (each along its local y) end to end on ball joints at their ends, laid from
/// `top` along `direction`: hanging straight when it points down, released swinging when it is
/// horizontal. The first link hangs from the world at `top` when `hangFromWorld`; a sphere of
/// `endMass` hangs from the last one on another ball joint when endMass > 0.
struct ChainSettings {
  int links = 10;
  Vec3 top = Vec3(0, 10, 0);        ///< The first link's free end (m, world).
  Vec3 direction = -Vec3::UnitY();  ///< From `top` along the chain (world; not zero).
  Real linkRadius = Real(0.05);     ///< Capsule radius (m), > 0.
  /// Half the capsule's core segment (m), > 0: a link spans 2 (linkHalfHeight + linkRadius)
  /// from joint to joint (0.5 m by default).
  Real linkHalfHeight = Real(0.2);
  bool hangFromWorld = true;
  Real endMass = 0;             ///< Mass of the end sphere (kg, >= 0); 0: no sphere.
  Real endRadius = Real(0.25);  ///< Radius of the end sphere (m), > 0.
  Material material{};
  std::string name = "chain";
};
/// Bodies: the links from the top, then the end sphere. Joints: the world's (when hung), then
/// one per link pair from the top, then the end sphere's.
Assembly chain(const ChainSettings& settings);

struct Chain {
  std::vector<BodyId> links;    ///< From the top.
  std::vector<JointId> joints;  ///< From the top; the end sphere's last.
  BodyId end{};                 ///< The end sphere; null without one.
};
Chain addChain(World& world, const ChainSettings& settings);

/// A rope bridge: `planks` boxes in a row along x between two static posts, joined at the seams
/// (the middle of the gaps between neighbours, and between the end planks and the posts) by a
/// hinge about z each, or by two ball joints at the planks' edges (a rope along either side).
/// With slack > 0 the planks start on a circular arc that sags between the posts, every joint
/// satisfied; gravity then pulls them into a discrete catenary.
struct RopeBridgeSettings {
  int planks = 20;
  Vec3 center = Vec3(0, 5, 0);  ///< Midpoint between the posts' seams (m, world).
  /// Half extents of a plank (m): x along the bridge, y its thickness, z across.
  Vec3 plankHalfExtents = Vec3(Real(0.2), Real(0.05), Real(0.75));
  Real gap = Real(0.05);  ///< Between neighbouring planks, and a plank and a post (m, >= 0).
  /// The length of the planks and gaps over the posts' distance, minus one (>= 0): 0 is
  /// straight and taut.
  Real slack = Real(0.05);
  JointType joint = JointType::Ball;  ///< Ball (two a seam) or Hinge (one a seam, about z).
  Real breakForce = kUnbreakable;     ///< Each joint breaks above this force (N).
  Material material{};
  std::string name = "bridge";
};
/// Bodies: the planks from -x to +x, then the -x and +x posts (static). Joints: seam by seam
/// from the -x post; a seam's ball joints at -z, then +z.
Assembly ropeBridge(const RopeBridgeSettings& settings);

struct RopeBridge {
  std::vector<BodyId> planks;  ///< From -x to +x.
  BodyId leftPost{};           ///< At -x.
  BodyId rightPost{};
  std::vector<JointId> joints;  ///< Seam by seam from the -x post.
};
RopeBridge addRopeBridge(World& world, const RopeBridgeSettings& settings);

/// The parts of a ragdoll, in the order of Assembly::bodies and Ragdoll::parts. Left is the
/// figure's left (+x when it faces +z).
enum class RagdollPart : std::uint8_t {
  Pelvis,
  Torso,
  Head,
  UpperArmLeft,
  LowerArmLeft,
  UpperArmRight,
  LowerArmRight,
  UpperLegLeft,
  LowerLegLeft,
  UpperLegRight,
  LowerLegRight,
};
inline constexpr int kRagdollParts = 11;

/// A humanoid ragdoll standing upright, arms down: box pelvis and torso, sphere head, capsule
/// upper and lower arms and legs, 1.73 m tall and about 70 kg at scale 1 and density 1000
/// kg/m^3. Joints (10, collideConnected false): a hinge with limits at the waist (bending
/// forwards 0.8 rad, backwards 0.3), ball joints at the neck, shoulders and hips (free: without
/// cone or twist limits), hinges with limits at the elbows and knees (straight to 2.6 rad of
/// flexion, the right way).
struct RagdollSettings {
  /// The pelvis's centre (m, world); the soles are 0.95 m below it at scale 1.
  Vec3 position = Vec3(0, 1, 0);
  /// Of the whole figure: identity stands it along +y, facing +z, its left towards +x.
  Quat orientation = Quat::Identity();
  Real scale = 1;                      ///< Multiplies every length (> 0).
  Vec3 linearVelocity = Vec3::Zero();  ///< Of every part (m/s, world).
  Real jointFriction = 0;              ///< Torque resisting every joint's rotation (N m, >= 0).
  Material material{};
  std::string name = "ragdoll";
};
/// Bodies in RagdollPart order. Joints: waist, neck, left and right shoulder and elbow, left
/// and right hip and knee (the order of Ragdoll's named joints below).
Assembly ragdoll(const RagdollSettings& settings);

struct Ragdoll {
  std::array<BodyId, kRagdollParts> parts{};  ///< In RagdollPart order.
  std::vector<JointId> joints;                ///< As ragdoll() orders them.
  BodyId part(RagdollPart p) const { return parts[std::size_t(p)]; }
};
Ragdoll addRagdoll(World& world, const RagdollSettings& settings);

/// Box2D v3's joint_grid benchmark in 3D: rows x columns spheres in the x-y plane, `spacing`
/// apart, each joined to its right and lower neighbours by a ball joint at their midpoint
/// (rows (columns - 1) + (rows - 1) columns joints); the middle `pinned` spheres of the top row
/// hang from the world on ball joints at their centres (Box2D makes seven static).
struct JointGridSettings {
  int rows = 100;
  int columns = 100;
  Real spacing = 1;            ///< (m), > 2 radius
  Real radius = Real(0.4);     ///< (m)
  Vec3 top = Vec3(0, 100, 0);  ///< Centre of the top row (m, world).
  int pinned = 7;              ///< 0..columns
  Material material{};
  std::string name = "grid";
};
/// Bodies row by row from the top, each row from -x. Joints: the pins from -x, then sphere by
/// sphere in the bodies' order, the right neighbour's before the lower's.
Assembly jointGrid(const JointGridSettings& settings);

}  // namespace inertia
