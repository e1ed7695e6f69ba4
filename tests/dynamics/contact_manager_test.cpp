// The contact manager (src/dynamics/contact_manager.cpp: the broad phase over
// collision::BroadPhase, its kept pairs, the planes' pairs, the narrow phase) against brute
// force: after every step of spheres in a walled box, while spheres are added, removed and
// teleported (proxies created and destroyed, the kept pairs dropped and found again), the
// step's contacts are exactly the shape pairs that collide() finds within the speculative
// distance at the step's start poses, each once, in shape order, on one thread and on two.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>
#include <vector>

#include "../step_constants.h"
#include "inertia/collision/contact.h"
#include "inertia/world/world.h"

using namespace inertia;
using inertia::test::kDt;

namespace {

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

constexpr Real kRadius = Real(0.3);

struct ShapeAt {
  ShapeId shape;
  BodyId body;
  BodyType type;
  Transform pose;
  Vec3 v, w;    // the body's velocities (m/s, rad/s)
  Real extent;  // farthest point of the body's bounds from its centre (m)
  bool fast;    // continuous this step (ContactTuning::bulletFraction)
};

// Every shape with its body's pose and motion now. A sphere's bounds reach r sqrt(3) from its
// centre (the corner of its box), and its smallest half size is r.
std::vector<ShapeAt> shapesNow(const RigidBodySystem& rb, const ContactTuning& tuning) {
  std::vector<ShapeAt> out;
  for (BodyId b : rb.bodies()) {
    const bool dynamic = rb.type(b) == BodyType::Dynamic;
    const Vec3 v = rb.linearVelocity(b), w = rb.angularVelocity(b);
    const Real extent = dynamic ? Vec3::Constant(kRadius).norm() : 0;
    const bool fast =
        dynamic && (v.norm() + w.norm() * extent) * kDt > tuning.bulletFraction * kRadius;
    for (ShapeId s : rb.shapes(b))
      out.push_back({s, b, rb.type(b), rb.shapeTransform(s), v, w, extent, fast});
  }
  return out;
}

// The oracle: pairs of shapes of different bodies, not both static, whose collide() at `at`
// gives a manifold within the speculative distance, widened by the pair's motion bound when
// one body is fast (ContactTuning::speculativeDistance, bulletFraction).
PairSet bruteForce(const RigidBodySystem& rb, const std::vector<ShapeAt>& at, Real margin) {
  PairSet out;
  for (std::size_t i = 0; i < at.size(); ++i)
    for (std::size_t j = i + 1; j < at.size(); ++j) {
      if (at[i].body == at[j].body) continue;
      if (at[i].type == BodyType::Static && at[j].type == BodyType::Static) continue;
      ContactSettings cs{.speculativeDistance = margin};
      const ShapeAt &a = at[i], &b = at[j];
      if (a.fast || b.fast)
        cs.speculativeDistance +=
            ((b.v - a.v).norm() + a.w.norm() * a.extent + b.w.norm() * b.extent) * kDt;
      ContactManifold m;
      if (!collideConvex(rb.collider(at[i].shape), at[i].pose, rb.collider(at[j].shape), at[j].pose,
                         cs, m) ||
          m.pointCount == 0)
        continue;
      out.insert(std::minmax(at[i].shape.index, at[j].shape.index));
    }
  return out;
}

void run(int threads) {
  World world({.threads = threads, .sleeping = false});
  const BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{Vec3::UnitY(), 0});
  for (int side = 0; side < 4; ++side) {
    const Real s = side % 2 ? Real(1) : Real(-1);
    const Vec3 at = side < 2 ? Vec3(s * 3, 1, 0) : Vec3(0, 1, s * 3);
    const Vec3 half = side < 2 ? Vec3(Real(0.2), 1, 3) : Vec3(3, 1, Real(0.2));
    const BodyId wall = world.createBody({.type = BodyType::Static, .position = at});
    world.addShape(wall, Box{half});
  }
  std::mt19937 rng(17);
  std::uniform_real_distribution<Real> across(Real(-2.5), Real(2.5)), up(Real(0.5), Real(2));
  std::vector<BodyId> spheres;
  // z, y, x: the order GCC drew Vec3(across(rng), up(rng), across(rng)) in (tests/draws.h).
  auto position = [&] {
    const Real z = across(rng), y = up(rng), x = across(rng);
    return Vec3(x, y, z);
  };
  auto add = [&] {
    const BodyId b = world.createBody({.position = position()});
    world.addShape(b, Sphere{kRadius});
    spheres.push_back(b);
  };
  for (int i = 0; i < 80; ++i) add();
  const Real margin = world.settings().contact.speculativeDistance;
  std::size_t checked = 0;
  for (int step = 0; step < 150; ++step) {
    if (step % 10 == 3) {  // remove one
      const std::size_t k = rng() % spheres.size();
      world.destroyBody(spheres[k]);
      spheres.erase(spheres.begin() + std::ptrdiff_t(k));
    }
    if (step % 7 == 2) add();
    if (step % 5 == 4) {  // teleport one into the crowd
      const BodyId b = spheres[rng() % spheres.size()];
      world.rigidBodies().setTransform(
          b, Transform{position(), Quat::Identity()});
    }
    const RigidBodySystem& rb = world.rigidBodies();
    const PairSet expected = bruteForce(rb, shapesNow(rb, world.settings().contact), margin);
    world.step(kDt);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const ContactInfo& c : rb.contacts()) found.emplace_back(c.shapeA.index, c.shapeB.index);
    ASSERT_TRUE(std::is_sorted(found.begin(), found.end())) << "step " << step;
    ASSERT_EQ(PairSet(found.begin(), found.end()).size(), found.size()) << "step " << step;
    const PairSet got(found.begin(), found.end());
    for (auto p : got)
      if (!expected.count(p)) std::printf("extra %u %u\n", p.first, p.second);
    for (auto p : expected)
      if (!got.count(p)) std::printf("missing %u %u\n", p.first, p.second);
    ASSERT_EQ(PairSet(found.begin(), found.end()), expected)
        << "step " << step << ", " << threads << " threads";
    checked += expected.size();
  }
  EXPECT_GT(checked, 150u * 80u);  // the spheres touch: about one contact per sphere or more
}

}  // namespace

TEST(ContactManager, ContactsAreTheCollidingPairsOnOneThread) { run(1); }
TEST(ContactManager, ContactsAreTheCollidingPairsOnTwoThreads) { run(2); }
