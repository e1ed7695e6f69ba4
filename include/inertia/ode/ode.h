// The ode layer: generic integrators over any state vector (Eigen vectors, spans of
// structure-of-arrays particle data), the seeds' general interface of state in, state out and
// a derivative callback.
//
//   explicit.h        explicit Euler, midpoint, Heun, RK4          (y' = f(t, y))
//   implicit.h        linearised backward Euler: dense LU, matrix-free CG / BiCGSTAB
//   second_order.h    symplectic Euler, velocity Verlet, Verlet, backward Euler, stacking
//                     of first-order methods                       (x'' = a(t, x, v))
//   dormand_prince.h  Dormand-Prince 5 at a fixed step, adaptive Dormand-Prince 5(4)
//   adaptive.h        step-doubling control, options and statistics
//   method.h          the Method enum, scene-file names, orders
//   step.h            ode::step: one step of a Method chosen at run time
//   state.h, workspace.h  accepted state types, views, concepts; caller-owned scratch
#pragma once

#include "inertia/ode/adaptive.h"
#include "inertia/ode/dormand_prince.h"
#include "inertia/ode/explicit.h"
#include "inertia/ode/implicit.h"
#include "inertia/ode/method.h"
#include "inertia/ode/second_order.h"
#include "inertia/ode/state.h"
#include "inertia/ode/step.h"
#include "inertia/ode/workspace.h"
