// Umbrella header: everything in tricell::core.
#pragma once

#include "tricell/analysis/nearest.hpp"
#include "tricell/analysis/rdf.hpp"
#include "tricell/analysis/shells.hpp"
#include "tricell/batch.hpp"
#include "tricell/box.hpp"
#include "tricell/cell_list.hpp"
#include "tricell/displacement.hpp"
#include "tricell/error.hpp"
#include "tricell/grid.hpp"
#include "tricell/neighbor_list.hpp"
#include "tricell/stencil.hpp"
#include "tricell/tuning.hpp"
#include "tricell/types.hpp"
#include "tricell/verify.hpp"
#include "tricell/verlet.hpp"
