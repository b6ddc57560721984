// The sparse matrix type of assembly and solvers: compressed sparse column, double, full
// symmetric storage (both triangles), 32-bit indices. Here in common so that a model can hand
// out matrices without linking the solvers (CHOLMOD, hypre and MPI stay behind polycut::solve,
// which names the same type solve::SparseMatrix).
#pragma once

#include <Eigen/SparseCore>

namespace polycut {

/// Sparse matrix (n x n, CSC, full symmetric storage, int indices).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

} // namespace polycut
