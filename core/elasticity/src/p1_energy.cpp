#include "p1_energy.hpp"

#include "polycut/elasticity/rotation.hpp"

namespace polycut::elasticity::detail {

double p1_energy(
    const P1TetView& tet, double lambda, double mu, const double* x, bool corotated, Mat3& R) {
    Mat3 F = Mat3::Zero();
    for (int i = 0; i < 4; ++i) {
        const double* xi = x + 3 * tet.nodes[i];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                F(a, b) += xi[a] * tet.g[i][b];
    }
    if (corotated)
        R = polar_rotation_warm(F, R);
    else
        R.setIdentity();
    Mat3 H = R.transpose() * F;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            H(a, b) -= tet.c0[a][b];
    const Mat3 eps = 0.5 * (H + H.transpose());
    const double tr = eps.trace();
    return tet.volume * (mu * eps.squaredNorm() + 0.5 * lambda * tr * tr);
}

} // namespace polycut::elasticity::detail
