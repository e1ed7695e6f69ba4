// Self-collision (Bridson, Fedkiw and Anderson 2002): a cloth dropped in a heap on the ground
// never passes through itself, checked by brute force over every vertex-triangle pair between
// steps and every edge-triangle pair at each step, with an oracle independent of the stage's
// own continuous tests.
#include <gtest/gtest.h>

#include <cmath>

#include "../sanitizer.h"
#include "crossings.h"
#include "inertia/deformable/deformable.h"
#include "inertia/deformable/generators.h"

namespace inertia {
namespace {

// A 0.5 m cloth hanging straight down, its lower edge 2 cm above the ground, released: it
// crumples into a heap on the ground. With self-collision no vertex crosses a triangle between
// any two steps and no edge pierces a triangle after any step; without it, it does pass
// through itself (so the check can fail).
TEST(DeformableSelfCollision, ClothDroppedInAHeapNeverPassesThroughItself) {
  // The run without self-collision (which shows that the heap does cross itself, so that the
  // test can fail) is left to the presets without sanitizers.
  for (bool self : {true, false}) {
    if (!self && test::kSanitized) continue;
    const int n = 10;
    MassSpringModel m =
        cloth({.pose = {Vec3(0, Real(0.27), 0),
                        Quat(Eigen::AngleAxis<Real>(Real(M_PI / 2), Vec3::UnitX()))},
               .size = {Real(0.5), Real(0.5)},
               .resolution = {n, n},
               .mass = Real(0.1),
               .stiffness = {.stretch = 2000, .shear = 200, .bend = Real(0.05)},
               .damping = Real(0.01)});
    // A little sideways wave so that it folds rather than stacks.
    m.velocities.assign(m.vertexCount(), Vec3::Zero());
    for (std::size_t i = 0; i < m.vertexCount(); ++i)
      m.velocities[i].z() = Real(0.3) * std::sin(Real(12) * m.positions[i].y());
    Deformable d({.thickness = Real(0.005), .friction = Real(0.5), .selfCollision = self}, m);
    d.addField({GravityField{}});
    d.addObstacle({Collider(Plane{Vec3::UnitY(), 0}), Transform{}});
    test::Crossings total;
    for (int step = 0; step < 90; ++step) {
      const std::vector<Eigen::Vector3d> before = test::positions(d);
      d.step(Real(1) / 60);
      const test::Crossings c = test::countCrossings(d, before, d, before);
      total.vertexTriangle += c.vertexTriangle;
      total.edgeTriangle += c.edgeTriangle;
      if (self) {
        ASSERT_EQ(c.vertexTriangle, 0) << "step " << step;
        ASSERT_EQ(c.edgeTriangle, 0) << "step " << step;
      }
    }
    // It did fall into a heap: every vertex within 5 cm of the ground.
    Real highest = 0;
    for (std::size_t i = 0; i < d.vertexCount(); ++i)
      highest = std::max(highest, d.position(i).y());
    EXPECT_LT(highest, Real(0.05)) << (self ? "self" : "none");
    if (!self) {
      EXPECT_GT(total.vertexTriangle + total.edgeTriangle, 0);
    }
  }
}

}  // namespace
}  // namespace inertia
