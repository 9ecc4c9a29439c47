// Umbrella header of the analysis built on the neighbour search (part of tricell::core):
// radial distribution functions, k nearest neighbours, lists at several cutoffs.
#pragma once

#include "tricell/analysis/nearest.hpp"
#include "tricell/analysis/rdf.hpp"
#include "tricell/analysis/shells.hpp"
