// Umbrella header: everything in tricell::core.
#pragma once

#include "tricell/box.hpp"
#include "tricell/error.hpp"
#include "tricell/types.hpp"
