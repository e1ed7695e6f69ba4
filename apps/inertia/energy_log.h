// `inertia run --energy`: energy and momenta of the rigid bodies per step, as CSV.
#pragma once

#include <Eigen/Core>
#include <cstdio>
#include <span>
#include <string>

#include "inertia/world/world.h"

namespace inertia::app {

/// Energies (J) and momenta of the dynamic rigid bodies at one instant, summed in double.
struct EnergySample {
  double time = 0;       ///< s
  double kinetic = 0;    ///< Linear plus rotational: sum 1/2 m v.v + 1/2 w.(I w).
  double potential = 0;  ///< Gravity: sum -m s (g . c), zero for a centre of mass at the origin
                         ///< (for g = (0, -g, 0): m g y, relative to y = 0); s = gravity scale.
  double total = 0;      ///< kinetic + potential
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();  ///< sum m v (kg m/s)
  Eigen::Vector3d angularMomentum =
      Eigen::Vector3d::Zero();  ///< About the origin: sum c x m v + I w
};

/// Measures the world's dynamic bodies; `gravityScale[i]` is that of the i-th body in
/// RigidBodySystem::bodies() order (1 when missing).
EnergySample measureEnergy(const World& world, std::span<const Real> gravityScale);

/// The CSV file: header `time,kinetic,potential,total,px,py,pz,lx,ly,lz`, a row per sample,
/// %.17g. Throws std::runtime_error when the file cannot be written.
class EnergyLog {
 public:
  explicit EnergyLog(const std::string& path);
  ~EnergyLog();
  EnergyLog(const EnergyLog&) = delete;
  EnergyLog& operator=(const EnergyLog&) = delete;
  void write(const EnergySample& s);
  void close();

 private:
  std::string path_{};
  std::FILE* file_ = nullptr;
};

}  // namespace inertia::app
