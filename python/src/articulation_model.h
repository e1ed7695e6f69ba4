// Articulation models as Python holds them (articulation_model.cpp), shared with the World's
// articulations (articulations.cpp).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

#include "inertia/articulation/model.h"
#include "inertia/world/world.h"

namespace inertia::python {

namespace py = pybind11;

/// inertia.ArticulationModel: the library's model (the tree of links, their joints and mass
/// properties) and the links' collision shapes, which a World gives to the link bodies.
struct PyModel {
  articulation::Model<Real> model;
  std::vector<LinkShapeSettings> shapes;
};

/// A vector of n finite Reals from any sequence or array; ValueError naming `arg` otherwise.
articulation::VectorX<Real> toVector(py::handle value, const char* arg, int n);
/// A configuration q of `model` (size nq, finite, quaternions not zero); ValueError naming
/// `arg` otherwise.
articulation::VectorX<Real> toConfiguration(const articulation::Model<Real>& model,
                                            py::handle value, const char* arg);
/// A link index of `model` from an int or a link name; ValueError naming `arg` otherwise.
int toLink(const articulation::Model<Real>& model, py::handle value, const char* arg);
/// A copy of v as a new NumPy array.
py::array fromVector(const articulation::VectorX<Real>& v);

void bindArticulationModel(py::module_& m);
void bindArticulations(py::module_& m);

}  // namespace inertia::python
