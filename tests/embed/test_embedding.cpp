// The embedded surface follows its cells' bases (issue 15 item 2): a rigid motion and a general
// affine deformation of the nodes move every embedded vertex exactly as they move its rest
// position, in tets (P1), hexes (Q1), mean value and harmonic polyhedra, and for vertices just
// outside the mesh (affine fit of the nearest cell).
#include "polycut/embed/embedding.hpp"
#include "polycut/mesh/builders.hpp"
#include "uv_sphere.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using test::uv_sphere;

namespace {
struct Case {
    const char* name;
    int kind; ///< 0 tet grid, 1 hex grid, 2 merged hexes (mean value), 3 merged (harmonic)
};

class Reproduction : public ::testing::TestWithParam<Case> { };

/// The largest distance [m] between an embedded vertex moved with the nodes of `m` by a fixed
/// general affine map and the same map applied to the vertex's rest position.
double worst_affine_error(const embed::Embedding& e, const mesh::Mesh& m) {
    Mat3 A;
    A << 1.2, 0.3, -0.1, 0.05, 0.8, 0.2, -0.15, 0.1, 1.1;
    const Vec3 shift(0.3, -0.1, 0.05);
    std::vector<Vec3> x;
    for (const Vec3& X : m.rest)
        x.push_back(A * X + shift);
    double worst = 0;
    for (std::size_t i = 0; i < e.rest.size(); ++i)
        worst = std::max(worst, (embed::deformed_vertex(e, x, i) - (A * e.rest[i] + shift)).norm());
    return worst;
}
} // namespace

TEST_P(Reproduction, RigidAndAffineMotionsAreExact) {
    mesh::BoxGrid g;
    g.lo = Vec3(0, 0, 0);
    g.hi = Vec3(0.04, 0.03, 0.03);
    g.cells = Eigen::Vector3i(4, 3, 3);
    const int kind = GetParam().kind;
    const mesh::Mesh m = kind == 0 ? mesh::tet_grid(g)
        : kind == 1                ? mesh::hex_grid(g)
                                   : mesh::merged_hex_grid(g, 0.6, 3);
    // A sphere that pokes 1 mm out of the box at +-x and 6 mm at +-y, +-z (outside vertices).
    std::vector<Vec3> v;
    std::vector<std::array<Index, 3>> t;
    uv_sphere(Vec3(0.02, 0.015, 0.015), 0.021, 24, 48, v, t);
    const embed::Embedding e = embed::embed_surface(
        m, v, t, kind == 3 ? basis::PolyBasis::Harmonic : basis::PolyBasis::MeanValue);
    ASSERT_EQ(e.rest.size(), v.size());
    EXPECT_GT(e.outside, 0);
    EXPECT_LT(e.max_outside_distance, 0.0061);
    // Weights sum to one (partition of unity of every basis and of the affine fit).
    for (std::size_t i = 0; i + 1 < e.offsets.size(); ++i) {
        double sum = 0;
        for (std::uint32_t k = e.offsets[i]; k < e.offsets[i + 1]; ++k)
            sum += e.weights[k];
        ASSERT_NEAR(sum, 1.0, 1e-9) << i;
    }
    const Mat3 R = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
    Mat3 A;
    A << 1.2, 0.3, -0.1, 0.05, 0.8, 0.2, -0.15, 0.1, 1.1;
    const Vec3 shift(0.3, -0.1, 0.05);
    for (const Mat3& F : { R, A }) {
        std::vector<Vec3> x;
        for (const Vec3& X : m.rest)
            x.push_back(F * X + shift);
        double worst = 0;
        for (std::size_t i = 0; i < e.rest.size(); ++i)
            worst = std::max(
                worst, (embed::deformed_vertex(e, x, i) - (F * e.rest[i] + shift)).norm());
        EXPECT_LT(worst, 1e-12) << GetParam().name; // [m], on a 4 cm box
    }
}

INSTANTIATE_TEST_SUITE_P(Bases, Reproduction,
    ::testing::Values(Case { "p1_tets", 0 }, Case { "q1_hexes", 1 }, Case { "mean_value", 2 },
        Case { "harmonic", 3 }),
    [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(Embedding, APointOnTheCornerOfACutHexPieceTakesThatCorner) {
    // A cut piece with a hexahedron's faces is a Hex (Mesh::classify_cell) and its points take
    // trilinear weights by Newton on its map. The piece below (node order VTK, coordinates as
    // the live case had them) is so warped that Newton, started at its centre, did not reach its
    // node 6 from there: weights up to 2.2e9, and the skin vertex on that node came out 2e7 m
    // away (organ_embedded, cell splitting, 4 frames). A point on a node takes that node; all
    // follow an affine motion.
    const std::vector<Vec3> rest { { -0.019381533941272108, -0.012350499604351164,
                                       0.017546899883631256 },
        { -0.014718646027865628, -0.010652811186395689, 0.010379288629181247 },
        { -0.013885230330046489, -0.011526336515270387, 0.0073828167033083234 },
        { -0.020729842448680771, -0.014825063851087523, 0.016728345191229441 },
        { -0.019651054787077363, -0.012235068934718313, 0.017012547249666585 },
        { -0.019306415790258154, -0.010756879282638023, 0.010473911796887423 },
        { -0.020618086315536008, -0.010786632967223899, 0.01050096512051016 },
        { -0.022157415828903643, -0.011161642007256292, 0.01204343022139035 } };
    const mesh::Mesh m = mesh::Mesh::from_hexes(rest, { { 0, 1, 2, 3, 4, 5, 6, 7 } });
    ASSERT_EQ(m.cells[0].shape, mesh::CellShape::Hex);
    const std::vector<Vec3> points { rest[6], rest[6] + Vec3(1e-13, -2e-13, 1e-13) };
    const embed::Embedding e = embed::embed_points(m, points, basis::PolyBasis::MeanValue);
    for (std::uint32_t k = e.offsets[0]; k < e.offsets[1]; ++k)
        EXPECT_EQ(e.weights[k], m.rest[std::size_t(e.nodes[k])] == rest[6] ? 1.0 : 0.0);
    for (const double w : e.weights)
        EXPECT_LE(std::abs(w), 10.0);
    EXPECT_LT(worst_affine_error(e, m), 1e-12);
}

TEST(Embedding, PointsOnAndBesideTheFacesOfPolyhedraKeepSaneWeights) {
    // A vertex that a cut's split of the surface puts on a Cut face lies on a face, an edge or
    // a corner of its polyhedral cell, where mean value coordinates divide by its distance to
    // them (they take a point within 1e-12 of the cell's size as on the surface). Points at
    // each face's centroid, corner and edge middle, and 1e-14 .. 1e-6 of the way from them to
    // the cell's centre: every weight within 10 in size, and an affine motion reproduced to
    // 1e-9 m.
    mesh::BoxGrid g;
    g.lo = Vec3(0, 0, 0);
    g.hi = Vec3(0.04, 0.03, 0.03);
    g.cells = Eigen::Vector3i(4, 3, 3);
    const mesh::Mesh m = mesh::merged_hex_grid(g, 0.6, 3);
    std::vector<Vec3> points;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const mesh::Cell& cell = m.cells[std::size_t(c)];
        if (cell.nodes.size() <= 8)
            continue; // a hex (trilinear) or a tet: not a polyhedron's basis
        Vec3 centre = Vec3::Zero();
        for (const Index n : cell.nodes)
            centre += m.rest[std::size_t(n)] / double(cell.nodes.size());
        for (const Index f : cell.faces) {
            const auto& loop = m.faces[std::size_t(f)].nodes;
            Vec3 fc = Vec3::Zero();
            for (const Index n : loop)
                fc += m.rest[std::size_t(n)] / double(loop.size());
            // the face's centroid, its first corner and the middle of its first edge
            for (const Vec3& p : { fc, m.rest[std::size_t(loop[0])],
                     Vec3(0.5 * (m.rest[std::size_t(loop[0])] + m.rest[std::size_t(loop[1])])) })
                for (const double s : { 0.0, 1e-14, 1e-12, 1e-10, 1e-8, 1e-6 })
                    points.push_back(p + s * (centre - p));
        }
    }
    ASSERT_GT(points.size(), 100u);
    const embed::Embedding e = embed::embed_points(m, points, basis::PolyBasis::MeanValue);
    double largest = 0;
    for (const double w : e.weights)
        largest = std::max(largest, std::abs(w));
    EXPECT_LE(largest, 10.0);
    EXPECT_LT(worst_affine_error(e, m), 1e-9);
}
