// Articulations shared by the tests, the benchmarks and (later) the samples: seeded random trees
// with every joint type, pendulum chains, a 7-DOF arm and a humanoid.
#pragma once

#include <cstdint>

#include "inertia/articulation/model.h"

namespace inertia::articulation {

struct RandomTreeOptions {
  int links = 10;
  bool floatingBase = false;  ///< Link 0 on a floating joint (else a revolute one).
  bool armature = true;       ///< Random armature on some joints.
  std::uint32_t seed = 1;
};

/// A random tree: link i's parent drawn from the earlier links, joint types cycling through
/// revolute, prismatic, spherical and fixed, random joint frames and axes, masses in [0.5, 2] kg
/// and inertias of random boxes (so they are physical) turned by random rotations.
template <class S>
Model<S> randomTree(const RandomTreeOptions& options);

/// A random configuration and velocity of `model` (angles and displacements in [-1, 1],
/// uniformly random quaternions, velocities in [-1, 1]), drawn from `seed`.
template <class S>
void randomState(const Model<S>& model, std::uint32_t seed, VectorX<S>& q, VectorX<S>& qd);

/// A chain of `links` revolute joints about z hanging along -y from the base origin, each link a
/// point mass `mass` (kg) at its end, `length` (m) below its joint, with a tiny isotropic
/// inertia (1e-6 m^2 times the mass, the model needs a positive definite one).
template <class S>
Model<S> pendulumChain(int links, S length, S mass);

/// A 7-DOF arm shaped as the Franka Panda (its published kinematics and link masses; inertias
/// of cylinders), fixed base, revolute joints about z with limits.
template <class S>
Model<S> sevenDofArm();

/// A 30-DOF humanoid (a benchmark's model, y up, about 1.7 m and 57 kg): a floating pelvis;
/// two-axis waist, neck and ankles, three-axis shoulders and hips, one-axis elbows and knees,
/// each axis a revolute joint (multi-axis joints as chains of small links at one origin); box
/// inertias.
template <class S>
Model<S> humanoid();

}  // namespace inertia::articulation
