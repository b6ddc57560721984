// Settings of the algebraic multigrid preconditioner: defined in the options layer
// (docs/decisions/0051) so that core/scene can take its defaults from them.
#pragma once

#include "polycut/options/solve.hpp"
