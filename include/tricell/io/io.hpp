// Umbrella header: everything in tricell::io (link tricell::io).
#pragma once

#include "tricell/io/coordination.hpp"
#include "tricell/io/structure.hpp"
#include "tricell/io/symmetry.hpp"
#include "tricell/io/trajectory.hpp"
