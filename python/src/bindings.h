// The binding files' shared declarations: the World as Python holds it, and one bind
// function per area (shapes.cpp, world.cpp, joints.cpp, particles.cpp, deformables.cpp,
// batch.cpp; articulations in articulation_model.h).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "inertia/world/world.h"

namespace inertia::python {

namespace py = pybind11;

/// How to build a world again from nothing, for pickling: the scene it was made from and the
/// steps taken since, replayed on unpickling (the library is deterministic, so the replay gives
/// the same bytes). A world built or changed through the API has none.
struct Recipe {
  // The scene's JSON text, shared by the worlds made from it (a Batch's thousands).
  std::shared_ptr<const std::string> scene;
  std::string name;   // its file, for relative paths and messages
  std::optional<Real> dt;
  std::optional<int> threads;
  std::optional<Vec3> gravity;
  /// step(value) when maxSteps is 0, else advance(value, maxSteps); `repeat` times in a row.
  struct Call {
    Real value = 0;
    int maxSteps = 0;
    std::int64_t repeat = 1;
  };
  std::vector<Call> calls;

  void record(Real value, int maxSteps, std::int64_t times = 1);
  /// The world the recipe makes, with its calls replayed (without the GIL).
  std::unique_ptr<World> make() const;
};

/// Counts of the NumPy views alive on each system's memory, by the system's slot index.
using ViewCounts = std::unordered_map<std::uint32_t, int>;

/// A World as the Python object holds it: the world, how many NumPy views of each particle
/// system's and deformable's memory are alive (destroying one with views on it is refused
/// instead of leaving them dangling), whether a step is running on it without the GIL, and its
/// recipe while it has one.
struct PyWorld {
  std::unique_ptr<World> world;
  ViewCounts particleViews;
  ViewCounts deformableViews;
  ViewCounts articulationViews;
  // Set while a step runs with the GIL released (World.step, advance, Batch.step); read and
  // written only while holding the GIL, so the check below cannot race with it.
  bool stepping = false;
  std::optional<Recipe> recipe;
  /// Tells this world from every other of the process (for snapshots and their recipes).
  std::uint64_t serial = nextSerial();

  /// The world, to read from Python: RuntimeError while another thread steps it (instead of a
  /// data race that could crash).
  const World* operator->() const { return &get(); }
  const World& operator*() const { return get(); }
  /// The world, to change from Python: as the const one, and the world no longer follows its
  /// recipe (pickling it raises).
  World* operator->() {
    World* w = &get();
    recipe.reset();
    return w;
  }
  World& operator*() { return *operator->(); }
  /// ValueError from `call` while NumPy arrays view the memory of system `slot` (in `views`),
  /// whose `what` (its particles, ...) it would free.
  static void refuseViewed(const ViewCounts& views, std::uint32_t slot, const char* call,
                           const char* what) {
    if (const auto it = views.find(slot); it != views.end())
      throw py::value_error(std::string(call) + ": " + std::to_string(it->second) +
                            " NumPy arrays still view " + what + "; delete them first");
  }
  /// ValueError from `call` while any NumPy array views this world's memory (restore_state
  /// may free or move it).
  void refuseAnyViewed(const char* call) const {
    int n = 0;
    for (const ViewCounts* views : {&particleViews, &deformableViews, &articulationViews})
      for (const auto& [slot, count] : *views) n += count;
    if (n > 0)
      throw py::value_error(std::string(call) + ": " + std::to_string(n) +
                            " NumPy arrays still view this world's particles, vertices or "
                            "articulation states, which it would free or move; delete them first");
  }
  static std::uint64_t nextSerial() {
    static std::uint64_t last = 0;  // only touched with the GIL held
    return ++last;
  }
  /// The world to step, keeping the recipe (the step is recorded in it).
  World& get() const {
    if (stepping) throw std::runtime_error("World: another thread is stepping it");
    return *world;
  }
};

/// A read-only NumPy array of n rows of `cols` Reals (n values when cols is 1) over `data`,
/// which belongs to system `slot` of the World `self`: it keeps `self` alive and counts itself
/// in (self's) `counts` while it lives. Read-only because the library trusts what it stores
/// (a NaN could reach grid arithmetic); writes go through the set_* methods, which check.
py::array countedView(py::object self, ViewCounts PyWorld::*counts, std::uint32_t slot,
                      const Real* data, std::size_t n, py::ssize_t cols);

/// A force field from one of the inertia.*Field objects, limited to region = (lower, upper)
/// when that is not None (particles.cpp; shared with deformables.cpp).
ForceField toForceField(py::handle field, py::handle region);

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
void bindDeformables(py::module_& m);
void bindBatch(py::module_& m);
/// Makes every class of the module raise TypeError, instead of crashing, when a method is
/// called on an instance made by __new__ without __init__. Call it after binding them all.
void guardModuleClasses(py::module_& m);

/// The World class object, for files that add methods to it.
py::class_<PyWorld> worldClass(py::module_& m);

}  // namespace inertia::python
