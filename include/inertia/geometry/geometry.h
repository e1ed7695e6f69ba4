// The geometry layer: shapes, their bounds, support functions and mass properties.
#pragma once

#include "inertia/geometry/bounds.h"
#include "inertia/geometry/height_field.h"
#include "inertia/geometry/hull.h"
#include "inertia/geometry/mass.h"
#include "inertia/geometry/mesh.h"
#include "inertia/geometry/shapes.h"
#include "inertia/geometry/support.h"
