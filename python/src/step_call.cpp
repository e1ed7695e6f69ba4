// World.step as a plain CPython method (METH_FASTCALL), the common call made without pybind11's
// dispatcher: step() and step(dt) on a world that is initialised and not being stepped. The
// dispatcher's general machinery (an argument vector and a conversion-flag vector allocated
// per call, the keyword and default handling, a type lookup by name for the instance) is about
// a tenth of an empty world's step; it buys nothing here. Every other call, and every call
// that would raise, goes to the same step bound by pybind11, so that the errors and their
// messages are those of the rest of the module.
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <vector>

#include "bindings.h"

namespace inertia::python {

namespace {

// The pybind11-bound step and World's type record, set by bindStep; they live
// as long as the interpreter, as the module does.
PyObject* checkedStep = nullptr;
const py::detail::type_info* worldType = nullptr;

// Calls the pybind11-bound step(self, *args, **kwargs): every case the fast path does not take.
PyObject* slowStep(PyObject* self, PyObject* const* args, Py_ssize_t nargs, PyObject* kwnames) {
  const Py_ssize_t nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
  std::vector<PyObject*> all(std::size_t(1 + nargs + nkw));
  all[0] = self;
  for (Py_ssize_t i = 0; i < nargs + nkw; ++i) all[std::size_t(1 + i)] = args[i];
  return PyObject_Vectorcall(checkedStep, all.data(), std::size_t(1 + nargs), kwnames);
}

// The world of an initialised inertia.World (the method descriptor has checked the type), or
// null for one made by __new__ without __init__.
PyWorld* worldOf(PyObject* self) {
  const py::detail::value_and_holder v =
      reinterpret_cast<py::detail::instance*>(self)->get_value_and_holder(worldType, false);
  if (!v.inst || !v.holder_constructed()) return nullptr;
  return v.value_ptr<PyWorld>();
}

// step(dt=None): the dt of a fast call, the world's own for none, or nullopt to take the slow
// path (keywords, a value that is not a float, or one the library would refuse).
std::optional<Real> fastDt(const World& world, PyObject* const* args, Py_ssize_t nargs,
                           PyObject* kwnames) {
  if (kwnames || nargs > 1) return std::nullopt;
  if (nargs == 0 || args[0] == Py_None) return world.settings().dt;
  if (!PyFloat_CheckExact(args[0])) return std::nullopt;
  const Real h = Real(PyFloat_AS_DOUBLE(args[0]));
  if (!(std::isfinite(h) && h > 0)) return std::nullopt;
  return h;
}

PyObject* step(PyObject* self, PyObject* const* args, Py_ssize_t nargs, PyObject* kwnames) {
  PyWorld* w = worldOf(self);
  if (!w || w->stepping) return slowStep(self, args, nargs, kwnames);
  const std::optional<Real> h = fastDt(*w->world, args, nargs, kwnames);
  if (!h) return slowStep(self, args, nargs, kwnames);
  try {
    {
      SteppingScope stepping(*w);
      py::gil_scoped_release release;
      w->world->step(*h);
    }
    if (w->recipe) w->recipe->record(*h, 0);
  } catch (...) {
    // As pybind11's dispatcher does: the module's translators, then the default ones.
    if (!py::detail::apply_exception_translators(
            py::detail::get_local_internals().registered_exception_translators) &&
        !py::detail::apply_exception_translators(
            py::detail::get_internals().registered_exception_translators))
      PyErr_SetString(PyExc_SystemError, "World.step: an exception escaped the translators");
    return nullptr;
  }
  Py_RETURN_NONE;
}

PyMethodDef stepMethod = {"step",
                          reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&step)),
                          METH_FASTCALL | METH_KEYWORDS,
                          "step($self, /, dt=None)\n--\n\n"
                          "Advances by exactly dt seconds (default: the world's dt), in substeps."};

}  // namespace

void bindStep(py::class_<PyWorld>& world) {
  // The pybind11 function is kept here only, not on the class: its messages name it "step".
  py::cpp_function checked(
      [](PyWorld& w, std::optional<Real> dt) {
        World& wd = w.get();
        const Real h = dt.value_or(wd.settings().dt);
        {
          SteppingScope stepping(w);
          py::gil_scoped_release release;  // the library checks h (InvalidArgument)
          wd.step(h);
        }
        if (w.recipe) w.recipe->record(h, 0);
      },
      py::name("step"), py::is_method(world), py::arg("dt") = py::none());
  checkedStep = checked.release().ptr();
  worldType = py::detail::get_type_info(typeid(PyWorld));
  py::object descriptor = py::reinterpret_steal<py::object>(
      PyDescr_NewMethod(reinterpret_cast<PyTypeObject*>(world.ptr()), &stepMethod));
  if (!descriptor) throw py::error_already_set();
  py::setattr(world, "step", descriptor);
}

}  // namespace inertia::python
