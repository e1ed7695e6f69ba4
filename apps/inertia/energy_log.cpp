#include "energy_log.h"

#include <stdexcept>

namespace inertia::app {

EnergySample measureEnergy(const World& world, std::span<const Real> gravityScale) {
  const RigidBodySystem& rb = world.rigidBodies();
  const Eigen::Vector3d g = world.settings().gravity.cast<double>();
  EnergySample s;
  s.time = world.time();
  const std::vector<BodyId> bodies = rb.bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyId b = bodies[i];
    if (rb.type(b) != BodyType::Dynamic) continue;
    const double m = double(rb.mass(b));
    const Eigen::Vector3d c = rb.centerOfMass(b).cast<double>();
    const Eigen::Vector3d v = rb.linearVelocity(b).cast<double>();
    const Eigen::Vector3d w = rb.angularVelocity(b).cast<double>();
    const Eigen::Vector3d Iw = rb.inertiaWorld(b).cast<double>() * w;
    const double scale = i < gravityScale.size() ? double(gravityScale[i]) : 1.0;
    s.kinetic += 0.5 * m * v.squaredNorm() + 0.5 * w.dot(Iw);
    s.potential -= m * scale * g.dot(c);
    s.momentum += m * v;
    s.angularMomentum += c.cross(m * v) + Iw;
  }
  s.total = s.kinetic + s.potential;
  return s;
}

EnergyLog::EnergyLog(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "w")) {
  if (!file_) throw std::runtime_error(path + ": cannot be opened for writing");
  std::fputs("time,kinetic,potential,total,px,py,pz,lx,ly,lz\n", file_);
}

EnergyLog::~EnergyLog() {
  if (file_) std::fclose(file_);
}

void EnergyLog::write(const EnergySample& s) {
  std::fprintf(file_, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", s.time,
               s.kinetic, s.potential, s.total, s.momentum.x(), s.momentum.y(), s.momentum.z(),
               s.angularMomentum.x(), s.angularMomentum.y(), s.angularMomentum.z());
}

void EnergyLog::close() {
  if (!file_) return;
  const bool failed = std::ferror(file_) != 0;
  const bool closeFailed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed || closeFailed) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace inertia::app
