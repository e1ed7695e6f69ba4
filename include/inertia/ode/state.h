// State vectors the integrators accept, the views their callbacks receive, and the concepts
// that check a callback's signature at compile time.
//
// Every integrator works on a "state": one contiguous array of floating-point scalars. Accepted
// are Eigen column vectors with unit inner stride (VectorXd, Vector3f, Map<VectorXf>, Ref,
// a segment of a vector), std::span<T>, std::vector<T> and std::array<T, N>. Inside, a state is
// always seen through an Eigen::Map (View below), so one algorithm serves all of them and a
// structure-of-arrays particle buffer is integrated in place, without a copy.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "inertia/core/error.h"

namespace inertia::ode {

/// Owning column vector of `N` scalars (`Eigen::Dynamic`: size set at run time).
template <class Scalar, int N = Eigen::Dynamic>
using Vector = Eigen::Matrix<Scalar, N, 1>;

/// Mutable view of a state or of a derivative: what callbacks write into.
template <class Scalar, int N = Eigen::Dynamic>
using View = Eigen::Map<Vector<Scalar, N>>;

/// Read-only view of a state: what callbacks read.
template <class Scalar, int N = Eigen::Dynamic>
using ConstView = Eigen::Map<const Vector<Scalar, N>>;

/// Mutable view of a dense N x N Jacobian (column-major).
template <class Scalar, int N = Eigen::Dynamic>
using JacobianView = Eigen::Map<Eigen::Matrix<Scalar, N, N>>;

/// Compile-time description of a state type: its scalar, its compile-time size (or
/// Eigen::Dynamic) and access to its storage. Specialised below for Eigen vectors, std::span,
/// std::vector and std::array; `valid` is false for anything else.
template <class T>
struct StateTraits {
  static constexpr bool valid = false;
};

namespace detail {

template <class T>
concept EigenColumnVector = std::is_base_of_v<Eigen::DenseBase<T>, T> &&
                                T::ColsAtCompileTime == 1 &&
                            (Eigen::internal::traits<T>::Flags & Eigen::DirectAccessBit) != 0 &&
                            T::InnerStrideAtCompileTime == 1;

}  // namespace detail

template <detail::EigenColumnVector T>
struct StateTraits<T> {
  static constexpr bool valid = true;
  using Scalar = typename T::Scalar;
  static constexpr int size = T::RowsAtCompileTime;
};

template <class T, std::size_t E>
struct StateTraits<std::span<T, E>> {
  static constexpr bool valid = true;
  using Scalar = std::remove_const_t<T>;
  static constexpr int size = E == std::dynamic_extent ? Eigen::Dynamic : static_cast<int>(E);
};

template <class T, class A>
struct StateTraits<std::vector<T, A>> {
  static constexpr bool valid = true;
  using Scalar = T;
  static constexpr int size = Eigen::Dynamic;
};

template <class T, std::size_t N>
struct StateTraits<std::array<T, N>> {
  static constexpr bool valid = true;
  using Scalar = T;
  static constexpr int size = static_cast<int>(N);
};

/// A type the integrators can update in place: a supported container of a floating-point
/// scalar whose elements are writable through this reference (a `const VectorXd&` or a
/// `std::span<const float>` is not).
template <class S>
concept MutableState = StateTraits<std::remove_cvref_t<S>>::valid &&
    std::floating_point<typename StateTraits<std::remove_cvref_t<S>>::Scalar> &&
    requires(std::remove_reference_t<S>& s) {
  { s.data() } -> std::same_as<typename StateTraits<std::remove_cvref_t<S>>::Scalar*>;
  { s.size() } -> std::convertible_to<std::ptrdiff_t>;
};

/// Scalar of a state type (`double` for VectorXd, `float` for std::span<float>).
template <class S>
using ScalarOf = typename StateTraits<std::remove_cvref_t<S>>::Scalar;

/// Compile-time size of a state type, or Eigen::Dynamic.
template <class S>
inline constexpr int sizeOf = StateTraits<std::remove_cvref_t<S>>::size;

/// Compile-time size shared by two states, or Eigen::Dynamic when they differ.
template <class X, class V>
inline constexpr int commonSizeOf = sizeOf<X> == sizeOf<V> ? sizeOf<X> : Eigen::Dynamic;

/// A first-order right-hand side y' = f(t, y): `f(t, y, dydt)` writes y'(t) into `dydt`.
/// It must not keep the views: they point into the state or into workspace buffers.
template <class F, class Scalar, int N>
concept Derivative = std::invocable<F&, Scalar, ConstView<Scalar, N>, View<Scalar, N>>;

/// A second-order right-hand side x'' = a(t, x, v): `a(t, x, v, acc)` writes the acceleration.
template <class F, class Scalar, int N>
concept Acceleration =
    std::invocable<F&, Scalar, ConstView<Scalar, N>, ConstView<Scalar, N>, View<Scalar, N>>;

/// A dense Jacobian of a first-order system: `jacobian(t, y, J)` writes df/dy into J (which is
/// zeroed before the call, so a sparse pattern only has to fill its non-zeros).
template <class F, class Scalar, int N>
concept DenseJacobian = std::invocable<F&, Scalar, ConstView<Scalar, N>, JacobianView<Scalar, N>>;

/// A matrix-free Jacobian of a first-order system: `jacobianTimes(t, y, w, out)` writes
/// (df/dy)(t, y) * w into `out`.
template <class F, class Scalar, int N>
concept JacobianProduct =
    std::invocable<F&, Scalar, ConstView<Scalar, N>, ConstView<Scalar, N>, View<Scalar, N>>;

/// A matrix-free Jacobian of a second-order system: `dadx(t, x, v, w, out)` writes
/// (da/dx)(t, x, v) * w into `out` (likewise for da/dv).
template <class F, class Scalar, int N>
concept SecondOrderJacobianProduct =
    std::invocable<F&, Scalar, ConstView<Scalar, N>, ConstView<Scalar, N>, ConstView<Scalar, N>,
                   View<Scalar, N>>;

namespace detail {

/// The Eigen view of any state; writes through it update the caller's storage.
template <MutableState S>
View<ScalarOf<S>, sizeOf<S>> view(S&& s) {
  return View<ScalarOf<S>, sizeOf<S>>(s.data(), static_cast<Eigen::Index>(s.size()));
}

/// The same view with the compile-time size N (Eigen::Dynamic or the state's own size).
template <int N, MutableState S>
View<ScalarOf<S>, N> viewAs(S&& s) {
  return View<ScalarOf<S>, N>(s.data(), static_cast<Eigen::Index>(s.size()));
}

template <class Scalar, int N>
ConstView<Scalar, N> constView(const View<Scalar, N>& v) {
  return ConstView<Scalar, N>(v.data(), v.size());
}

/// Boundary check shared by every stepper. The message is built only on failure, so the
/// check costs no allocation on the hot path.
template <class Scalar>
void checkStep(Scalar t, Scalar h) {
  if (!(std::isfinite(h) && h > Scalar(0)))
    throw InvalidArgument(
        "ode: the step size h must be finite and > 0 (got h = " + std::to_string(h) + ")");
  if (!std::isfinite(t))
    throw InvalidArgument("ode: the time t must be finite (got t = " + std::to_string(t) + ")");
}

inline void checkSameSize(Eigen::Index a, Eigen::Index b, const char* what) {
  if (a != b)
    throw InvalidArgument(std::string("ode: ") + what + " must have the same size (got " +
                          std::to_string(a) + " and " + std::to_string(b) + ")");
}

}  // namespace detail
}  // namespace inertia::ode
