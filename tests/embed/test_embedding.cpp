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
