// A cell's small-strain stress from the affine fit of its nodes' motion.
#include "cell_stress.hpp"

#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"

namespace polycut::sim {

Mat3 cell_stress(const elasticity::Material& material, bool corotated, const mesh::Mesh& m,
    const std::vector<Vec3>& positions, Index c, Mat3* rotation) {
    const auto& cell = m.cells[std::size_t(c)];
    const auto fit = geometry::fit_affine(
        geometry::gather(m.rest, cell.nodes), geometry::gather(positions, cell.nodes));
    const Mat3 R = corotated ? geometry::polar_rotation(fit.A) : Mat3::Identity();
    const Mat3 F = R.transpose() * fit.A;
    const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
    if (rotation)
        *rotation = R;
    return material.lambda() * eps.trace() * Mat3::Identity() + 2.0 * material.mu() * eps;
}

} // namespace polycut::sim
