// The coarse space of the two-level DG preconditioner (dg_model.hpp coarse_space(),
// docs/decisions/0024): a continuous field given by one displacement per mesh node, carried to
// each cell as the least-squares affine fit of the cell's nodal values. Rows 0-3 of a cell's
// orthonormal basis span P1 (cell_basis.hpp), so the fit lives in them and rows 4+ (p = 2) are
// zero. On a tet the fit interpolates: the coarse space is the conforming P1 space, the CG-P1
// auxiliary space of DG multigrid. On hexes and polyhedra it is the per-cell affine part of the
// nodal field, with jumps across faces of the order of its second differences.
#include "polycut/dg/dg_model.hpp"

#include <Eigen/Dense>

namespace polycut::dg {

SparseMatrix DgModel::coarse_space() const {
    const mesh::Mesh& m = *m_mesh;
    // Columns: 3 per node that some cell uses (floating nodes left by cuts get none).
    std::vector<Index> column(std::size_t(m.num_nodes()), kNone);
    Index n_used = 0;
    for (const mesh::Cell& cell : m.cells)
        for (Index n : cell.nodes)
            if (column[std::size_t(n)] == kNone)
                column[std::size_t(n)] = n_used++;
    std::vector<Eigen::Triplet<double, int>> triplets;
    for (Index c = 0; c < num_cells(); ++c) {
        const CellBasis& b = basis(c);
        const std::vector<Index>& nodes = m.cells[std::size_t(c)].nodes;
        const Index k = Index(nodes.size());
        MatX E(k, 4); // E(q, j) = phi_j(X_q), j < 4: the affine functions
        for (Index q = 0; q < k; ++q)
            E.row(q) = b.values(m.rest[std::size_t(nodes[std::size_t(q)])]).head(4).transpose();
        const MatX fit = E.completeOrthogonalDecomposition().pseudoInverse(); // 4 x k
        for (int j = 0; j < 4; ++j)
            for (Index q = 0; q < k; ++q) {
                const double w = fit(j, q);
                if (w == 0)
                    continue;
                const Index col = column[std::size_t(nodes[std::size_t(q)])];
                for (int a = 0; a < 3; ++a)
                    triplets.emplace_back(int(dof(offset(c) + j, a)), int(3 * col + a), w);
            }
    }
    SparseMatrix P(int(3 * m_num_coeffs), int(3 * n_used));
    P.setFromTriplets(triplets.begin(), triplets.end());
    P.makeCompressed();
    return P;
}

} // namespace polycut::dg
