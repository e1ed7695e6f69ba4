#include "inertia/world/builders.h"

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

}  // namespace

BodyId addBody(World& world, const BodyDesc& desc) {
  const BodyId id = world.createBody(desc.settings);
  for (const ShapeDesc& s : desc.shapes) world.addShape(id, s.shape, s.material, s.local);
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
                            "pyramid_" + std::to_string(row) + "_" + std::to_string(i)));
    }
  }
  return out;
}

std::vector<BodyDesc> tower(const TowerSettings& s) {
  requireCount(s.height, "TowerSettings::height");
  std::vector<BodyDesc> out;
  for (int i = 0; i < s.height; ++i)
    out.push_back(boxBody(s.origin + Vec3(0, s.halfExtents.y() * Real(2 * i + 1), 0),
                          s.halfExtents, s.material, "tower_" + std::to_string(i)));
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
                            "wall_" + std::to_string(r) + "_" + std::to_string(c)));
    }
  }
  return out;
}

std::vector<BodyDesc> grid(const GridSettings& s) {
  for (int k = 0; k < 3; ++k) requireCount(s.counts[std::size_t(k)], "GridSettings::counts");
  require(allFinite(s.spacing) && allFinite(s.origin), "GridSettings: spacing and origin must be finite");
  std::vector<BodyDesc> out;
  for (int y = 0; y < s.counts[1]; ++y)
    for (int z = 0; z < s.counts[2]; ++z)
      for (int x = 0; x < s.counts[0]; ++x) {
        BodyDesc d;
        d.settings.position = s.origin + Vec3(Real(x) * s.spacing.x(), Real(y) * s.spacing.y(),
                                              Real(z) * s.spacing.z());
        d.settings.name = "grid_" + std::to_string(out.size());
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
    d.settings.name = "rain_" + std::to_string(i);
    d.shapes.push_back({s.shape, s.material, {}});
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace inertia
