// Shapes from Python values (shapes.cpp), for the files that take them.
#pragma once

#include <pybind11/pybind11.h>

#include "inertia/geometry/shapes.h"

namespace inertia::python {

namespace py = pybind11;

/// An inertia.Sphere, Box, ... as a Shape; ValueError naming `arg` for anything else.
Shape toShape(py::handle value, const char* arg);
/// A pose from an optional position (m) and orientation ([w, x, y, z]); None leaves each at
/// the identity.
Transform toPose(py::handle position, py::handle orientation);

}  // namespace inertia::python
