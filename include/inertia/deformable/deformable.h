// A mass-spring deformable (rope and hair, cloth, soft body): its model, force fields, static
// obstacles, and one step of explicit (the ode layer's methods) or implicit integration
// (Baraff and Witkin 1998), collisions with shapes, tearing.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "inertia/core/id.h"
#include "inertia/core/thread_pool.h"
#include "inertia/core/types.h"
#include "inertia/deformable/model.h"
#include "inertia/ode/implicit.h"
#include "inertia/ode/method.h"
#include "inertia/particles/fields.h"
#include "inertia/particles/particle_system.h"

namespace inertia {

namespace detail {
class StepWorkers;
}

/// How the implicit step solves each Newton system (src/deformable/implicit_euler.h).
enum class DeformableLinearSolver : std::uint8_t {
  /// Direct where its factors stay sparse (ropes, hair: strands), conjugate gradients elsewhere
  /// (cloth, soft bodies, whose factors fill in).
  Automatic,
  /// Baraff and Witkin's modified PCG, block-Jacobi preconditioned, to a relative residual
  /// between solverTolerance and 0.1 (inexact Newton).
  ConjugateGradient,
  /// A sparse LDL^T of the filtered system (Eigen's SimplicialLDLT in minimum-degree order),
  /// per group of connected components on the step's threads: backward stable whatever the
  /// system's condition, with no iteration cap to run out.
  Direct,
};

/// Settings of a deformable (designated initialisers).
struct DeformableSettings {
  std::string name{};
  /// BackwardEuler is Baraff and Witkin's implicit step ("implicit_euler" in scene files);
  /// every other method is the ode layer's, through ode::step.
  ode::Method integrator = ode::Method::BackwardEuler;
  /// Distance (m) kept between a vertex and an obstacle's surface, > 0.
  Real thickness = Real(0.01);
  /// Coulomb coefficient against obstacles, >= 0 (contacts are inelastic).
  Real friction = Real(0.3);
  /// A spring breaks when its strain (l - L) / L exceeds this; 0 never breaks.
  Real tearStrain = 0;
  /// The implicit step's Newton iterations stop when the gradient of the incremental potential
  /// has fallen to this fraction of its scale (|M v0| + h |f|), or after newtonMaxIterations;
  /// each one's modified PCG stops at a relative residual between this and 0.1, or after
  /// solverMaxIterations.
  double solverTolerance = 1e-6;
  int solverMaxIterations = 1000;
  int newtonMaxIterations = 20;
  DeformableLinearSolver linearSolver = DeformableLinearSolver::Automatic;
  /// Vertex-triangle and edge-edge collisions within the deformable (Bridson et al. 2002); in
  /// a World, also with the other deformables that have it.
  bool selfCollision = false;
  /// In a World: every body's shapes are obstacles too; dynamic bodies feel the contacts.
  bool collideWithBodies = true;
};

/// Checks settings; throws InvalidArgument naming the first bad field.
void validate(const DeformableSettings& settings);

/// A vertex held to a point of a body by a zero-length damped spring, F = -k (x - p) - c (v - v_p)
/// on the vertex and -F on the body at p (two-way). The world gives the point's motion before
/// each step (setAttachmentMotion) and applies attachmentImpulse() to the body after it.
struct Attachment {
  std::uint32_t vertex = 0;
  BodyId body{};
  Vec3 anchor = Vec3::Zero();  ///< p in the body's frame (m).
  Real stiffness = 1e4;        ///< k (N/m), > 0.
  Real damping = 0;            ///< c (N s/m), >= 0.
};

/// An impulse a deformable's vertex gave a moving obstacle (a body) during a step.
struct ObstacleImpulse {
  std::size_t obstacle = 0;     ///< Index into the span given to setMovingObstacles().
  Vec3 impulse = Vec3::Zero();  ///< On the obstacle (N s, world).
  Vec3 point = Vec3::Zero();    ///< Where (m, world).
};

/// The last implicit step's solve (Newton on the incremental potential, src/deformable/
/// implicit_euler.h).
struct ImplicitSolveReport {
  int newtonIterations = 0;  ///< Newton steps taken.
  int iterations = 0;        ///< PCG iterations (1 per direct solve), over all Newton steps.
  double error = 0;          ///< Final gradient relative to its scale.
  /// max(0, G . v1) (J): the step's total energy (kinetic, springs, gravity) is at most this
  /// above its start (0 for an exact solve, which never gains energy).
  double energySlack = 0;
  bool converged = true;  ///< False if the tolerance was not met or the result was not finite.
};

/// What Deformable::collideDeformables keeps from call to call: bounding-volume trees over the
/// triangles' and edges' swept boxes and the stage's buffers, so that a step after warm-up
/// allocates nothing while the deformables stay the same. Not part of a deformable's state: a
/// copy starts empty.
class DeformableCollisionCache {
 public:
  DeformableCollisionCache();
  ~DeformableCollisionCache();
  DeformableCollisionCache(const DeformableCollisionCache&);
  DeformableCollisionCache& operator=(const DeformableCollisionCache&);
  DeformableCollisionCache(DeformableCollisionCache&&) noexcept;
  DeformableCollisionCache& operator=(DeformableCollisionCache&&) noexcept;

  struct Impl;  ///< Opaque: src/deformable/self_collision.cpp.

 private:
  friend class Deformable;
  std::unique_ptr<Impl> impl_;
};

/// A spring that broke: the step's strain exceeded DeformableSettings::tearStrain.
struct TearEvent {
  std::size_t spring = 0;      ///< Index into Deformable::springs().
  std::uint32_t a = 0, b = 0;  ///< Its vertices.
  Real strain = 0;             ///< (l - L) / L when it broke.
  double time = 0;             ///< s, the end of the step.
};

/// A mass-spring object. Vertex data is stored as structures of arrays: positions and
/// velocities are 3 Reals per vertex, contiguous.
class Deformable {
 public:
  /// Throws InvalidArgument for invalid settings or model.
  Deformable(const DeformableSettings& settings, const MassSpringModel& model);
  ~Deformable();
  Deformable(Deformable&&) noexcept;
  Deformable& operator=(Deformable&&) noexcept;
  /// A deep copy, step scratch included (the implicit solve's buffers): the copy continues
  /// bit-identically (World::saveState). Moving obstacles are shared, not copied.
  Deformable(const Deformable& other);
  Deformable& operator=(const Deformable& other);

  const DeformableSettings& settings() const { return settings_; }
  const std::string& name() const { return settings_.name; }

  std::size_t vertexCount() const { return masses_.size(); }
  std::span<const Real> positions() const { return x_; }    ///< m, 3 per vertex.
  std::span<const Real> velocities() const { return v_; }   ///< m/s, 3 per vertex.
  std::span<const Real> masses() const { return masses_; }  ///< kg.
  Vec3 position(std::size_t vertex) const;
  Vec3 velocity(std::size_t vertex) const;
  /// Moves a vertex or sets its velocity (InvalidArgument for a bad index or a non-finite
  /// value; a pinned vertex keeps velocity zero).
  void setPosition(std::size_t vertex, const Vec3& x);
  void setVelocity(std::size_t vertex, const Vec3& v);
  bool isPinned(std::size_t vertex) const;
  /// Pins a vertex where it is now (its velocity becomes zero), or frees it.
  void setPinned(std::size_t vertex, bool pinned);

  std::span<const Spring> springs() const { return springs_; }
  bool isBroken(std::size_t spring) const { return broken_.at(spring) != 0; }
  std::size_t brokenCount() const;
  std::span<const std::array<std::uint32_t, 3>> triangles() const { return triangles_; }

  /// Force fields of the particle layer (gravity, drag, wind, ...): accelerations of every
  /// vertex. Validated (InvalidArgument); returns the index.
  std::size_t addField(const ForceField& field);
  std::span<const ForceField> fields() const { return fields_; }
  /// A static obstacle (validated pose); returns the index.
  std::size_t addObstacle(const Obstacle& obstacle);
  std::span<const Obstacle> obstacles() const { return obstacles_; }
  /// Obstacles owned elsewhere for the next steps (a World's bodies): tested discretely at the
  /// end of each step, with friction on the velocity relative to their surface.
  void setMovingObstacles(std::span<const MovingObstacle> obstacles);

  /// Holds a vertex to a body's point (validated: a vertex that exists, k > 0, c >= 0, finite
  /// anchor); returns the index. The point stays where it is until setAttachmentMotion.
  std::size_t addAttachment(const Attachment& attachment);
  std::span<const Attachment> attachments() const { return attachments_; }
  /// The attachment point's world position (m) and velocity (m/s) at the next step's start;
  /// during the step it moves on at that velocity.
  void setAttachmentMotion(std::size_t attachment, const Vec3& position, const Vec3& velocity);
  /// The attachment point's world position now (m): at the end of the last step's motion, or
  /// the vertex's position before any setAttachmentMotion (then hasAttachmentMotion is false).
  Vec3 attachmentPoint(std::size_t attachment) const { return attachmentPositions_.at(attachment); }
  bool hasAttachmentMotion(std::size_t attachment) const {
    return attachmentMoved_.at(attachment) != 0;
  }
  /// The impulse (N s, world) the last step's attachment spring gave the body at its point.
  Vec3 attachmentImpulse(std::size_t attachment) const {
    return attachmentImpulses_.at(attachment);
  }
  /// Impulses the last step's contacts gave moving obstacles with mass (two-way contacts): the
  /// vertices' momentum change, reversed, so their sum is conserved.
  std::span<const ObstacleImpulse> obstacleImpulses() const { return obstacleImpulses_; }

  /// Advances by h seconds: integrate (explicit or implicit), collide with the obstacles
  /// (swept, then pushed out to `thickness`), break springs past the strain limit. Throws
  /// InvalidArgument when h is not finite and > 0. Never produces NaN from valid input: an
  /// implicit solve that fails to give finite values leaves the velocities as they were, and an
  /// explicit step that diverges (past the method's stability limit) is undone; lastSolve()
  /// says so. The implicit solve runs on the threads of `pool` (in sequence when null); the
  /// result is the same bytes.
  void step(Real h, ThreadPool* pool = nullptr);
  /// The same on the workers of a step already under way (a World's). Internal.
  void step(Real h, detail::StepWorkers& workers);

  /// The collision stage of self-collision run over several deformables' last steps at once
  /// (each stepped by h from where its own step started): their vertices and triangles collide
  /// with each other's as with their own. A World calls it for its deformables with
  /// selfCollision after stepping them. `cache` holds the stage's trees and buffers between
  /// calls; the result does not depend on what it holds.
  static void collideDeformables(std::span<Deformable* const> deformables, Real h,
                                 DeformableCollisionCache& cache);

  /// The springs that broke during the last step.
  std::span<const TearEvent> tearEvents() const { return tearEvents_; }
  /// The last step's solve: the implicit step's Newton and PCG figures; for an explicit
  /// method, `converged` false when the step gave non-finite values and was undone.
  const ImplicitSolveReport& lastSolve() const { return lastSolve_; }
  double time() const { return time_; }

  /// Kinetic energy (J) and the springs' potential energy sum k (l - L)^2 / 2 (J), in double.
  double kineticEnergy() const;
  double springEnergy() const;

 private:
  struct Scratch;  // src/deformable/scratch.h
  // The stages of step(), each in its own file of src/deformable/.
  void integrateExplicit(Real h);                                // integration.cpp
  void integrateImplicit(Real h, detail::StepWorkers& workers);  // integration.cpp
  void holdBodyContacts(Real h);                                 // obstacle_collision.cpp
  void pushHeldContacts();                                       // obstacle_collision.cpp
  void moveAttachments(Real h);                                  // attachments.cpp
  void collide(Real h);                                          // obstacle_collision.cpp
  void tear();                                                   // tearing.cpp

  DeformableSettings settings_;
  std::vector<Real> x_, v_, masses_;
  std::vector<std::uint8_t> pinned_;
  std::vector<Spring> springs_;
  std::vector<std::uint8_t> broken_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::array<std::uint32_t, 2>> edges_;  // the triangles' edges, each once
  std::vector<ForceField> fields_;
  std::vector<Obstacle> obstacles_;
  std::vector<MovingObstacle> moving_;
  std::vector<Attachment> attachments_;
  std::vector<Vec3> attachmentPositions_, attachmentVelocities_, attachmentImpulses_;
  std::vector<std::uint8_t> attachmentMoved_;
  std::vector<ObstacleImpulse> obstacleImpulses_;
  std::vector<TearEvent> tearEvents_;
  std::unique_ptr<Scratch> scratch_;
  ImplicitSolveReport lastSolve_{};
  double time_ = 0;
};

}  // namespace inertia
