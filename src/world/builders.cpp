#include "inertia/world/builders.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "inertia/core/error.h"
#include "inertia/core/math.h"

namespace inertia {

namespace {

BodyDesc boxBody(const Vec3& position, const Vec3& halfExtents, const Material& material,
                 const std::string& name) {
  BodyDesc d;
  d.settings.position = position;
  d.settings.name = name;
  d.shapes.push_back({Box{halfExtents}, material, {}});
  return d;
}

void requireCount(long long n, const char* what) {
  require(n >= 1 && n <= 10'000'000, std::string(what) + " must be in 1..10000000");
}

void requirePositive(Real x, const char* what) {
  require(std::isfinite(x) && x > 0, std::string(what) + " must be finite and > 0");
}

BodyDesc shapeBody(const Vec3& position, const Quat& orientation, const Shape& shape,
                   const Material& material, std::string name) {
  BodyDesc d;
  d.settings.position = position;
  d.settings.orientation = orientation;
  d.settings.name = std::move(name);
  d.shapes.push_back({shape, material, {}});
  return d;
}

Transform poseOf(const Assembly& a, int body) {
  if (body < 0) return {};  // the world
  const BodySettings& s = a.bodies[std::size_t(body)].settings;
  return {s.position, s.orientation.normalized()};
}

// A ball joint between bodies a and b of `as` (-1: the world) at a world point, with its anchors
// in each body's frame, so that it starts satisfied.
AssemblyJoint ballAt(const Assembly& as, int a, int b, const Vec3& point, Real friction = 0,
                     Real breakForce = kUnbreakable) {
  return {BallJointSettings{.anchorA = poseOf(as, a).applyInverse(point),
                            .anchorB = poseOf(as, b).applyInverse(point),
                            .friction = friction,
                            .breakForce = breakForce},
          a, b};
}

// A ball joint through a world point whose swing cone and twist limits are about a world axis
// (zero swing and twist in the described poses).
AssemblyJoint limitedBallAt(const Assembly& as, int a, int b, const Vec3& point, const Vec3& axis,
                            Real cone, JointLimits twist, Real friction) {
  AssemblyJoint j = ballAt(as, a, b, point, friction);
  auto& s = std::get<BallJointSettings>(j.settings);
  s.axisA = poseOf(as, a).q.conjugate() * axis;
  s.axisB = poseOf(as, b).q.conjugate() * axis;
  s.coneLimit = cone;
  s.twistLimits = twist;
  return j;
}

// A hinge about a world axis through a world point; limits are B's angle relative to A about
// the axis (right-hand rule), zero in the described poses.
AssemblyJoint hingeAt(const Assembly& as, int a, int b, const Vec3& point, const Vec3& axis,
                      std::optional<JointLimits> limits = {}, Real friction = 0,
                      Real breakForce = kUnbreakable) {
  const Transform pa = poseOf(as, a), pb = poseOf(as, b);
  return {HingeJointSettings{.anchorA = pa.applyInverse(point),
                             .anchorB = pb.applyInverse(point),
                             .axisA = pa.q.conjugate() * axis,
                             .axisB = pb.q.conjugate() * axis,
                             .limits = limits,
                             .friction = friction,
                             .breakForce = breakForce},
          a, b};
}

void requireBodies(const Assembly& as, int a, int b, const char* what) {
  const int n = int(as.bodies.size());
  require(a >= -1 && a < n && b >= 0 && b < n && a != b,
          std::string(what) + ": bodyA must be -1..bodies - 1 and bodyB 0..bodies - 1, not bodyA");
}

void requireAxis(const Vec3& point, const Vec3& axis, const char* what) {
  require(allFinite(point) && allFinite(axis) && axis.norm() > 0,
          std::string(what) + ": point and axis must be finite and axis not zero");
}

// Rotates local +y onto `up` (unit).
Quat yTo(const Vec3& up) { return Quat::FromTwoVectors(Vec3::UnitY(), up).normalized(); }

}  // namespace

BodyId addBody(World& world, const BodyDesc& desc) {
  const BodyId id = world.createBody(desc.settings);
  for (const ShapeDesc& s : desc.shapes) {
    const ShapeId shape = world.addShape(id, s.shape, s.material, s.local);
    world.rigidBodies().setFilter(shape, s.filter);  // returns at once on the default
  }
  return id;
}

std::vector<BodyDesc> pyramid(const PyramidSettings& s) {
  requireCount(s.base, "PyramidSettings::base");
  require(allFinite(s.origin) && s.gap >= 0 && std::isfinite(s.gap),
          "PyramidSettings: origin must be finite and gap finite and >= 0");
  std::vector<BodyDesc> out;
  out.reserve(std::size_t(s.base) * std::size_t(s.base + 1) / 2);
  const Real pitch = 2 * s.halfExtents.x() + s.gap;
  for (int row = 0; row < s.base; ++row) {
    const int n = s.base - row;
    for (int i = 0; i < n; ++i) {
      const Vec3 p = s.origin + Vec3((Real(i) - Real(n - 1) / 2) * pitch,
                                     s.halfExtents.y() * Real(2 * row + 1), 0);
      out.push_back(boxBody(p, s.halfExtents, s.material,
                            s.name + "_" + std::to_string(row) + "_" + std::to_string(i)));
    }
  }
  return out;
}

std::vector<BodyDesc> tower(const TowerSettings& s) {
  requireCount(s.height, "TowerSettings::height");
  std::vector<BodyDesc> out;
  for (int i = 0; i < s.height; ++i)
    out.push_back(boxBody(s.origin + Vec3(0, s.halfExtents.y() * Real(2 * i + 1), 0), s.halfExtents,
                          s.material, s.name + "_" + std::to_string(i)));
  return out;
}

std::vector<BodyDesc> wall(const WallSettings& s) {
  requireCount(s.rows, "WallSettings::rows");
  requireCount(s.columns, "WallSettings::columns");
  std::vector<BodyDesc> out;
  const Real pitch = 2 * s.halfExtents.x();
  for (int r = 0; r < s.rows; ++r) {
    const Real shift = (s.staggered && r % 2 == 1) ? Real(0.5) * pitch : 0;
    for (int c = 0; c < s.columns; ++c) {
      const Vec3 p = s.origin + Vec3((Real(c) - Real(s.columns - 1) / 2) * pitch + shift,
                                     s.halfExtents.y() * Real(2 * r + 1), 0);
      out.push_back(boxBody(p, s.halfExtents, s.material,
                            s.name + "_" + std::to_string(r) + "_" + std::to_string(c)));
    }
  }
  return out;
}

std::vector<BodyDesc> grid(const GridSettings& s) {
  for (int k = 0; k < 3; ++k) requireCount(s.counts[std::size_t(k)], "GridSettings::counts");
  require(allFinite(s.spacing) && allFinite(s.origin),
          "GridSettings: spacing and origin must be finite");
  std::vector<BodyDesc> out;
  for (int y = 0; y < s.counts[1]; ++y)
    for (int z = 0; z < s.counts[2]; ++z)
      for (int x = 0; x < s.counts[0]; ++x) {
        BodyDesc d;
        d.settings.position = s.origin + Vec3(Real(x) * s.spacing.x(), Real(y) * s.spacing.y(),
                                              Real(z) * s.spacing.z());
        d.settings.name = s.name + "_" + std::to_string(out.size());
        d.shapes.push_back({s.shape, s.material, {}});
        out.push_back(std::move(d));
      }
  return out;
}

std::vector<BodyDesc> rain(const RainSettings& s) {
  requireCount(s.count, "RainSettings::count");
  require(allFinite(s.lower) && allFinite(s.upper) && (s.lower.array() <= s.upper.array()).all(),
          "RainSettings: lower and upper must be finite with lower <= upper");
  std::mt19937_64 rng(s.seed);
  // Uniform reals from the raw 64-bit stream (std::uniform_real_distribution's algorithm is
  // not fixed by the standard, so its numbers may differ between library versions).
  auto uniform = [&rng]() { return double(rng() >> 11) * 0x1.0p-53; };
  std::vector<BodyDesc> out;
  for (int i = 0; i < s.count; ++i) {
    BodyDesc d;
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = s.lower[k] + Real(uniform()) * (s.upper[k] - s.lower[k]);
    // Shoemake 1992: a uniformly random unit quaternion from three uniforms.
    const double u1 = uniform(), u2 = uniform(), u3 = uniform();
    const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
    const double t2 = 2 * std::numbers::pi * u2, t3 = 2 * std::numbers::pi * u3;
    d.settings.position = p;
    d.settings.orientation = Quat(Real(b * std::cos(t3)), Real(a * std::sin(t2)),
                                  Real(a * std::cos(t2)), Real(b * std::sin(t3)))
                                 .normalized();
    d.settings.name = s.name + "_" + std::to_string(i);
    d.shapes.push_back({s.shape, s.material, {}});
    out.push_back(std::move(d));
  }
  return out;
}

BallJointSettings ballJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                              const Vec3& axis) {
  requireBodies(assembly, bodyA, bodyB, "ballJointAt");
  requireAxis(point, axis, "ballJointAt");
  const Transform pa = poseOf(assembly, bodyA), pb = poseOf(assembly, bodyB);
  return {.anchorA = pa.applyInverse(point),
          .anchorB = pb.applyInverse(point),
          .axisA = pa.q.conjugate() * axis.normalized(),
          .axisB = pb.q.conjugate() * axis.normalized()};
}

HingeJointSettings hingeJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                                const Vec3& axis) {
  requireBodies(assembly, bodyA, bodyB, "hingeJointAt");
  requireAxis(point, axis, "hingeJointAt");
  return std::get<HingeJointSettings>(
      hingeAt(assembly, bodyA, bodyB, point, axis.normalized()).settings);
}

SliderJointSettings sliderJointAt(const Assembly& assembly, int bodyA, int bodyB, const Vec3& point,
                                  const Vec3& axis) {
  requireBodies(assembly, bodyA, bodyB, "sliderJointAt");
  requireAxis(point, axis, "sliderJointAt");
  const Transform pa = poseOf(assembly, bodyA), pb = poseOf(assembly, bodyB);
  return {.anchorA = pa.applyInverse(point),
          .anchorB = pb.applyInverse(point),
          .axisA = pa.q.conjugate() * axis.normalized()};
}

AssemblyIds addAssembly(World& world, const Assembly& assembly) {
  const int n = int(assembly.bodies.size());
  for (std::size_t i = 0; i < assembly.joints.size(); ++i) {
    const AssemblyJoint& j = assembly.joints[i];
    require(j.bodyA >= -1 && j.bodyA < n && j.bodyB >= 0 && j.bodyB < n,
            "Assembly::joints[" + std::to_string(i) + "]: body index out of range");
  }
  AssemblyIds ids;
  ids.bodies.reserve(assembly.bodies.size());
  for (const BodyDesc& d : assembly.bodies) ids.bodies.push_back(addBody(world, d));
  ids.joints.reserve(assembly.joints.size());
  for (const AssemblyJoint& j : assembly.joints)
    ids.joints.push_back(std::visit(
        [&](auto settings) {
          settings.bodyA = j.bodyA < 0 ? BodyId{} : ids.bodies[std::size_t(j.bodyA)];
          settings.bodyB = ids.bodies[std::size_t(j.bodyB)];
          return world.createJoint(settings);
        },
        j.settings));
  return ids;
}

void append(Assembly& to, const Assembly& from) {
  const int offset = int(to.bodies.size());
  to.bodies.insert(to.bodies.end(), from.bodies.begin(), from.bodies.end());
  for (AssemblyJoint j : from.joints) {
    if (j.bodyA >= 0) j.bodyA += offset;
    j.bodyB += offset;
    to.joints.push_back(std::move(j));
  }
}

Assembly pendulum(const PendulumSettings& s) {
  requirePositive(s.length, "PendulumSettings::length");
  requirePositive(s.bobRadius, "PendulumSettings::bobRadius");
  require(allFinite(s.pivot) && std::isfinite(s.angle) && allFinite(s.axis) && s.axis.norm() > 0,
          "PendulumSettings: pivot, angle and axis must be finite and axis not zero");
  require(s.joint == JointType::Hinge || s.joint == JointType::Ball,
          "PendulumSettings::joint must be Hinge or Ball");
  const Vec3 axis = s.axis.normalized();
  const Quat turn(Eigen::AngleAxis<Real>(s.angle, axis));
  Assembly a;
  a.bodies.push_back(shapeBody(s.pivot + turn * Vec3(0, -s.length, 0), turn, Sphere{s.bobRadius},
                               s.material, s.name + "_bob"));
  a.joints.push_back(s.joint == JointType::Hinge ? hingeAt(a, -1, 0, s.pivot, axis)
                                                 : ballAt(a, -1, 0, s.pivot));
  return a;
}

Pendulum addPendulum(World& world, const PendulumSettings& settings) {
  const AssemblyIds ids = addAssembly(world, pendulum(settings));
  return {ids.bodies[0], ids.joints[0]};
}

Assembly chain(const ChainSettings& s) {
  requireCount(s.links, "ChainSettings::links");
  requirePositive(s.linkRadius, "ChainSettings::linkRadius");
  requirePositive(s.linkHalfHeight, "ChainSettings::linkHalfHeight");
  requirePositive(s.endRadius, "ChainSettings::endRadius");
  require(std::isfinite(s.endMass) && s.endMass >= 0, "ChainSettings::endMass must be >= 0");
  require(allFinite(s.top) && allFinite(s.direction) && s.direction.norm() > 0,
          "ChainSettings: top and direction must be finite and direction not zero");
  const Vec3 dir = s.direction.normalized();
  const Quat q = yTo(-dir);  // each link's +y end points back towards `top`
  const Real pitch = 2 * (s.linkHalfHeight + s.linkRadius);
  Assembly a;
  for (int i = 0; i < s.links; ++i)
    a.bodies.push_back(shapeBody(s.top + (Real(i) + Real(0.5)) * pitch * dir, q,
                                 Capsule{s.linkRadius, s.linkHalfHeight}, s.material,
                                 s.name + "_" + std::to_string(i)));
  if (s.hangFromWorld) a.joints.push_back(ballAt(a, -1, 0, s.top));
  for (int i = 1; i < s.links; ++i)
    a.joints.push_back(ballAt(a, i - 1, i, s.top + Real(i) * pitch * dir));
  if (s.endMass > 0) {
    const Vec3 end = s.top + Real(s.links) * pitch * dir;
    BodyDesc bob =
        shapeBody(end + s.endRadius * dir, q, Sphere{s.endRadius}, s.material, s.name + "_end");
    bob.settings.mass = s.endMass;
    a.bodies.push_back(std::move(bob));
    a.joints.push_back(ballAt(a, s.links - 1, s.links, end));
  }
  return a;
}

Chain addChain(World& world, const ChainSettings& settings) {
  AssemblyIds ids = addAssembly(world, chain(settings));
  Chain c;
  c.links.assign(ids.bodies.begin(), ids.bodies.begin() + settings.links);
  if (settings.endMass > 0) c.end = ids.bodies.back();
  c.joints = std::move(ids.joints);
  return c;
}

namespace {

// The seams of a bridge of n planks of pitch p (chord from seam to seam) whose end seams are
// `span` apart, centred on the origin in the x-y plane and sagging towards -y: equal chords on
// a circular arc. A plank subtends alpha, where span = p sin(n alpha / 2) / sin(alpha / 2); the
// ratio falls from n to 0 over alpha in (0, 2 pi / n), so bisection finds it.
std::vector<Vec3> bridgeSeams(int n, double p, double span) {
  std::vector<Vec3> seams(std::size_t(n) + 1);
  const double target = span / p;
  if (double(n) - target < 1e-9) {  // straight
    for (int k = 0; k <= n; ++k) seams[std::size_t(k)] = Vec3(Real((k - n / 2.0) * p), 0, 0);
    return seams;
  }
  double lo = 0, hi = 2 * std::numbers::pi / n;
  for (int it = 0; it < 200; ++it) {
    const double mid = (lo + hi) / 2;
    (std::sin(n * mid / 2) / std::sin(mid / 2) > target ? lo : hi) = mid;
  }
  const double alpha = (lo + hi) / 2, radius = p / (2 * std::sin(alpha / 2));
  const double half = n * alpha / 2, centreY = radius * std::cos(half);
  for (int k = 0; k <= n; ++k) {
    const double phi = -half + k * alpha;
    seams[std::size_t(k)] =
        Vec3(Real(radius * std::sin(phi)), Real(centreY - radius * std::cos(phi)), 0);
  }
  return seams;
}

}  // namespace

Assembly ropeBridge(const RopeBridgeSettings& s) {
  requireCount(s.planks, "RopeBridgeSettings::planks");
  require(allFinite(s.plankHalfExtents) && (s.plankHalfExtents.array() > 0).all(),
          "RopeBridgeSettings::plankHalfExtents must be finite and > 0");
  require(allFinite(s.center), "RopeBridgeSettings::center must be finite");
  require(std::isfinite(s.gap) && s.gap >= 0, "RopeBridgeSettings::gap must be finite and >= 0");
  require(std::isfinite(s.slack) && s.slack >= 0,
          "RopeBridgeSettings::slack must be finite and >= 0");
  require(s.joint == JointType::Hinge || s.joint == JointType::Ball,
          "RopeBridgeSettings::joint must be Hinge or Ball");
  require(s.breakForce > 0, "RopeBridgeSettings::breakForce must be > 0");
  const int n = s.planks;
  const double pitch = 2 * double(s.plankHalfExtents.x()) + double(s.gap);
  const std::vector<Vec3> seams = bridgeSeams(n, pitch, n * pitch / (1 + double(s.slack)));
  Assembly a;
  for (int k = 0; k < n; ++k) {
    const Vec3 from = seams[std::size_t(k)], to = seams[std::size_t(k) + 1];
    const Vec3 d = to - from;
    const Quat q(Eigen::AngleAxis<Real>(std::atan2(d.y(), d.x()), Vec3::UnitZ()));
    a.bodies.push_back(shapeBody(s.center + (from + to) / 2, q, Box{s.plankHalfExtents}, s.material,
                                 s.name + "_plank_" + std::to_string(k)));
  }
  // Posts: static bodies whose origin is the end seam, a block reaching away from the planks.
  const Vec3 post(Real(0.1), s.plankHalfExtents.y() * 4, s.plankHalfExtents.z());
  for (int side = 0; side < 2; ++side) {
    const Real away = side == 0 ? -1 : 1;
    BodyDesc d;
    d.settings.type = BodyType::Static;
    d.settings.position = s.center + seams[side == 0 ? 0 : std::size_t(n)];
    d.settings.name = s.name + (side == 0 ? "_post_left" : "_post_right");
    Transform local;
    local.p = Vec3(away * (post.x() + s.gap / 2), 0, 0);
    d.shapes.push_back({Box{post}, s.material, local});
    a.bodies.push_back(std::move(d));
  }
  const int left = n, right = n + 1;
  for (int k = 0; k <= n; ++k) {
    const int bodyA = k == 0 ? left : k - 1;
    const int bodyB = k == n ? right : k;
    const Vec3 seam = s.center + seams[std::size_t(k)];
    const std::string name = s.name + "_seam_" + std::to_string(k);
    if (s.joint == JointType::Hinge) {
      a.joints.push_back(hingeAt(a, bodyA, bodyB, seam, Vec3::UnitZ(), {}, 0, s.breakForce));
      std::get<HingeJointSettings>(a.joints.back().settings).name = name;
    } else {
      for (Real side : {Real(-1), Real(1)}) {
        a.joints.push_back(ballAt(a, bodyA, bodyB, seam + Vec3(0, 0, side * s.plankHalfExtents.z()),
                                  0, s.breakForce));
        std::get<BallJointSettings>(a.joints.back().settings).name =
            name + (side < 0 ? "_back" : "_front");
      }
    }
  }
  return a;
}

RopeBridge addRopeBridge(World& world, const RopeBridgeSettings& settings) {
  AssemblyIds ids = addAssembly(world, ropeBridge(settings));
  RopeBridge b;
  b.planks.assign(ids.bodies.begin(), ids.bodies.begin() + settings.planks);
  b.leftPost = ids.bodies[std::size_t(settings.planks)];
  b.rightPost = ids.bodies[std::size_t(settings.planks) + 1];
  b.joints = std::move(ids.joints);
  return b;
}

Assembly ragdoll(const RagdollSettings& s) {
  requirePositive(s.scale, "RagdollSettings::scale");
  require(allFinite(s.position) && allFinite(s.orientation) && s.orientation.norm() > 0 &&
              allFinite(s.linearVelocity),
          "RagdollSettings: position, orientation and linearVelocity must be finite");
  require(std::isfinite(s.jointFriction) && s.jointFriction >= 0,
          "RagdollSettings::jointFriction must be >= 0");
  const Quat q = s.orientation.normalized();
  const Real k = s.scale;
  // The figure's points (m at scale 1) relative to the pelvis's centre: standing along +y,
  // facing +z, its left at +x; each limb's capsule spans its two joints (the hand and foot
  // ends are free).
  auto at = [&](Real x, Real y) { return Vec3(s.position + q * (k * Vec3(x, y, 0))); };
  Assembly a;
  auto part = [&](const char* name, const Shape& shape, Real x, Real y) {
    BodyDesc d = shapeBody(at(x, y), q, shape, s.material, s.name + "_" + name);
    d.settings.linearVelocity = s.linearVelocity;
    a.bodies.push_back(std::move(d));
  };
  auto capsule = [&](Real radius, Real length) {  // length: end to end, along y
    return Capsule{k * radius, k * (length / 2 - radius)};
  };
  part("pelvis", Box{k * Vec3(Real(0.14), Real(0.09), Real(0.09))}, 0, 0);
  part("torso", Box{k * Vec3(Real(0.16), Real(0.22), Real(0.1))}, 0, Real(0.33));
  part("head", Sphere{k * Real(0.1)}, 0, Real(0.68));
  const Real shoulderY = Real(0.52), elbowY = Real(0.22), handY = Real(-0.08);
  const Real hipY = Real(-0.09), kneeY = Real(-0.53), soleY = Real(-0.95);
  const Real armX = Real(0.23), legX = Real(0.09);
  for (Real side : {Real(1), Real(-1)}) {  // left (+x), then right
    const std::string lr = side > 0 ? "left" : "right";
    part(("upper_arm_" + lr).c_str(), capsule(Real(0.05), shoulderY - elbowY), side * armX,
         (shoulderY + elbowY) / 2);
    part(("lower_arm_" + lr).c_str(), capsule(Real(0.045), elbowY - handY), side * armX,
         (elbowY + handY) / 2);
  }
  for (Real side : {Real(1), Real(-1)}) {
    const std::string lr = side > 0 ? "left" : "right";
    part(("upper_leg_" + lr).c_str(), capsule(Real(0.07), hipY - kneeY), side * legX,
         (hipY + kneeY) / 2);
    part(("lower_leg_" + lr).c_str(), capsule(Real(0.06), kneeY - soleY), side * legX,
         (kneeY + soleY) / 2);
  }
  auto index = [](RagdollPart p) { return int(p); };
  using P = RagdollPart;
  const Vec3 lateral = q * Vec3::UnitX();  // the figure's left: the hinges' axis
  const Real f = s.jointFriction;
  // Bending forwards turns a part's top towards +z: positive about +x. The neck, shoulders and
  // hips are ball joints with a swing cone and twist limits about the part's rest direction
  // (up for the head, down for the limbs): the head tips 0.8 rad and turns 1.2; an arm swings
  // 2.2 rad from hanging (raised sideways above the shoulder) and twists 1.2; a thigh swings
  // 1.5 rad (a high kick) and twists 0.6.
  a.joints.push_back(hingeAt(a, index(P::Pelvis), index(P::Torso), at(0, Real(0.1)), lateral,
                             JointLimits{Real(-0.3), Real(0.8)}, f));
  const Vec3 up = q * Vec3::UnitY();
  a.joints.push_back(limitedBallAt(a, index(P::Torso), index(P::Head), at(0, Real(0.565)), up,
                                   Real(0.8), {Real(-1.2), Real(1.2)}, f));
  std::vector<std::string> names = {"waist", "neck"};
  for (Real side : {Real(1), Real(-1)}) {
    const P upper = side > 0 ? P::UpperArmLeft : P::UpperArmRight;
    const P lower = side > 0 ? P::LowerArmLeft : P::LowerArmRight;
    a.joints.push_back(limitedBallAt(a, index(P::Torso), index(upper), at(side * armX, shoulderY),
                                     -up, Real(2.2), {Real(-1.2), Real(1.2)}, f));
    // The forearm flexes forwards: its lower end towards +z, negative about +x.
    a.joints.push_back(hingeAt(a, index(upper), index(lower), at(side * armX, elbowY), lateral,
                               JointLimits{Real(-2.6), 0}, f));
    const std::string lr = side > 0 ? "_left" : "_right";
    names.insert(names.end(), {"shoulder" + lr, "elbow" + lr});
  }
  for (Real side : {Real(1), Real(-1)}) {
    const P upper = side > 0 ? P::UpperLegLeft : P::UpperLegRight;
    const P lower = side > 0 ? P::LowerLegLeft : P::LowerLegRight;
    a.joints.push_back(limitedBallAt(a, index(P::Pelvis), index(upper), at(side * legX, hipY), -up,
                                     Real(1.5), {Real(-0.6), Real(0.6)}, f));
    // The shin flexes backwards: its lower end towards -z, positive about +x.
    a.joints.push_back(hingeAt(a, index(upper), index(lower), at(side * legX, kneeY), lateral,
                               JointLimits{0, Real(2.6)}, f));
    const std::string lr = side > 0 ? "_left" : "_right";
    names.insert(names.end(), {"hip" + lr, "knee" + lr});
  }
  for (std::size_t i = 0; i < a.joints.size(); ++i)
    std::visit([&](auto& j) { j.name = s.name + "_" + names[i]; }, a.joints[i].settings);
  return a;
}

Ragdoll addRagdoll(World& world, const RagdollSettings& settings) {
  AssemblyIds ids = addAssembly(world, ragdoll(settings));
  Ragdoll r;
  std::copy(ids.bodies.begin(), ids.bodies.end(), r.parts.begin());
  r.joints = std::move(ids.joints);
  return r;
}

Assembly jointGrid(const JointGridSettings& s) {
  requireCount(s.rows, "JointGridSettings::rows");
  requireCount(s.columns, "JointGridSettings::columns");
  requirePositive(s.radius, "JointGridSettings::radius");
  require(std::isfinite(s.spacing) && s.spacing > 2 * s.radius,
          "JointGridSettings::spacing must be finite and > 2 radius");
  require(s.pinned >= 0 && s.pinned <= s.columns, "JointGridSettings::pinned must be 0..columns");
  require(allFinite(s.top), "JointGridSettings::top must be finite");
  Assembly a;
  a.bodies.reserve(std::size_t(s.rows) * std::size_t(s.columns));
  const int firstPinned = (s.columns - s.pinned) / 2;
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.columns; ++c) {
      a.bodies.push_back(
          shapeBody(s.top + s.spacing * Vec3(Real(c) - Real(s.columns - 1) / 2, -Real(r), 0),
                    Quat::Identity(), Sphere{s.radius}, s.material,
                    s.name + "_" + std::to_string(r) + "_" + std::to_string(c)));
    }
  a.joints.reserve(std::size_t(s.rows) * std::size_t(s.columns) * 2 + std::size_t(s.pinned));
  for (int c = firstPinned; c < firstPinned + s.pinned; ++c)
    a.joints.push_back(ballAt(a, -1, c, a.bodies[std::size_t(c)].settings.position));
  const Real h = s.spacing / 2;
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.columns; ++c) {
      const int i = r * s.columns + c;
      if (c + 1 < s.columns)
        a.joints.push_back(
            {BallJointSettings{.anchorA = Vec3(h, 0, 0), .anchorB = Vec3(-h, 0, 0)}, i, i + 1});
      if (r + 1 < s.rows)
        a.joints.push_back({BallJointSettings{.anchorA = Vec3(0, -h, 0), .anchorB = Vec3(0, h, 0)},
                            i, i + s.columns});
    }
  return a;
}

}  // namespace inertia
