// The binding files' shared declarations: the World as Python holds it, and one bind
// function per area (shapes.cpp, world.cpp, joints.cpp, particles.cpp, batch.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <unordered_map>

#include "inertia/world/world.h"

namespace inertia::python {

namespace py = pybind11;

/// A World as the Python object holds it: the world, and how many NumPy views of each particle
/// system's memory are alive, so that destroying a system with views on it is refused instead
/// of leaving them dangling.
struct PyWorld {
  std::unique_ptr<World> world;
  std::unordered_map<std::uint32_t, int> particleViews;  // by the system's slot index

  World& operator*() const { return *world; }
  World* operator->() const { return world.get(); }
};

void bindIds(py::module_& m);
void bindShapes(py::module_& m);
void bindWorld(py::module_& m);
void bindJoints(py::module_& m);
void bindParticles(py::module_& m);
void bindBatch(py::module_& m);

/// The World class object, for files that add methods to it.
py::class_<PyWorld> worldClass(py::module_& m);

}  // namespace inertia::python
