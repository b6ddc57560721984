// The completeness measure of issue 12 item 4 (cut/completeness.hpp) against closed forms: the
// area of sweep triangles inside a 2 x 2 x 2 block of unit cells (hex and Kuhn tets), in general
// position, half outside, lying in an interior grid plane (counted once) and in the skin (not
// counted), and the Cut-face area of a through cut.
#include "polycut/cut/completeness.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>

namespace polycut::cut {
namespace {

mesh::Mesh block(bool tets) {
    mesh::BoxGrid g;
    g.hi = Vec3(2, 2, 2);
    g.cells = Eigen::Vector3i(2, 2, 2);
    return tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
}

class AreaInside : public ::testing::TestWithParam<bool> { };

TEST_P(AreaInside, MatchesClosedForms) {
    const mesh::Mesh m = block(GetParam());
    // Oblique plane x + y + z = 3 cut by the block: a triangle well inside it, area exact.
    const Triangle inside { Vec3(1.5, 1, 0.5), Vec3(0.5, 1.5, 1), Vec3(1, 0.5, 1.5) };
    const double a = 0.5 * (inside[1] - inside[0]).cross(inside[2] - inside[0]).norm();
    EXPECT_NEAR(area_inside(m, inside), a, 1e-12);
    // Half outside: the square x in [1, 3], z in [0.5, 1.5] at y = 0.7 as two triangles; the
    // part x <= 2 is inside: 1 x 1.
    const Triangle t1 { Vec3(1, 0.7, 0.5), Vec3(3, 0.7, 0.5), Vec3(3, 0.7, 1.5) };
    const Triangle t2 { Vec3(1, 0.7, 0.5), Vec3(3, 0.7, 1.5), Vec3(1, 0.7, 1.5) };
    EXPECT_NEAR(area_inside(m, t1) + area_inside(m, t2), 1.0, 1e-12);
    // In the interior grid plane y = 1 (faces shared by two cells): counted once.
    const Triangle mid { Vec3(0.2, 1, 0.2), Vec3(1.8, 1, 0.2), Vec3(0.2, 1, 1.8) };
    EXPECT_NEAR(area_inside(m, mid), 0.5 * 1.6 * 1.6, 1e-12);
    // In the skin y = 0: not inside.
    const Triangle skin { Vec3(0.2, 0, 0.2), Vec3(1.8, 0, 0.2), Vec3(0.2, 0, 1.8) };
    EXPECT_NEAR(area_inside(m, skin), 0.0, 1e-12);
    // Outside altogether.
    const Triangle out { Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5) };
    EXPECT_EQ(area_inside(m, out), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Cells, AreaInside, ::testing::Values(false, true),
    [](const ::testing::TestParamInfo<bool>& param) {
        return param.param ? std::string("KuhnTets") : std::string("Hexes");
    });

TEST(CutFaceArea, ThroughCutOpensTwiceTheSweptArea) {
    mesh::Mesh m = block(false);
    EXPECT_EQ(cut_face_area(m), 0.0);
    // A plane x = 0.6 through the whole block, swept by two triangles reaching beyond it.
    const std::vector<Triangle> sweep { { Vec3(0.6, -1, -1), Vec3(0.6, 3, -1), Vec3(0.6, 3, 3) },
        { Vec3(0.6, -1, -1), Vec3(0.6, 3, 3), Vec3(0.6, -1, 3) } };
    double swept = 0;
    for (const Triangle& t : sweep)
        swept += area_inside(m, t);
    EXPECT_NEAR(swept, 4.0, 1e-12); // the block's 2 x 2 cross-section
    cut_rest(m, sweep);
    EXPECT_NEAR(cut_face_area(m), 2 * swept, 1e-9);
}

} // namespace
} // namespace polycut::cut
