// The fixed-step integration methods by name, for scene files ("integrator": "rk4").
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace inertia::ode {

/// A fixed-step method that can advance a second-order system x'' = a(t, x, v) (see ode::step).
enum class Method {
  ExplicitEuler,    ///< "explicit_euler", order 1 (on the stacked state (x, v)).
  Midpoint,         ///< "midpoint", explicit midpoint / RK2, order 2.
  Heun,             ///< "heun", explicit trapezoid, order 2.
  Rk4,              ///< "rk4", classic Runge-Kutta, order 4.
  Verlet,           ///< "verlet", position (Stormer) Verlet, order 2.
  VelocityVerlet,   ///< "velocity_verlet", order 2.
  SymplecticEuler,  ///< "symplectic_euler", semi-implicit Euler, order 1.
  BackwardEuler,    ///< "backward_euler", linearised implicit Euler, order 1.
};

/// Every method, in declaration order.
inline constexpr std::array<Method, 8> kMethods = {Method::ExplicitEuler,
                                                   Method::Midpoint,
                                                   Method::Heun,
                                                   Method::Rk4,
                                                   Method::Verlet,
                                                   Method::VelocityVerlet,
                                                   Method::SymplecticEuler,
                                                   Method::BackwardEuler};

/// The scene-file name of every method, in the order of kMethods.
inline constexpr std::array<std::string_view, 8> kMethodNames = {
    "explicit_euler",  "midpoint",         "heun",          "rk4", "verlet",
    "velocity_verlet", "symplectic_euler", "backward_euler"};

/// The scene-file name of `method` ("rk4"); empty for a value outside the enum.
constexpr std::string_view methodName(Method method) {
  const auto i = static_cast<std::size_t>(method);
  return i < kMethodNames.size() ? kMethodNames[i] : std::string_view{};
}

/// The method with scene-file name `name` (exact, lower case), or nullopt.
constexpr std::optional<Method> methodFromName(std::string_view name) {
  for (std::size_t i = 0; i < kMethodNames.size(); ++i)
    if (kMethodNames[i] == name) return kMethods[i];
  return std::nullopt;
}

/// Theoretical global order of accuracy p: the error at a fixed end time is O(h^p).
/// 0 for a value outside the enum.
constexpr int methodOrder(Method method) {
  switch (method) {
    case Method::ExplicitEuler:
      return 1;
    case Method::Midpoint:
      return 2;
    case Method::Heun:
      return 2;
    case Method::Rk4:
      return 4;
    case Method::Verlet:
      return 2;
    case Method::VelocityVerlet:
      return 2;
    case Method::SymplecticEuler:
      return 1;
    case Method::BackwardEuler:
      return 1;
  }
  return 0;
}

/// True for methods that solve a linear system and so need the system's Jacobians.
constexpr bool isImplicit(Method method) { return method == Method::BackwardEuler; }

}  // namespace inertia::ode
