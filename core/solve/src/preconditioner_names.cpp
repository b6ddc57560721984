// The names of the PCG preconditioners, as scenes and reports spell them (docs/scenes.md).
#include "polycut/solve/pcg.hpp"

namespace polycut::solve {

const char* to_string(Preconditioner p) {
    switch (p) {
    case Preconditioner::None:
        return "none";
    case Preconditioner::Jacobi:
        return "jacobi";
    case Preconditioner::BlockJacobi3:
        return "block_jacobi3";
    case Preconditioner::LaggedCholesky:
        return "lagged_cholesky";
    case Preconditioner::IncompleteCholesky:
        return "incomplete_cholesky";
    case Preconditioner::Amg:
        return "amg";
    case Preconditioner::BlockJacobi:
        return "block_jacobi";
    case Preconditioner::TwoLevel:
        return "two_level";
    }
    return "unknown";
}

} // namespace polycut::solve
