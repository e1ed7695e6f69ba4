// Seeded random trees, pendulum chains and a 7-DOF arm, shared by tests and benchmarks.
#include "inertia/articulation/builders.h"

#include <cmath>
#include <numbers>
#include <random>

#include "inertia/core/error.h"

namespace inertia::articulation {

namespace {

template <class S>
S uniform(std::mt19937& rng, double lo, double hi) {
  return S(std::uniform_real_distribution<double>(lo, hi)(rng));
}

template <class S>
Vector3<S> uniformVector(std::mt19937& rng, double lo, double hi) {
  return {uniform<S>(rng, lo, hi), uniform<S>(rng, lo, hi), uniform<S>(rng, lo, hi)};
}

// A uniformly random rotation (Shoemake's method from three uniforms).
template <class S>
Quaternion<S> uniformRotation(std::mt19937& rng) {
  const double u1 = uniform<double>(rng, 0, 1), u2 = uniform<double>(rng, 0, 1),
               u3 = uniform<double>(rng, 0, 1);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1), t = 2 * std::numbers::pi;
  return Quaternion<S>(S(b * std::cos(t * u3)), S(a * std::sin(t * u2)), S(a * std::cos(t * u2)),
                       S(b * std::sin(t * u3)));
}

}  // namespace

template <class S>
Model<S> randomTree(const RandomTreeOptions& options) {
  require(options.links >= 1, "articulation: randomTree needs at least one link");
  std::mt19937 rng(options.seed);
  Model<S> model;
  constexpr JointType kCycle[] = {JointType::Revolute, JointType::Prismatic, JointType::Spherical,
                                  JointType::Fixed};
  for (int i = 0; i < options.links; ++i) {
    LinkSettings<S> s;
    s.name = "link" + std::to_string(i);
    s.parent = i == 0 ? -1 : std::uniform_int_distribution<int>(0, i - 1)(rng);
    s.joint.type = i == 0 ? (options.floatingBase ? JointType::Floating : JointType::Revolute)
                          : kCycle[(i - 1) % 4];
    s.joint.originPosition = uniformVector<S>(rng, -0.5, 0.5);
    s.joint.originOrientation = uniformRotation<S>(rng);
    s.joint.axis = uniformVector<S>(rng, -1, 1);
    if (options.armature && s.joint.type != JointType::Floating && i % 3 == 0)
      s.joint.armature = uniform<S>(rng, 0, 0.1);
    const S m = uniform<S>(rng, 0.5, 2);
    const Vector3<S> e = uniformVector<S>(rng, 0.05, 0.4);  // box half extents
    const Vector3<S> principal(m / 3 * (e.y() * e.y() + e.z() * e.z()),
                               m / 3 * (e.x() * e.x() + e.z() * e.z()),
                               m / 3 * (e.x() * e.x() + e.y() * e.y()));
    const Matrix3<S> R = uniformRotation<S>(rng).toRotationMatrix();
    s.inertia = {m, uniformVector<S>(rng, -0.3, 0.3), R * principal.asDiagonal() * R.transpose()};
    model.addLink(s);
  }
  return model;
}

template <class S>
void randomState(const Model<S>& model, std::uint32_t seed, VectorX<S>& q, VectorX<S>& qd) {
  std::mt19937 rng(seed);
  q = model.neutralConfiguration();
  for (const Link<S>& l : model.links()) {
    const int i = l.qIndex;
    switch (l.joint) {
      case JointType::Revolute:
      case JointType::Prismatic:
        q(i) = uniform<S>(rng, -1, 1);
        break;
      case JointType::Spherical: {
        const Quaternion<S> r = uniformRotation<S>(rng);
        q.template segment<4>(i) << r.w(), r.x(), r.y(), r.z();
        break;
      }
      case JointType::Floating: {
        q.template segment<3>(i) = uniformVector<S>(rng, -1, 1);
        const Quaternion<S> r = uniformRotation<S>(rng);
        q.template segment<4>(i + 3) << r.w(), r.x(), r.y(), r.z();
        break;
      }
      case JointType::Fixed:
        break;
    }
  }
  qd.resize(model.nv());
  for (int k = 0; k < model.nv(); ++k) qd(k) = uniform<S>(rng, -1, 1);
}

template <class S>
Model<S> pendulumChain(int links, S length, S mass) {
  require(links >= 1, "articulation: pendulumChain needs at least one link");
  Model<S> model;
  for (int i = 0; i < links; ++i) {
    LinkSettings<S> s;
    s.name = "link" + std::to_string(i);
    s.parent = i - 1;
    s.joint.axis = Vector3<S>::UnitZ();
    s.joint.originPosition = i == 0 ? Vector3<S>::Zero() : Vector3<S>(S(0), -length, S(0));
    s.inertia = {mass, Vector3<S>(S(0), -length, S(0)), Matrix3<S>::Identity() * S(1e-6) * mass};
    model.addLink(s);
  }
  return model;
}

template <class S>
Model<S> sevenDofArm() {
  // Modified Denavit-Hartenberg parameters of the Franka Emika Panda (a, d, alpha per joint);
  // joint i's frame is RotX(alpha) TransX(a) TransZ(d) from its parent's.
  constexpr double kA[] = {0, 0, 0, 0.0825, -0.0825, 0, 0.088};
  constexpr double kD[] = {0.333, 0, 0.316, 0, 0.384, 0, 0};
  constexpr double h = std::numbers::pi / 2;
  constexpr double kAlpha[] = {0, -h, h, h, -h, h, h};
  constexpr double kMass[] = {4.97, 0.65, 3.23, 3.59, 1.23, 1.67, 0.74};  // approximate (kg)
  constexpr double kLower[] = {-2.90, -1.76, -2.90, -3.07, -2.90, -0.02, -2.90};
  constexpr double kUpper[] = {2.90, 1.76, 2.90, -0.07, 2.90, 3.75, 2.90};
  Model<S> model;
  for (int i = 0; i < 7; ++i) {
    LinkSettings<S> s;
    s.name = "panda_link" + std::to_string(i + 1);
    s.parent = i - 1;
    s.joint.originPosition =
        Vector3<S>(S(kA[i]), S(-kD[i] * std::sin(kAlpha[i])), S(kD[i] * std::cos(kAlpha[i])));
    s.joint.originOrientation =
        Quaternion<S>(Eigen::AngleAxis<S>(S(kAlpha[i]), Vector3<S>::UnitX()));
    s.joint.lower = S(kLower[i]);
    s.joint.upper = S(kUpper[i]);
    // A solid cylinder of radius 6 cm and length 20 cm along z, centred 5 cm along -z.
    const S m = S(kMass[i]), r = S(0.06), l = S(0.2);
    const S side = m * (3 * r * r + l * l) / 12, axial = m * r * r / 2;
    s.inertia = {m, Vector3<S>(S(0), S(0), S(-0.05)), Vector3<S>(side, side, axial).asDiagonal()};
    model.addLink(s);
  }
  return model;
}

template <class S>
Model<S> humanoid() {
  Model<S> model;
  // A link on one revolute joint about `axis` at `origin` (in the parent's frame), its mass that
  // of a box of half extents `half` centred at `com`.
  const auto add = [&](const std::string& name, int parent, const Vector3<S>& origin,
                       const Vector3<S>& axis, S mass, const Vector3<S>& com,
                       const Vector3<S>& half, JointType type = JointType::Revolute) {
    LinkSettings<S> s;
    s.name = name;
    s.parent = parent;
    s.joint.type = type;
    s.joint.originPosition = origin;
    s.joint.axis = axis;
    const Vector3<S> h2 = half.cwiseProduct(half);
    s.inertia = {mass, com,
                 (mass / 3 * Vector3<S>(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y()))
                     .asDiagonal()};
    model.addLink(s);
    return model.linkCount() - 1;
  };
  using V = Vector3<S>;
  const V x = V::UnitX(), y = V::UnitY(), z = V::UnitZ(), o = V::Zero();
  const V small = V::Constant(S(0.03));  // the links between the axes of a multi-axis joint
  const int pelvis = add("pelvis", -1, o, z, 10, o, V(S(0.15), S(0.1), S(0.1)), JointType::Floating);
  const int abdomen = add("abdomen", pelvis, V(0, S(0.1), 0), z, S(0.5), o, small);
  const int chest = add("chest", abdomen, o, x, 12, V(0, S(0.2), 0), V(S(0.15), S(0.2), S(0.1)));
  const int neck = add("neck", chest, V(0, S(0.45), 0), x, S(0.3), o, small);
  add("head", neck, o, y, 4, V(0, S(0.1), 0), V::Constant(S(0.1)));
  for (const S side : {S(1), S(-1)}) {
    const std::string n = side > 0 ? "left_" : "right_";
    const int sz = add(n + "shoulder_z", chest, V(side * S(0.2), S(0.4), 0), z, S(0.2), o, small);
    const int sx = add(n + "shoulder_x", sz, o, x, S(0.2), o, small);
    const int upper =
        add(n + "upper_arm", sx, o, y, 2, V(0, S(-0.15), 0), V(S(0.04), S(0.15), S(0.04)));
    add(n + "forearm", upper, V(0, S(-0.3), 0), x, S(1.2), V(0, S(-0.13), 0),
        V(S(0.035), S(0.13), S(0.035)));
    const int hz = add(n + "hip_z", pelvis, V(side * S(0.1), S(-0.1), 0), z, S(0.3), o, small);
    const int hx = add(n + "hip_x", hz, o, x, S(0.3), o, small);
    const int thigh =
        add(n + "thigh", hx, o, y, 6, V(0, S(-0.22), 0), V(S(0.07), S(0.22), S(0.07)));
    const int shin = add(n + "shin", thigh, V(0, S(-0.45), 0), x, S(3.5), V(0, S(-0.2), 0),
                         V(S(0.05), S(0.2), S(0.05)));
    const int ankle = add(n + "ankle_x", shin, V(0, S(-0.42), 0), x, S(0.2), o, small);
    add(n + "foot", ankle, o, z, 1, V(0, S(-0.04), S(0.05)), V(S(0.05), S(0.03), S(0.1)));
  }
  return model;
}

#define INERTIA_INSTANTIATE(S)                                                            \
  template Model<S> randomTree<S>(const RandomTreeOptions&);                              \
  template void randomState<S>(const Model<S>&, std::uint32_t, VectorX<S>&, VectorX<S>&); \
  template Model<S> pendulumChain<S>(int, S, S);                                          \
  template Model<S> sevenDofArm<S>();                                                     \
  template Model<S> humanoid<S>();
INERTIA_INSTANTIATE(float)
INERTIA_INSTANTIATE(double)
#undef INERTIA_INSTANTIATE

}  // namespace inertia::articulation
