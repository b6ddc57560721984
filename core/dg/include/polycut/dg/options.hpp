// Options of the discontinuous Galerkin method (seed 003): defined in the options layer
// (docs/decisions/0051) so that core/scene can read scene files into them.
#pragma once

#include "polycut/options/dg.hpp"
