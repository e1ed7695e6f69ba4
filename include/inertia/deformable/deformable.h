// A mass-spring deformable (rope and hair, cloth, soft body): its model, force fields, static
// obstacles, and one step of explicit (the ode layer's methods) or implicit integration
// (Baraff and Witkin 1998), collisions with shapes, tearing.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/deformable/model.h"
#include "inertia/ode/implicit.h"
#include "inertia/ode/method.h"
#include "inertia/particles/fields.h"
#include "inertia/particles/particle_system.h"

namespace inertia {

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
  /// The implicit step's modified PCG stops when its preconditioned residual has fallen by
  /// this factor (relative), or after maxIterations.
  double solverTolerance = 1e-6;
  int solverMaxIterations = 1000;
  /// In a World: every body's shapes are obstacles too (one way: bodies do not feel it).
  bool collideWithBodies = true;
};

/// Checks settings; throws InvalidArgument naming the first bad field.
void validate(const DeformableSettings& settings);

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

  /// Advances by h seconds: integrate (explicit or implicit), collide with the obstacles
  /// (swept, then pushed out to `thickness`), break springs past the strain limit. Throws
  /// InvalidArgument when h is not finite and > 0. Never produces NaN from valid input: an
  /// implicit solve that fails to give finite values leaves the velocities as they were.
  void step(Real h);

  /// The springs that broke during the last step.
  std::span<const TearEvent> tearEvents() const { return tearEvents_; }
  /// The last implicit step's linear solve (iterations, relative residual |r| / |b|).
  const ode::LinearSolveReport& lastSolve() const { return lastSolve_; }
  double time() const { return time_; }

  /// Kinetic energy (J) and the springs' potential energy sum k (l - L)^2 / 2 (J), in double.
  double kineticEnergy() const;
  double springEnergy() const;

 private:
  struct Scratch;  // src/deformable/scratch.h
  // The stages of step(), each in its own file of src/deformable/.
  void integrateExplicit(Real h);  // integration.cpp
  void integrateImplicit(Real h);  // integration.cpp
  void collide();                  // obstacle_collision.cpp
  void tear();                     // tearing.cpp

  DeformableSettings settings_;
  std::vector<Real> x_, v_, masses_;
  std::vector<std::uint8_t> pinned_;
  std::vector<Spring> springs_;
  std::vector<std::uint8_t> broken_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<ForceField> fields_;
  std::vector<Obstacle> obstacles_;
  std::vector<MovingObstacle> moving_;
  std::vector<TearEvent> tearEvents_;
  std::unique_ptr<Scratch> scratch_;
  ode::LinearSolveReport lastSolve_{};
  double time_ = 0;
};

}  // namespace inertia
