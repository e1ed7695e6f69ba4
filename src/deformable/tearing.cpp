// The tearing stage of a deformable's step: a spring stretched past the strain limit breaks
// for good and is reported (TearEvent).
#include "deformable/scratch.h"

namespace inertia {

void Deformable::tear() {
  if (settings_.tearStrain <= 0) return;
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    if (broken_[k]) continue;
    const Spring& s = springs_[k];
    const Real l =
        (Eigen::Map<const Vec3>(&x_[3 * s.a]) - Eigen::Map<const Vec3>(&x_[3 * s.b])).norm();
    const Real strain = (l - s.restLength) / s.restLength;
    if (strain > settings_.tearStrain) {
      broken_[k] = 1;
      tearEvents_.push_back({k, s.a, s.b, strain, time_});
    }
  }
}

}  // namespace inertia
