// The stabilisation of polyhedral cells (BasisOptions::stabilization, issue 12): a cell a cut
// left with two nodes micrometres apart has deformation modes of almost no energy under the mean
// value basis; the stabilisation lifts them and leaves affine fields alone.
#include "helpers.hpp"

#include <Eigen/Eigenvalues>
#include <cstdio>

using namespace polycut;
using namespace polycut::elasticity;

namespace {
Material material() {
    Material m;
    m.youngs_modulus = 3e4;
    m.poisson_ratio = 0.45;
    m.density = 1000;
    return m;
}

/// A cell the cell-splitting cutter made in the blob organ (issue 12: default material, cell
/// size 2.8 mm, a blade at y = plane + 2.5 mm): the wedge between the cut plane and two grid
/// nodes 70 and 150 um beside it, 4 mm long and 0.2 mm thick, rest positions [m] as the cutter
/// left them. Its mean value stiffness had three modes below 1e-6 of its mean; corotation pumped
/// energy into them until the organ exploded.
mesh::Mesh wedge_from_an_organ_cut() {
    std::vector<Vec3> X {
        { -2.372560223e-02, -1.497726632e-03, 3.927288884e-02 },
        { -2.002183385e-02, -1.574391631e-03, 3.713966029e-02 },
        { -2.004368608e-02, -1.646919794e-03, 3.715790077e-02 },
        { -1.998868920e-02, -1.653027613e-03, 3.749090100e-02 },
        { -2.358349758e-02, -1.681467329e-03, 3.920505011e-02 },
        { -2.286612690e-02, -1.689277619e-03, 3.960337966e-02 },
        { -2.012191861e-02, -1.647683321e-03, 3.720314433e-02 },
        { -2.013123721e-02, -1.654823435e-03, 3.759555300e-02 },
    };
    const std::vector<std::vector<Index>> faces {
        { 2, 1, 3 },
        { 5, 0, 4 },
        { 4, 0, 1, 2, 6 },
        { 3, 1, 0, 5, 7 },
        { 5, 4, 6, 7 },
        { 6, 2, 3, 7 },
    };
    return mesh::Mesh::from_polyhedra(std::move(X), { faces });
}

/// A 3 mm cube whose edge from corner 0 to corner 1 carries an extra node 0.4 mm from corner 0:
/// one polyhedral cell of 9 nodes.
mesh::Mesh cube_with_edge_node() {
    const double a = 3e-3, gap = 0.4e-3;
    std::vector<Vec3> X { { 0, 0, 0 }, { a, 0, 0 }, { a, a, 0 }, { 0, a, 0 }, { 0, 0, a },
        { a, 0, a }, { a, a, a }, { 0, a, a }, { gap, 0, 0 } };
    // Outward loops (kHexFaces) with node 8 inserted between 0 and 1.
    const std::vector<std::vector<Index>> faces { { 0, 3, 2, 1, 8 }, { 4, 5, 6, 7 },
        { 0, 8, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 }, { 3, 0, 4, 7 } };
    return mesh::Mesh::from_polyhedra(std::move(X), { faces });
}

/// Eigenvalues of cell 0's stiffness, ascending, divided by its mean diagonal entry.
VecX relative_spectrum(const mesh::Mesh& m, double stabilization) {
    basis::BasisOptions o;
    o.stabilization = stabilization;
    const ElasticModel model(m, material(), o, {});
    const MatX K = model.cell_stiffness(0);
    const Eigen::SelfAdjointEigenSolver<MatX> es(K, Eigen::EigenvaluesOnly);
    return es.eigenvalues() / (K.trace() / double(K.rows()));
}
} // namespace

TEST(Stabilization, LiftsTheNearZeroModesOfAWedgeACutMade) {
    const mesh::Mesh m = wedge_from_an_organ_cut();
    ASSERT_GT(m.cell_volume(0), 0.0);
    ASSERT_EQ(m.cells[0].shape, mesh::CellShape::Polyhedron);
    const VecX off = relative_spectrum(m, 0.0);
    const VecX on = relative_spectrum(m, 0.005);
    // Six rigid modes either way (to round-off).
    for (int i = 0; i < 6; ++i) {
        EXPECT_LT(std::abs(off(i)), 1e-9) << i;
        EXPECT_LT(std::abs(on(i)), 1e-9) << i;
    }
    // Without it, three deformation modes cost next to nothing (below 1e-6 of the mean diagonal
    // entry); with it, every non-affine mode costs at least the stabilisation's share
    // tau x tr(Ke) / 3n = 0.005 of it, and the softest mode left is one of the wedge's six
    // affine strains (measured 1.6e-3: a 0.2 mm thick cell is soft across itself).
    EXPECT_LT(off(8), 1e-6) << "the unstabilised wedge should have three near-zero modes";
    for (Index i = 6; i < on.size(); ++i)
        EXPECT_GT(on(i), 1e-3) << i;
    std::printf("[ info ] wedge: 7th-9th eigenvalues / mean diagonal %.3g %.3g %.3g without, %.3g "
                "%.3g %.3g with\n",
        off(6), off(7), off(8), on(6), on(7), on(8));
}

TEST(Stabilization, LeavesAffineFieldsAndRigidMotionsUntouched) {
    const mesh::Mesh m = cube_with_edge_node();
    basis::BasisOptions o0, o1;
    o0.stabilization = 0.0;
    o1.stabilization = 0.05;
    const ElasticModel plain(m, material(), o0, {}), stabilized(m, material(), o1, {});
    const MatX K0 = plain.cell_stiffness(0), K1 = stabilized.cell_stiffness(0);
    // The stabilisation changed the matrix...
    EXPECT_GT((K1 - K0).norm(), 1e-3 * K0.norm());
    // ...but not its action on an affine displacement u = B X + c (the patch test): K u equal
    // to round-off.
    Mat3 B;
    B << 0.02, -0.01, 0.03, 0.015, -0.02, 0.01, -0.005, 0.025, 0.01;
    const Vec3 c(1e-4, -2e-4, 3e-4);
    const auto& nodes = m.cells[0].nodes;
    VecX u(3 * Index(nodes.size()));
    for (std::size_t i = 0; i < nodes.size(); ++i)
        u.segment<3>(3 * Index(i)) = B * m.rest[std::size_t(nodes[i])] + c;
    EXPECT_LT((K1 * u - K0 * u).norm(), 1e-10 * (K0 * u).norm());
    // And it is symmetric positive semi-definite with exactly six zero modes.
    EXPECT_LT((K1 - K1.transpose()).norm(), 1e-12 * K1.norm());
    const VecX ev = relative_spectrum(m, 0.05);
    EXPECT_LT(std::abs(ev(5)), 1e-9);
    EXPECT_GT(ev(6), 1e-3);
}
