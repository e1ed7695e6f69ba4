#include "convert.h"

#include <algorithm>

namespace inertia::python {

void argumentError(const std::string& arg, const std::string& what) {
  throw py::value_error(arg + ": " + what);
}

namespace {

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Any array-like as a C-contiguous array of Reals; ValueError naming `arg` when it holds
// something that is not a number.
RealArray asReals(py::handle value, const char* arg) {
  // NumPy would read None as NaN.
  if (value.is_none()) argumentError(arg, "expected numbers, got None");
  // forcecast: ints and float64 are accepted and rounded to Real.
  RealArray a = RealArray::ensure(value);
  if (!a)
    argumentError(arg, "expected numbers (a regular array of them), got " +
                           std::string(py::str(py::type::of(value))));
  return a;
}

}  // namespace

void toReals(py::handle value, const char* arg, Real* out, std::size_t n) {
  RealArray a = asReals(value, arg);
  if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
    argumentError(arg, "expected " + std::to_string(n) + " numbers, got shape " + shapeText(a));
  std::copy_n(a.data(), n, out);
}

Vec3 toVec3(py::handle value, const char* arg) {
  Vec3 v;
  toReals(value, arg, v.data(), 3);
  return v;
}

Quat toQuat(py::handle value, const char* arg) {
  Real q[4];
  toReals(value, arg, q, 4);
  return Quat(q[0], q[1], q[2], q[3]);
}

RealArray toRows(py::handle value, const char* arg, py::ssize_t cols) {
  RealArray a = asReals(value, arg);
  if (a.ndim() != 2 || (cols >= 0 && a.shape(1) != cols))
    argumentError(arg, "expected an array of shape (n, " +
                           (cols >= 0 ? std::to_string(cols) : std::string("m")) + "), got " +
                           shapeText(a));
  return a;
}

RealArray toMatrix(py::handle value, const char* arg, py::ssize_t rows, py::ssize_t cols) {
  RealArray a = toRows(value, arg, cols);
  if (a.shape(0) != rows)
    argumentError(arg, "expected an array of shape (" + std::to_string(rows) + ", " +
                           std::to_string(cols) + "), got " + shapeText(a));
  return a;
}

RealArray fromVec3(const Vec3& v) {
  RealArray a(3);
  std::copy_n(v.data(), 3, a.mutable_data());
  return a;
}

Real* put(const Vec3& v, Real* out) {
  out[0] = v.x(), out[1] = v.y(), out[2] = v.z();
  return out + 3;
}

Real* put(const Quat& q, Real* out) {
  out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
  return out + 4;
}

RealArray fromQuat(const Quat& q) {
  RealArray a(4);
  put(q, a.mutable_data());
  return a;
}

RealArray fromMat3(const Mat3& m) {
  RealArray a({3, 3});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.mutable_at(i, j) = m(i, j);
  return a;
}

void setAttributes(py::handle object, const py::kwargs& kwargs, const char* type) {
  for (auto [key, value] : kwargs) {
    const std::string name = py::str(key);
    // Only the class's properties are settable this way, not its methods.
    py::object attr = py::getattr(py::type::of(object), key, py::none());
    if (!py::isinstance(attr, py::module_::import("builtins").attr("property")))
      throw py::type_error(std::string(type) + ": unknown argument '" + name + "'");
    object.attr(key) = value;
  }
}

}  // namespace inertia::python
