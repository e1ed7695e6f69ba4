// The attachment stage of a deformable's step: each attachment's reaction on its body, and its
// point moved on to the step's end. With the implicit step the vertex's momentum changed by
// exactly h F(x1, v1) through the attachment (backward Euler), so the body gets -h F(x1, v1)
// and the pair's momentum is conserved to the solver's tolerance; with the explicit methods
// the same end-of-step force stands in for the step's average.
#include "deformable/scratch.h"

namespace inertia {

void Deformable::moveAttachments(Real h) {
  for (std::size_t k = 0; k < attachments_.size(); ++k) {
    const Attachment& a = attachments_[k];
    Vec3& p = attachmentPositions_[k];
    p += h * attachmentVelocities_[k];
    if (pinned_[a.vertex]) {
      attachmentImpulses_[k].setZero();
      continue;
    }
    const Vec3 x = Eigen::Map<const Vec3>(&x_[3 * a.vertex]);
    const Vec3 v = Eigen::Map<const Vec3>(&v_[3 * a.vertex]);
    attachmentImpulses_[k] =
        h * (a.stiffness * (x - p) + a.damping * (v - attachmentVelocities_[k]));
  }
}

}  // namespace inertia
