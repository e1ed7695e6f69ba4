// inertia.Batch: N independent worlds (copies of a scene, or one scene each) stepped together
// in C++ across the cores with one call; state in and out as (N, bodies, ...) arrays. Each
// world steps on one thread and the worlds are shared out among the threads: a world's result
// does not depend on the thread count (the library's promise), so a batch gives the bits of
// stepping each world alone.
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "inertia/io/scene.h"

namespace inertia::python {

namespace {

class Batch {
 public:
  // `worlds` are the World objects the batch owns (kept alive with it); every one must have
  // the same number of bodies.
  Batch(std::vector<py::object> worlds, int threads)
      : objects_(std::move(worlds)), arena_(threads > 0 ? threads : tbb::task_arena::automatic) {
    for (py::object& o : objects_) {
      pyWorlds_.push_back(&o.cast<PyWorld&>());
      worlds_.push_back(pyWorlds_.back()->world.get());
    }
    if (worlds_.empty()) argumentError("scene", "a batch needs at least one world");
    bodies_ = worlds_[0]->bodyCount();
    for (std::size_t i = 0; i < worlds_.size(); ++i)
      if (worlds_[i]->bodyCount() != bodies_)
        argumentError("scenes", "world " + std::to_string(i) + " has " +
                                    std::to_string(worlds_[i]->bodyCount()) +
                                    " bodies, world 0 has " + std::to_string(bodies_) +
                                    ": the state arrays need the same count");
  }

  std::size_t size() const { return worlds_.size(); }
  int bodyCount() const { return bodies_; }
  py::object world(std::ptrdiff_t i) const {
    const auto n = std::ptrdiff_t(size());
    if (i < 0) i += n;
    if (i < 0 || i >= n) throw py::index_error("batch index out of range");
    return objects_[std::size_t(i)];
  }

  // RuntimeError while another thread steps the batch or one of its worlds.
  void checkIdle() const {
    for (const PyWorld* w : pyWorlds_)
      if (w->stepping) throw std::runtime_error("Batch: another thread is stepping its worlds");
  }

  void step(int steps) {
    if (steps < 0) argumentError("steps", "must be >= 0");
    checkIdle();
    {
      SteppingScope stepping(pyWorlds_);
      py::gil_scoped_release release;
      arena_.execute([&] {
        // One world per task: worlds are small, and each costs about the same.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, worlds_.size(), 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            for (std::size_t i = r.begin(); i != r.end(); ++i)
                              for (int s = 0; s < steps; ++s)
                                worlds_[i]->step(worlds_[i]->settings().dt);
                          });
      });
    }
    for (PyWorld* w : pyWorlds_)
      if (w->recipe && steps > 0) w->recipe->record(w->world->settings().dt, 0, steps);
  }

  // (N, bodies, cols) from each world's bodies in slot order.
  template <class Get>
  RealArray gather(py::ssize_t cols, Get get) const {
    checkIdle();
    RealArray a({py::ssize_t(size()), py::ssize_t(bodies_), cols});
    Real* out = a.mutable_data();
    for (World* w : worlds_)
      for (BodyId id : w->rigidBodies().bodies()) out = get(*w, id, out);
    return a;
  }

  template <class Set>
  void scatter(py::handle value, const char* arg, py::ssize_t cols, Set set) {
    checkIdle();
    RealArray a = RealArray::ensure(value);
    if (!a || a.ndim() != 3 || a.shape(0) != py::ssize_t(size()) || a.shape(1) != bodies_ ||
        a.shape(2) != cols)
      argumentError(arg, "expected an array of shape (" + std::to_string(size()) + ", " +
                             std::to_string(bodies_) + ", " + std::to_string(cols) + ")");
    const Real* in = a.data();
    for (World* w : worlds_)
      for (BodyId id : w->rigidBodies().bodies()) set(*w, id, in), in += cols;
    for (PyWorld* w : pyWorlds_) w->recipe.reset();  // changed from Python: not picklable
  }

 private:
  std::vector<py::object> objects_;
  std::vector<PyWorld*> pyWorlds_;  // of objects_
  std::vector<World*> worlds_;      // theirs, for the workers (which cannot touch Python)
  tbb::task_arena arena_;
  int bodies_ = 0;
};

// A scene's text and name (the file, for relative paths and messages), from a dict or a path.
std::pair<std::string, std::string> readScene(py::handle scene) {
  if (py::isinstance<py::dict>(scene))
    return {py::module_::import("json").attr("dumps")(scene).cast<std::string>(), "<scene>"};
  // A path (str or os.PathLike).
  const std::string path =
      py::str(py::module_::import("os").attr("fspath")(scene)).cast<std::string>();
  io::loadScene(path);  // SceneError with the file and pointer, before the recipe's read
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return {text.str(), path};
}

std::vector<py::object> makeWorlds(py::handle scenes, std::optional<std::size_t> n,
                                   py::handle gravity) {
  std::vector<std::pair<std::string, std::string>> texts;
  std::vector<std::size_t> which;  // the text of each world
  if (py::isinstance<py::list>(scenes) || py::isinstance<py::tuple>(scenes)) {
    if (n) argumentError("n", "give n with one scene, not with a list of scenes");
    for (py::handle s : scenes) which.push_back(texts.size()), texts.push_back(readScene(s));
  } else {
    texts.push_back(readScene(scenes));
    which.assign(n.value_or(1), 0);
  }
  std::vector<io::Scene> parsed;
  std::vector<std::shared_ptr<const std::string>> shared;  // one copy of each text
  for (const auto& [text, name] : texts) {
    parsed.push_back(io::parseScene(text, name));
    shared.push_back(std::make_shared<const std::string>(text));
  }
  std::optional<RealArray> g;
  if (!gravity.is_none()) g = toMatrix(gravity, "gravity", py::ssize_t(which.size()), 3);
  std::vector<py::object> worlds;
  for (std::size_t i = 0; i < which.size(); ++i) {
    // Each world remembers its scene (and the steps the batch takes) so that it pickles.
    Recipe r{shared[which[i]], texts[which[i]].second, std::nullopt, 1, std::nullopt, {}};
    if (g)
      r.gravity =
          Vec3(g->at(py::ssize_t(i), 0), g->at(py::ssize_t(i), 1), g->at(py::ssize_t(i), 2));
    io::Scene s = parsed[which[i]];
    s.world.threads = 1;  // the batch shares the cores out among the worlds
    if (r.gravity) s.world.gravity = *r.gravity;
    PyWorld w;
    w.world = io::instantiate(s);
    w.recipe = std::move(r);
    worlds.push_back(py::cast(std::move(w)));
  }
  return worlds;
}

}  // namespace

void bindBatch(py::module_& m) {
  py::class_<Batch>(m, "Batch",
                    "N independent worlds stepped together across the cores with one call. "
                    "Each world gives the bits it gives when stepped alone.")
      .def(py::init(
               [](py::handle scene, std::optional<std::size_t> n, py::handle gravity, int threads) {
                 return std::make_unique<Batch>(makeWorlds(scene, n, gravity), threads);
               }),
           py::arg("scene"), py::arg("n") = py::none(), py::kw_only(),
           py::arg("gravity") = py::none(), py::arg("threads") = 0,
           "scene: a scene file's path or a dict, copied n times; or a list of them, one world "
           "each (same body count). gravity: (N, 3) per world (m/s^2), overriding the scenes'. "
           "threads: how many step the batch (0: every core). Each world steps on one thread.")
      .def("__len__", &Batch::size)
      .def("__getitem__", &Batch::world, py::arg("i"),
           "World i, to read or change on its own (joint motors, forces, ...).")
      .def_property_readonly("body_count", &Batch::bodyCount, "Bodies per world.")
      .def("step", &Batch::step, py::arg("steps") = 1,
           "Steps every world `steps` times by its own dt.")
      .def(
          "positions",
          [](const Batch& b) {
            return b.gather(3,
                            [](World& w, BodyId id, Real* o) { return put(w.transform(id).p, o); });
          },
          "(N, bodies, 3) (m).")
      .def(
          "orientations",
          [](const Batch& b) {
            return b.gather(4,
                            [](World& w, BodyId id, Real* o) { return put(w.transform(id).q, o); });
          },
          "(N, bodies, 4), [w, x, y, z].")
      .def(
          "linear_velocities",
          [](const Batch& b) {
            return b.gather(
                3, [](World& w, BodyId id, Real* o) { return put(w.linearVelocity(id), o); });
          },
          "(N, bodies, 3) (m/s).")
      .def(
          "angular_velocities",
          [](const Batch& b) {
            return b.gather(
                3, [](World& w, BodyId id, Real* o) { return put(w.angularVelocity(id), o); });
          },
          "(N, bodies, 3) (rad/s).")
      .def(
          "set_positions",
          [](Batch& b, py::handle a) {
            b.scatter(a, "positions", 3, [](World& w, BodyId id, const Real* p) {
              Transform t = w.transform(id);
              t.p = Vec3(p[0], p[1], p[2]);
              w.rigidBodies().setTransform(id, t);
            });
          },
          py::arg("positions"), "(N, bodies, 3) (m).")
      .def(
          "set_orientations",
          [](Batch& b, py::handle a) {
            b.scatter(a, "orientations", 4, [](World& w, BodyId id, const Real* q) {
              Transform t = w.transform(id);
              t.q = Quat(q[0], q[1], q[2], q[3]);
              w.rigidBodies().setTransform(id, t);
            });
          },
          py::arg("orientations"), "(N, bodies, 4), [w, x, y, z].")
      .def(
          "set_linear_velocities",
          [](Batch& b, py::handle a) {
            b.scatter(a, "velocities", 3, [](World& w, BodyId id, const Real* v) {
              w.rigidBodies().setLinearVelocity(id, Vec3(v[0], v[1], v[2]));
            });
          },
          py::arg("velocities"), "(N, bodies, 3) (m/s).")
      .def(
          "set_angular_velocities",
          [](Batch& b, py::handle a) {
            b.scatter(a, "angular_velocities", 3, [](World& w, BodyId id, const Real* v) {
              w.rigidBodies().setAngularVelocity(id, Vec3(v[0], v[1], v[2]));
            });
          },
          py::arg("angular_velocities"), "(N, bodies, 3) (rad/s).");
}

}  // namespace inertia::python
