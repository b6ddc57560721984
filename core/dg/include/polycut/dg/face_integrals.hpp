// Exact face integrals of the DG face terms (003 eq. 11-13): for a face F between cells K- and
// K+ (or a boundary face of one cell), the scalar integrals
//   S^{st}(i, j) = int_F phi^s_i phi^t_j          (penalty, eq. 13)
//   P^{st}_k(i, j) = int_F phi^s_i d_k phi^t_j      (consistency and symmetry, eq. 11-12)
// for sides s, t in {-, +}, computed by expressing both cells' bases in the face's own local
// coordinates and integrating their products against the face's monomial moments.
#pragma once

#include "polycut/dg/cell_basis.hpp"

#include <array>
#include <span>

namespace polycut::dg {

/// Scalar face integrals of one face (sides: 0 = owner K-, 1 = neighbour K+).
struct FaceIntegrals {
    int sides = 2; ///< 1 for a boundary face
    Vec3 normal = Vec3::Zero(); ///< unit normal, outward from the owner
    double area = 0; ///< |F| [m^2]
    std::array<std::array<MatX, 2>, 2> S; ///< S[s][t] (nb_s x nb_t) [m^2]
    std::array<std::array<std::array<MatX, 3>, 2>, 2> P; ///< P[s][t][k] (nb_s x nb_t) [m]
    std::array<VecX, 2> mean; ///< int_F phi^s_i (nb_s) [m^2]
    /// Face frame: zeta = (x - origin) / scale, and the face's moments up to degree 2p there.
    Vec3 origin = Vec3::Zero();
    double scale = 1;
    VecX moments;
    /// Values and gradients of each side's basis as polynomials in zeta: values[s] (nb x
    /// num_monomials(p)), gradients[s][k] (nb x num_monomials(p - 1)) [1/m].
    std::array<MatX, 2> values;
    std::array<std::array<MatX, 3>, 2> gradients;
};

/// Integrals of face loop `loop` (outward for the owner, indices into `points`); `neighbour`
/// null for a boundary face.
FaceIntegrals face_integrals(const std::vector<Vec3>& points, std::span<const Index> loop,
    const CellBasis& owner, const CellBasis* neighbour);

/// The face as planar parts: itself when planar, else the triangles joining its mean point to
/// each edge (is_planar(), the same pieces the volume moments use), each with its own normal.
std::vector<FaceIntegrals> face_integral_parts(const std::vector<Vec3>& points,
    std::span<const Index> loop, const CellBasis& owner, const CellBasis* neighbour);

} // namespace polycut::dg
