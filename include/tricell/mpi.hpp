// tricell::mpi: neighbour search over MPI ranks by domain decomposition in fractional space.
// Umbrella header (link tricell::mpi). See the headers in tricell/mpi/ for each piece.
#pragma once

#include "tricell/mpi/atoms.hpp"
#include "tricell/mpi/balance.hpp"
#include "tricell/mpi/decomposition.hpp"
#include "tricell/mpi/halo.hpp"
#include "tricell/mpi/neighbors.hpp"
#include "tricell/mpi/verlet.hpp"
