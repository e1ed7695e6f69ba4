// Inertia: the whole public API in one include.
#pragma once

#include "inertia/articulation/articulation.h"
#include "inertia/collision/queries.h"
#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/core/types.h"
#include "inertia/deformable/generators.h"
#include "inertia/ode/ode.h"
#include "inertia/world/builders.h"
#include "inertia/world/world.h"
