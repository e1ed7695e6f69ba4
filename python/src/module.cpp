// The `inertia` extension module: its exceptions, and the areas bound in their own files.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>

#include "articulation_model.h"
#include "bindings.h"
#include "convert.h"
#include "inertia/core/error.h"
#include "inertia/core/id.h"
#include "inertia/io/scene.h"

namespace inertia::python {

namespace {

template <class Tag>
void bindId(py::module_& m, const char* name, const char* doc) {
  using IdT = Id<Tag>;
  py::class_<IdT>(m, name, doc)
      .def(py::init<>(), "The null handle.")
      .def_readonly("index", &IdT::index, "Slot index.")
      .def_readonly("generation", &IdT::generation, "Slot generation (0: null).")
      .def("is_null", &IdT::isNull)
      .def("__eq__", [](const IdT& a, const IdT& b) { return a == b; })
      .def("__hash__", [](const IdT& a) { return py::hash(py::make_tuple(a.index, a.generation)); })
      .def("__repr__",
           [name](const IdT& a) {
             return std::string(name) + "(" + std::to_string(a.index) + ", " +
                    std::to_string(a.generation) + ")";
           })
      .def(py::pickle([](const IdT& a) { return py::make_tuple(a.index, a.generation); },
                      [](const py::tuple& t) {
                        if (t.size() != 2) throw py::value_error("bad pickled handle");
                        return IdT{t[0].cast<std::uint32_t>(), t[1].cast<std::uint32_t>()};
                      }));
}

// pybind11 gives an object made by Class.__new__(Class) without __init__ uninitialised memory
// as its value when a method is first called on it (type_caster_generic::load_value's "lazy
// allocation"), and the method would then run on garbage: a crash. It allocates that memory with
// the type's operator_new when one is set, and nothing else calls operator_new, so setting it
// to this function turns the crash into a TypeError. (Pickling's __setstate__ and __init__
// construct in place and never reach it.)
void* refuseUninitialised(std::size_t) {
  throw py::type_error(
      "this inertia object was made with __new__ and never initialised: make it by calling its "
      "class (inertia.World(...), ...)");
}

void guardUninitialised(py::handle scope, int depth = 0) {
  if (depth > 2) return;
  for (const auto& [name, value] : py::dict(scope.attr("__dict__"))) {
    if (!PyType_Check(value.ptr()) || name.cast<std::string>().starts_with("__")) continue;
    auto* type = reinterpret_cast<PyTypeObject*>(value.ptr());
    if (py::detail::type_info* info = py::detail::get_type_info(type)) {
      info->operator_new = &refuseUninitialised;
      guardUninitialised(value, depth + 1);  // nested classes
    }
  }
}

}  // namespace

void guardModuleClasses(py::module_& m) { guardUninitialised(m); }

void bindIds(py::module_& m) {
  bindId<BodyTag>(m, "BodyId", "A rigid body of a World (a small value: index and generation).");
  bindId<ShapeTag>(m, "ShapeId", "A shape attached to a body.");
  bindId<JointTag>(m, "JointId", "A joint between two bodies, or a body and the world.");
  bindId<ParticleSystemTag>(m, "ParticleSystemId", "A particle system of a World.");
  bindId<DeformableTag>(m, "DeformableId", "A deformable (rope, cloth, soft body) of a World.");
  bindId<ArticulationTag>(m, "ArticulationId", "An articulation (a tree of links) of a World.");
}

}  // namespace inertia::python

PYBIND11_MODULE(_inertia, m) {
  namespace py = pybind11;
  using namespace inertia;
  m.doc() = "Inertia, a real-time physics engine: the C++ library's API in Python's conventions.";

  // InvalidArgument and SceneError are ValueErrors; SceneError carries the file, the JSON
  // pointer and the reason as attributes. The types live as long as the interpreter.
  // InvalidArgument's message is the library's, in the Python API's names (pythonMessage).
  static PyObject* invalidArgument =
      py::exception<InvalidArgument>(m, "InvalidArgument", PyExc_ValueError).release().ptr();
  static PyObject* sceneError =
      py::exception<io::SceneError>(m, "SceneError", PyExc_ValueError).release().ptr();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const io::SceneError& e) {
      py::object error = py::reinterpret_borrow<py::object>(sceneError)(e.what());
      error.attr("file") = e.file();
      error.attr("pointer") = e.pointer();
      error.attr("reason") = e.reason();
      PyErr_SetObject(sceneError, error.ptr());
    } catch (const InvalidArgument& e) {
      PyErr_SetString(invalidArgument, python::pythonMessage(e.what()).c_str());
    }
  });

  m.attr("real_dtype") = py::dtype::of<Real>();
  python::bindIds(m);
  python::bindShapes(m);
  python::bindWorld(m);
  python::bindJoints(m);
  python::bindArticulationModel(m);
  python::bindArticulations(m);
  python::bindParticles(m);
  python::bindDeformables(m);
  python::bindBatch(m);
  python::guardModuleClasses(m);  // last: every class is bound
}
