// Conversions between Python values and the library's types, shared by the binding files.
// Every conversion names the argument it converts, so that a bad value raises a ValueError
// that says which one ("position: expected 3 numbers, got 2").
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>
#include <vector>

#include "inertia/core/id.h"
#include "inertia/core/types.h"

namespace inertia::python {

namespace py = pybind11;

/// NumPy's dtype of Real (float32, or float64 in a -DINERTIA_DOUBLE=ON build).
using RealArray = py::array_t<Real, py::array::c_style | py::array::forcecast>;

/// Raises ValueError with "ARG: WHAT".
[[noreturn]] void argumentError(const std::string& arg, const std::string& what);

/// A library error message in the Python API's names, for the InvalidArgument it raises:
/// a settings struct's qualifier goes (`BodySettings::linearDamping` is the argument
/// `linear_damping`), another type's becomes Python's dot (`World::advance: maxSteps` reads
/// `World.advance: max_steps`), camelCase names become snake_case, and the few fields whose
/// Python argument has another name take it (`BodySettings::linearVelocity` is `velocity`).
std::string pythonMessage(const std::string& what);

/// A sequence of n numbers (a list, tuple or NumPy array) as Reals; ValueError naming `arg`
/// otherwise. Values are not checked for finiteness here: the library rejects NaN where it
/// enters, with its own message.
void toReals(py::handle value, const char* arg, Real* out, std::size_t n);

Vec3 toVec3(py::handle value, const char* arg);
/// A quaternion given as [w, x, y, z] (the scene files' order).
Quat toQuat(py::handle value, const char* arg);

/// A (rows, cols) C-contiguous array of Reals converted from any array-like, or ValueError
/// naming `arg` and the shape it has.
RealArray toMatrix(py::handle value, const char* arg, py::ssize_t rows, py::ssize_t cols);
/// Any (k, cols) array-like; k is free (and cols too when negative).
RealArray toRows(py::handle value, const char* arg, py::ssize_t cols);

/// New NumPy arrays holding copies.
/// Writes v (3 values) or q ([w, x, y, z]) at `out` and returns the end: array rows.
Real* put(const Vec3& v, Real* out);
Real* put(const Quat& q, Real* out);
/// One row of `cols` values per body of `ids`, in their order: get(id, out) writes a row and
/// returns its end.
template <class Get>
RealArray bodyRows(const std::vector<BodyId>& ids, py::ssize_t cols, Get get) {
  RealArray a({py::ssize_t(ids.size()), cols});
  Real* out = a.mutable_data();
  for (BodyId id : ids) out = get(id, out);
  return a;
}

RealArray fromVec3(const Vec3& v);
RealArray fromQuat(const Quat& q);  ///< [w, x, y, z]
RealArray fromMat3(const Mat3& m);

/// Reads the keyword arguments into a default-constructed object's attributes, for settings
/// classes made with keywords only (inertia.HingeJoint(body_b=door, limits=(-1, 0))): an
/// unknown keyword raises TypeError naming it, a bad value the attribute's own error.
void setAttributes(py::handle object, const py::kwargs& kwargs, const char* type);

}  // namespace inertia::python

namespace inertia::python {

/// A read-write property of a Vec3 member, converted with toVec3 (ValueError naming it).
template <class C, class Class>
void vec3Property(Class& cls, const char* name, Vec3 C::*member, const char* doc) {
  cls.def_property(
      name, [member](const C& c) { return fromVec3(c.*member); },
      [member, name](C& c, py::handle v) { c.*member = toVec3(v, name); }, doc);
}

/// A read-write property of a Quat member ([w, x, y, z]).
template <class C, class Class>
void quatProperty(Class& cls, const char* name, Quat C::*member, const char* doc) {
  cls.def_property(
      name, [member](const C& c) { return fromQuat(c.*member); },
      [member, name](C& c, py::handle v) { c.*member = toQuat(v, name); }, doc);
}

}  // namespace inertia::python
