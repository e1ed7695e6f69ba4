// Shared helpers for the geometry tests: random poses, surface samples, Monte-Carlo integrals.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/geometry/geometry.h"
#include "../draws.h"

namespace inertia::test {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;
constexpr double kPi = std::numbers::pi;
/// Machine epsilon of Real: float-build tolerances scale with it.
constexpr double kEps = std::numeric_limits<Real>::epsilon();

inline Vec3d randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return draw3<Vec3d>([&] { return n(rng); }).normalized();
}

/// Points on a surface, and the sampling resolution: every surface point lies within
/// `spacing` (m) of some sample. Since x -> d . x is 1-Lipschitz for unit d, the maximum over
/// the samples is within `spacing` of the maximum over the surface.
struct SurfaceSamples {
  std::vector<Vec3d> points;
  double spacing = 0;
};

// A latitude-longitude grid on the unit sphere, n steps in latitude and 2n in longitude.
// Neighbouring grid points are at most pi/n apart on the sphere (along a meridian or a
// parallel), so every point is within pi/n of a sample.
inline std::vector<Vec3d> unitSphereGrid(int n) {
  std::vector<Vec3d> out;
  for (int i = 0; i <= n; ++i) {
    const double theta = kPi * i / n;
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = kPi * j / n;
      out.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta),
                       std::sin(theta) * std::sin(phi));
    }
  }
  return out;
}

inline SurfaceSamples samples(const Sphere& s, int n = 90) {
  SurfaceSamples out;
  for (const Vec3d& u : unitSphereGrid(n)) out.points.push_back(s.radius * u);
  out.spacing = s.radius * kPi / n;
  return out;
}

inline SurfaceSamples samples(const Capsule& c, int n = 90) {
  SurfaceSamples out;
  const double r = c.radius, h = c.halfHeight;
  for (const Vec3d& u : unitSphereGrid(n)) {
    if (u.y() >= 0) out.points.push_back(r * u + Vec3d(0, h, 0));
    if (u.y() <= 0) out.points.push_back(r * u - Vec3d(0, h, 0));
  }
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double y = -h + 2 * h * i / n, phi = kPi * j / n;
      out.points.emplace_back(r * std::cos(phi), y, r * std::sin(phi));
    }
  out.spacing = r * kPi / n + 2 * h / n;
  return out;
}

inline SurfaceSamples samples(const Cylinder& c, int n = 90) {
  SurfaceSamples out;
  const double r = c.radius, h = c.halfHeight;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = kPi * j / n, rho = r * i / n, y = -h + 2 * h * i / n;
      out.points.emplace_back(rho * std::cos(phi), h, rho * std::sin(phi));
      out.points.emplace_back(rho * std::cos(phi), -h, rho * std::sin(phi));
      out.points.emplace_back(r * std::cos(phi), y, r * std::sin(phi));
    }
  // Rim arcs are pi r / n long; radial and axial steps are r / n and 2h / n.
  out.spacing = r * kPi / n + r / n + 2 * h / n;
  return out;
}

inline SurfaceSamples samples(const Box& b, int n = 40) {
  SurfaceSamples out;
  const Vec3d h = b.halfExtents.cast<double>();
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2)
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3d x;
          const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
          x[axis] = sign * h[axis];
          x[a1] = -h[a1] + 2 * h[a1] * i / n;
          x[a2] = -h[a2] + 2 * h[a2] * j / n;
          out.points.push_back(x);
        }
  out.spacing = 2 * h.norm() / n;
  return out;
}

// Vertices plus points spread over each face (fan triangles at barycentric grid points).
inline SurfaceSamples samples(const ConvexHull& hull, int n = 6) {
  SurfaceSamples out;
  for (const Vec3& v : hull.vertices()) out.points.push_back(v.cast<double>());
  double longest = 0;
  for (std::size_t f = 0; f < hull.faces().size(); ++f) {
    const auto loop = hull.faceEdges(f);
    const Vec3d a = hull.vertices()[loop[0].origin].cast<double>();
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      const Vec3d b = hull.vertices()[loop[k].origin].cast<double>();
      const Vec3d c = hull.vertices()[loop[k + 1].origin].cast<double>();
      longest = std::max({longest, (b - a).norm(), (c - b).norm(), (a - c).norm()});
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
          out.points.push_back(a + (b - a) * i / n + (c - a) * j / n);
    }
  }
  out.spacing = longest / n;
  return out;
}

/// A Monte-Carlo estimate of the integrals of 1, x and x x^T over a solid, from N uniform
/// samples in a box: each estimate is V_box * mean(f * inside) with standard error
/// V_box * stddev(f * inside) / sqrt(N).
struct MonteCarlo {
  double volume = 0, volumeSigma = 0;
  Vec3d first = Vec3d::Zero(), firstSigma = Vec3d::Zero();
  Mat3d inertia = Mat3d::Zero(), inertiaSigma = Mat3d::Zero();  // unit density, about origin
};

inline MonteCarlo monteCarlo(const std::function<bool(const Vec3d&)>& inside, const Vec3d& lo,
                             const Vec3d& hi, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double boxVolume = (hi - lo).prod();
  // Running sums of f and f^2 for the 1 + 3 + 9 integrands.
  double s0 = 0, q0 = 0;
  Vec3d s1 = Vec3d::Zero(), q1 = Vec3d::Zero();
  Mat3d s2 = Mat3d::Zero(), q2 = Mat3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Vec3d x = lo + (hi - lo).cwiseProduct(draw3<Vec3d>([&] { return u(rng); }));
    if (!inside(x)) continue;
    s0 += 1;
    q0 += 1;
    s1 += x;
    q1 += x.cwiseProduct(x);
    const Mat3d j = x.squaredNorm() * Mat3d::Identity() - x * x.transpose();
    s2 += j;
    q2 += j.cwiseProduct(j);
  }
  auto sigma = [&](double s, double q) {
    const double mean = s / n, var = q / n - mean * mean;
    return boxVolume * std::sqrt(std::max(var, 0.0) / n);
  };
  MonteCarlo out;
  out.volume = boxVolume * s0 / n;
  out.volumeSigma = sigma(s0, q0);
  out.first = boxVolume * s1 / n;
  out.inertia = boxVolume * s2 / n;
  for (int k = 0; k < 3; ++k) out.firstSigma[k] = sigma(s1[k], q1[k]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.inertiaSigma(r, c) = sigma(s2(r, c), q2(r, c));
  return out;
}

/// Inertia about the origin from mass properties: I_com shifted by the parallel-axis theorem.
inline Mat3d inertiaAboutOrigin(const MassProperties& p) {
  const Vec3d c = p.centerOfMass.cast<double>();
  return p.inertia.cast<double>() +
         double(p.mass) * (c.squaredNorm() * Mat3d::Identity() - c * c.transpose());
}

/// Largest |a_ij - b_ij| relative to the largest |b_ij|.
inline double relativeError(const Mat3d& a, const Mat3d& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace inertia::test
