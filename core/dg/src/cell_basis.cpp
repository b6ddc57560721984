// Orthonormalised monomial basis of a polyhedral cell (cell_basis.hpp).
#include "polycut/dg/cell_basis.hpp"

#include "polycut/common/error.hpp"
#include "polycut/dg/polyhedron_moments.hpp"
#include "polycut/dg/polynomial.hpp"

#include <Eigen/Cholesky>
#include <string>

namespace polycut::dg {

int basis_size(int degree) {
    return num_monomials(degree);
}

VecX CellBasis::values(const Vec3& x) const {
    return T * monomial_values(degree, (x - center) / scale);
}

MatX3 CellBasis::gradients(const Vec3& x) const {
    const VecX m = monomial_values(degree - 1, (x - center) / scale);
    MatX3 g(size(), 3);
    for (int axis = 0; axis < 3; ++axis)
        g.col(axis) = T * (derivative_matrix(degree, axis) * m) / scale;
    return g;
}

CellBasis make_cell_basis(const std::vector<Vec3>& points,
    const std::vector<std::vector<Index>>& loops, int degree, Index cell) {
    if (degree < 1 || degree > 2)
        throw InputError("basis.degree", "DG degree must be 1 or 2, got " + std::to_string(degree));
    // Centroid and size from a first pass about the vertex mean.
    Vec3 mean = Vec3::Zero();
    int count = 0;
    for (const auto& loop : loops)
        for (Index v : loop) {
            mean += points[std::size_t(v)];
            ++count;
        }
    if (count == 0)
        throw MeshError(cell, -1, "cell has no faces");
    mean /= double(count);
    double extent = 0;
    for (const auto& loop : loops)
        for (Index v : loop)
            extent = std::max(extent, (points[std::size_t(v)] - mean).norm());
    if (!(extent > 0))
        throw MeshError(cell, -1, "cell has zero extent");
    const VecX first = polyhedron_moments(points, loops, mean, extent, 1);
    if (!(first[0] > 0))
        throw MeshError(cell, -1, "cell has non-positive volume " + std::to_string(first[0]));

    CellBasis b;
    b.degree = degree;
    b.volume = first[0];
    b.center = mean + extent * first.segment<3>(1) / first[0];
    b.scale = 0;
    for (const auto& loop : loops)
        for (Index v : loop)
            b.scale = std::max(b.scale, (points[std::size_t(v)] - b.center).norm());
    b.moments = polyhedron_moments(points, loops, b.center, b.scale, 2 * degree);
    b.volume = b.moments[0];

    // Orthonormalise: G = L L^T, T = L^-1, twice (the second pass removes what round-off left
    // of the first on thin cells).
    const MatX G = monomial_gram(b.moments, degree) / b.volume;
    const int n = int(G.rows());
    MatX T = MatX::Identity(n, n);
    for (int pass = 0; pass < 2; ++pass) {
        const MatX Gt = T * G * T.transpose();
        Eigen::LLT<MatX> llt(Gt);
        if (llt.info() != Eigen::Success
            || !(llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 1e-7))
            throw MeshError(cell, -1,
                "DG basis of degree " + std::to_string(degree)
                    + " is degenerate on this cell (flat or collapsed)");
        const MatX Linv = llt.matrixL().solve(MatX::Identity(n, n));
        T = Linv * T;
    }
    // Keep phi_0 = 1 exactly (the Cholesky of a Gram with G00 = 1 gives it up to round-off).
    b.T = T;
    b.T.row(0).setZero();
    b.T(0, 0) = 1;
    return b;
}

MatX3 rest_coefficients(const CellBasis& basis) {
    // c_i = (1/|K|) int_K x phi_i, with x = center + scale * xi.
    const int n = basis.size();
    MatX3 X0 = MatX3::Zero(n, 3);
    const VecX& M = basis.moments;
    for (int i = 0; i < n; ++i) {
        double mean_phi = 0;
        Vec3 first = Vec3::Zero();
        for (int j = 0; j < n; ++j) {
            const auto& e = exponent(j);
            mean_phi += basis.T(i, j) * M[j];
            first[0] += basis.T(i, j) * M[monomial_index(e[0] + 1, e[1], e[2])];
            first[1] += basis.T(i, j) * M[monomial_index(e[0], e[1] + 1, e[2])];
            first[2] += basis.T(i, j) * M[monomial_index(e[0], e[1], e[2] + 1)];
        }
        X0.row(i) = ((basis.center * mean_phi + basis.scale * first) / basis.volume).transpose();
    }
    return X0;
}

} // namespace polycut::dg
