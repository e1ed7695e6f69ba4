// The binding files' shared declarations: the World as Python holds it, and one bind
// function per area (shapes.cpp, world.cpp, joints.cpp, particles.cpp, batch.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <unordered_map>

#include "inertia/world/world.h"

namespace inertia::python {

namespace py = pybind11;

/// A World as the Python object holds it: the world, how many NumPy views of each particle
/// system's memory are alive (destroying a system with views on it is refused instead of
/// leaving them dangling), and whether a step is running on it without the GIL.
struct PyWorld {
  std::unique_ptr<World> world;
  std::unordered_map<std::uint32_t, int> particleViews;  // by the system's slot index
  // Set while a step runs with the GIL released (World.step, advance, Batch.step); read and
  // written only while holding the GIL, so the check below cannot race with it.
  bool stepping = false;

  /// The world, for a method called from Python: RuntimeError while another thread steps it
  /// (instead of a data race that could crash).
  World* operator->() const {
    if (stepping) throw std::runtime_error("World: another thread is stepping it");
    return world.get();
  }
  World& operator*() const { return *operator->(); }
};

/// Marks worlds as stepping for a scope. Declare it before the py::gil_scoped_release, so that
/// it clears the marks after the GIL is taken back, also when the step throws.
class SteppingScope {
 public:
  explicit SteppingScope(PyWorld& world) : one_(&world), worlds_(&one_, 1) { mark(true); }
  explicit SteppingScope(std::span<PyWorld* const> worlds) : worlds_(worlds) { mark(true); }
  ~SteppingScope() { mark(false); }
  SteppingScope(const SteppingScope&) = delete;
  SteppingScope& operator=(const SteppingScope&) = delete;

 private:
  void mark(bool on) {
    for (PyWorld* w : worlds_) w->stepping = on;
  }
  PyWorld* one_ = nullptr;
  std::span<PyWorld* const> worlds_;
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
