#include "inertia/deformable/model.h"

#include <cmath>
#include <string>

#include "inertia/core/error.h"

namespace inertia {

namespace {

std::string item(const char* what, std::size_t i) {
  return std::string("MassSpringModel::") + what + "[" + std::to_string(i) + "]";
}

void validateSpring(const Spring& s, std::size_t i, std::size_t n) {
  require(s.a < n && s.b < n, item("springs", i) + " joins a vertex that does not exist");
  require(s.a != s.b, item("springs", i) + " joins a vertex to itself");
  require(std::isfinite(s.restLength) && s.restLength > 0,
          item("springs", i) + ".restLength must be finite and > 0 (m)");
  require(std::isfinite(s.stiffness) && s.stiffness >= 0,
          item("springs", i) + ".stiffness must be finite and >= 0 (N/m)");
  require(std::isfinite(s.damping) && s.damping >= 0,
          item("springs", i) + ".damping must be finite and >= 0 (N s/m)");
}

}  // namespace

void validate(const MassSpringModel& m) {
  const std::size_t n = m.positions.size();
  require(n > 0, "MassSpringModel has no vertices");
  require(m.masses.size() == n, "MassSpringModel::masses must have one entry per vertex");
  require(m.velocities.empty() || m.velocities.size() == n,
          "MassSpringModel::velocities must be empty or have one entry per vertex");
  for (std::size_t i = 0; i < n; ++i) {
    require(m.positions[i].allFinite(), item("positions", i) + " must be finite");
    require(std::isfinite(m.masses[i]) && m.masses[i] > 0,
            item("masses", i) + " must be finite and > 0 (kg)");
    if (!m.velocities.empty())
      require(m.velocities[i].allFinite(), item("velocities", i) + " must be finite");
  }
  for (std::size_t i = 0; i < m.springs.size(); ++i) validateSpring(m.springs[i], i, n);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (std::uint32_t v : m.triangles[i])
      require(v < n, item("triangles", i) + " names a vertex that does not exist");
  for (std::size_t i = 0; i < m.pinned.size(); ++i)
    require(m.pinned[i] < n, item("pinned", i) + " names a vertex that does not exist");
}

}  // namespace inertia
