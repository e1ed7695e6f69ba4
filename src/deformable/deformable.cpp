#include "inertia/deformable/deformable.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/thread_pool_impl.h"
#include "deformable/scratch.h"
#include "inertia/core/error.h"

namespace inertia {

namespace {
// Vertex i's three components of a structure-of-arrays buffer.
Eigen::Map<Vec3> vertex(std::vector<Real>& a, std::size_t i) { return Eigen::Map<Vec3>(&a[3 * i]); }
}  // namespace

void validate(const DeformableSettings& s) {
  require(s.integrator == ode::Method::BackwardEuler || !ode::methodName(s.integrator).empty(),
          "DeformableSettings::integrator is not a method");
  require(std::isfinite(s.thickness) && s.thickness > 0,
          "DeformableSettings::thickness must be finite and > 0 (m)");
  require(std::isfinite(s.friction) && s.friction >= 0,
          "DeformableSettings::friction must be finite and >= 0");
  require(std::isfinite(s.tearStrain) && s.tearStrain >= 0,
          "DeformableSettings::tearStrain must be finite and >= 0 (0: never tears)");
  require(std::isfinite(s.solverTolerance) && s.solverTolerance > 0 && s.solverTolerance < 1,
          "DeformableSettings::solverTolerance must be in (0, 1)");
  require(s.solverMaxIterations >= 1, "DeformableSettings::solverMaxIterations must be >= 1");
  require(s.newtonMaxIterations >= 1, "DeformableSettings::newtonMaxIterations must be >= 1");
}

Deformable::Deformable(const DeformableSettings& settings, const MassSpringModel& model)
    : settings_(settings), scratch_(std::make_unique<Scratch>()) {
  validate(settings_);
  validate(model);
  const std::size_t n = model.vertexCount();
  x_.resize(3 * n);
  v_.assign(3 * n, Real(0));
  for (std::size_t i = 0; i < n; ++i) {
    vertex(x_, i) = model.positions[i];
    if (!model.velocities.empty()) vertex(v_, i) = model.velocities[i];
  }
  masses_ = model.masses;
  pinned_.assign(n, 0);
  for (std::uint32_t i : model.pinned) setPinned(i, true);
  springs_ = model.springs;
  broken_.assign(springs_.size(), 0);
  triangles_ = model.triangles;
  for (const auto& t : triangles_)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      edges_.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
}

Deformable::~Deformable() = default;
Deformable::Deformable(Deformable&&) noexcept = default;
Deformable& Deformable::operator=(Deformable&&) noexcept = default;

// Every member (a new one must be added here).
Deformable::Deformable(const Deformable& other)
    : settings_(other.settings_),
      x_(other.x_),
      v_(other.v_),
      masses_(other.masses_),
      pinned_(other.pinned_),
      springs_(other.springs_),
      broken_(other.broken_),
      triangles_(other.triangles_),
      fields_(other.fields_),
      obstacles_(other.obstacles_),
      moving_(other.moving_),
      tearEvents_(other.tearEvents_),
      scratch_(std::make_unique<Scratch>(*other.scratch_)),
      lastSolve_(other.lastSolve_),
      time_(other.time_) {}

Deformable& Deformable::operator=(const Deformable& other) {
  if (this != &other) *this = Deformable(other);
  return *this;
}

namespace {
// The message is built only on failure: position() and velocity() are called per vertex.
void checkVertex(std::size_t vertex, std::size_t n, const char* who) {
  if (vertex < n) return;
  require(false, std::string("Deformable::") + who + ": vertex " + std::to_string(vertex) +
                     " does not exist (" + std::to_string(n) + " vertices)");
}
}  // namespace

Vec3 Deformable::position(std::size_t i) const {
  checkVertex(i, vertexCount(), "position");
  return Eigen::Map<const Vec3>(&x_[3 * i]);
}

Vec3 Deformable::velocity(std::size_t i) const {
  checkVertex(i, vertexCount(), "velocity");
  return Eigen::Map<const Vec3>(&v_[3 * i]);
}

void Deformable::setPosition(std::size_t i, const Vec3& x) {
  checkVertex(i, vertexCount(), "setPosition");
  require(x.allFinite(), "Deformable::setPosition: the position must be finite");
  vertex(x_, i) = x;
}

void Deformable::setVelocity(std::size_t i, const Vec3& v) {
  checkVertex(i, vertexCount(), "setVelocity");
  require(v.allFinite(), "Deformable::setVelocity: the velocity must be finite");
  if (!pinned_[i]) vertex(v_, i) = v;
}

bool Deformable::isPinned(std::size_t i) const {
  checkVertex(i, vertexCount(), "isPinned");
  return pinned_[i] != 0;
}

void Deformable::setPinned(std::size_t i, bool pinned) {
  checkVertex(i, vertexCount(), "setPinned");
  pinned_[i] = pinned ? 1 : 0;
  if (pinned) vertex(v_, i).setZero();
}

std::size_t Deformable::brokenCount() const {
  std::size_t count = 0;
  for (std::uint8_t b : broken_) count += b;
  return count;
}

std::size_t Deformable::addField(const ForceField& field) {
  validate(field);
  fields_.push_back(field);
  return fields_.size() - 1;
}

std::size_t Deformable::addObstacle(const Obstacle& obstacle) {
  require(obstacle.pose.p.allFinite() && obstacle.pose.q.coeffs().allFinite() &&
              std::fabs(obstacle.pose.q.norm() - 1) < Real(1e-3),
          "Deformable::addObstacle: the pose must be finite with a unit quaternion");
  obstacles_.push_back(obstacle);
  obstacles_.back().pose.q.normalize();
  auto& bounds = scratch_->obstacleBounds;
  bounds.insert(bounds.begin() + std::ptrdiff_t(obstacles_.size() - 1),
                worldBounds(obstacle.collider.shape(), obstacles_.back().pose));
  return obstacles_.size() - 1;
}

void Deformable::setMovingObstacles(std::span<const MovingObstacle> obstacles) {
  for (const MovingObstacle& o : obstacles)
    require(o.collider && o.pose.p.allFinite() && o.pose.q.coeffs().allFinite() &&
                o.linearVelocity.allFinite() && o.angularVelocity.allFinite() &&
                o.center.allFinite(),
            "Deformable::setMovingObstacles: an obstacle needs a collider and finite pose and "
            "velocities");
  moving_.assign(obstacles.begin(), obstacles.end());
  // Their bounds follow the static obstacles' in obstacleBounds.
  auto& bounds = scratch_->obstacleBounds;
  bounds.resize(obstacles_.size());
  for (const MovingObstacle& o : moving_)
    bounds.push_back(worldBounds(o.collider->shape(), o.pose));
}

std::size_t Deformable::addAttachment(const Attachment& a) {
  checkVertex(a.vertex, vertexCount(), "addAttachment");
  require(a.anchor.allFinite(), "Deformable::addAttachment: the anchor must be finite (m)");
  require(std::isfinite(a.stiffness) && a.stiffness > 0,
          "Deformable::addAttachment: stiffness must be finite and > 0 (N/m)");
  require(std::isfinite(a.damping) && a.damping >= 0,
          "Deformable::addAttachment: damping must be finite and >= 0 (N s/m)");
  attachments_.push_back(a);
  attachmentPositions_.push_back(position(a.vertex));
  attachmentVelocities_.push_back(Vec3::Zero());
  attachmentImpulses_.push_back(Vec3::Zero());
  attachmentMoved_.push_back(0);
  return attachments_.size() - 1;
}

void Deformable::setAttachmentMotion(std::size_t i, const Vec3& position, const Vec3& velocity) {
  require(i < attachments_.size(),
          "Deformable::setAttachmentMotion: no attachment " + std::to_string(i));
  require(position.allFinite() && velocity.allFinite(),
          "Deformable::setAttachmentMotion: position and velocity must be finite");
  attachmentPositions_[i] = position;
  attachmentVelocities_[i] = velocity;
  attachmentMoved_[i] = 1;
}

// The step as a list of stages (each in its own file).
void Deformable::step(Real h, ThreadPool* pool) {
  detail::StepWorkers::run(pool ? &pool->impl().arena : nullptr,
                           [&](detail::StepWorkers& workers) { step(h, workers); });
}

void Deformable::step(Real h, detail::StepWorkers& workers) {
  require(std::isfinite(h) && h > 0, "Deformable::step: h must be finite and > 0 (s)");
  tearEvents_.clear();
  obstacleImpulses_.clear();
  scratch_->start = x_;
  if (settings_.integrator == ode::Method::BackwardEuler) {
    holdBodyContacts(h);
    integrateImplicit(h, workers);
    pushHeldContacts();
  } else
    integrateExplicit(h);
  time_ += double(h);
  moveAttachments(h);
  collide(h);
  if (settings_.selfCollision) {
    Deformable* self = this;
    collideDeformables({&self, 1}, h, scratch_->selfCollision);
  }
  tear();
}

double Deformable::kineticEnergy() const {
  double e = 0;
  for (std::size_t i = 0; i < vertexCount(); ++i)
    e += 0.5 * double(masses_[i]) * Eigen::Map<const Vec3>(&v_[3 * i]).cast<double>().squaredNorm();
  return e;
}

double Deformable::springEnergy() const {
  double e = 0;
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    if (broken_[k]) continue;
    const Spring& s = springs_[k];
    const double l = (Eigen::Map<const Vec3>(&x_[3 * s.a]) - Eigen::Map<const Vec3>(&x_[3 * s.b]))
                         .cast<double>()
                         .norm();
    e += 0.5 * double(s.stiffness) * (l - double(s.restLength)) * (l - double(s.restLength));
  }
  return e;
}

}  // namespace inertia
