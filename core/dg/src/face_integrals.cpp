// Face integrals of the DG face terms (face_integrals.hpp).
#include "polycut/dg/face_integrals.hpp"

#include "polycut/dg/polyhedron_moments.hpp"
#include "polycut/dg/polynomial.hpp"

namespace polycut::dg {

FaceIntegrals face_integrals(const std::vector<Vec3>& points, std::span<const Index> loop,
    const CellBasis& owner, const CellBasis* neighbour) {
    FaceIntegrals fi;
    fi.sides = neighbour ? 2 : 1;
    fi.normal = polygon_normal(points, loop, &fi.area);
    for (Index v : loop)
        fi.origin += points[std::size_t(v)];
    fi.origin /= double(loop.size());
    fi.scale = 0;
    for (Index v : loop)
        fi.scale = std::max(fi.scale, (points[std::size_t(v)] - fi.origin).norm());
    const int p = std::max(owner.degree, neighbour ? neighbour->degree : 0);
    fi.moments = polygon_moments(points, loop, fi.origin, fi.scale, 2 * p);
    const MatX Q = monomial_gram(fi.moments, p);
    const int n_values = num_monomials(p), n_grads = num_monomials(p - 1);

    const CellBasis* side[2] = { &owner, neighbour };
    for (int s = 0; s < fi.sides; ++s) {
        const CellBasis& b = *side[s];
        // xi = (x - c) / h = (origin - c) / h + (scale / h) zeta
        const MatX R = rebase_matrix(p, (fi.origin - b.center) / b.scale, fi.scale / b.scale);
        const int nm = num_monomials(b.degree);
        fi.values[std::size_t(s)] = b.T * R.topRows(nm);
        for (int k = 0; k < 3; ++k) {
            const MatX D = derivative_matrix(b.degree, k); // nm x nm(p_b - 1)
            fi.gradients[std::size_t(s)][std::size_t(k)]
                = b.T * D * R.topLeftCorner(D.cols(), n_grads) / b.scale;
        }
        fi.mean[std::size_t(s)] = fi.values[std::size_t(s)] * fi.moments.head(n_values);
    }
    for (int s = 0; s < fi.sides; ++s) {
        const MatX VQ = fi.values[std::size_t(s)] * Q; // nb_s x n_values
        for (int t = 0; t < fi.sides; ++t) {
            fi.S[std::size_t(s)][std::size_t(t)] = VQ * fi.values[std::size_t(t)].transpose();
            for (int k = 0; k < 3; ++k)
                fi.P[std::size_t(s)][std::size_t(t)][std::size_t(k)] = VQ.leftCols(n_grads)
                    * fi.gradients[std::size_t(t)][std::size_t(k)].transpose();
        }
    }
    return fi;
}

std::vector<FaceIntegrals> face_integral_parts(const std::vector<Vec3>& points,
    std::span<const Index> loop, const CellBasis& owner, const CellBasis* neighbour) {
    if (is_planar(points, loop))
        return { face_integrals(points, loop, owner, neighbour) };
    Vec3 mean = Vec3::Zero();
    for (Index v : loop)
        mean += points[std::size_t(v)] / double(loop.size());
    std::vector<FaceIntegrals> parts;
    const Index tri[3] = { 0, 1, 2 };
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const std::vector<Vec3> corners = { mean, points[std::size_t(loop[i])],
            points[std::size_t(loop[(i + 1) % loop.size()])] };
        parts.push_back(face_integrals(corners, tri, owner, neighbour));
    }
    return parts;
}

} // namespace polycut::dg
