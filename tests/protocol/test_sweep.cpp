// Sweep-triangle quality: analytic values, scale invariance, degenerate cases swept.
#include "polycut/protocol/sweep.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>

namespace polycut::protocol {
namespace {

TEST(ProtocolSweep, QualityAnalyticValues) {
    const double h = std::sqrt(3.0) / 2.0;
    EXPECT_NEAR(
        triangle_quality(Triangle3 { { { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, h, 0 } } }), 1.0, 1e-14);
    // Right isosceles, legs 1: area 1/2, sum of squared edges 4 -> q = sqrt(3)/2.
    EXPECT_NEAR(triangle_quality(Triangle3 { { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } } }),
        std::sqrt(3.0) / 2.0, 1e-14);
}

TEST(ProtocolSweep, QualityIsScaleAndRotationInvariant) {
    const Triangle3 t { { { 0, 0, 0 }, { 2, 0, 0 }, { 0.3, 0.7, 0 } } };
    const double q = triangle_quality(t);
    for (double s : { 1e-6, 1e-3, 1e3 }) {
        Triangle3 scaled = t;
        for (auto& p : scaled) {
            // scale and rotate 90 degrees about x: (x, y, z) -> (x, -z, y)
            p = { s * p[0], -s * p[2], s * p[1] };
        }
        EXPECT_NEAR(triangle_quality(scaled), q, 1e-12 * q);
        EXPECT_FALSE(triangle_defect(scaled).has_value());
    }
}

TEST(ProtocolSweep, DegenerateCases) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(triangle_defect(Triangle3 { { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 } } }));
    EXPECT_TRUE(triangle_defect(Triangle3 { { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 1, 0 } } }));
    EXPECT_TRUE(triangle_defect(Triangle3 { { { 1, 1, 1 }, { 1, 1, 1 }, { 1, 1, 1 } } }));
    EXPECT_TRUE(triangle_defect(Triangle3 { { { 0, 0, 0 }, { 1, 0, 0 }, { nan, 1, 0 } } }));
    // A needle: height 1e-9 over base 1 -> q ~ 3.5e-9 < 1e-6.
    EXPECT_TRUE(triangle_defect(Triangle3 { { { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, 1e-9, 0 } } }));
    // A thin but valid scalpel sweep: 2 cm blade moved 0.1 mm -> q ~ 8.7e-3.
    const Triangle3 sweep { { { 0, 0, 0 }, { 0, 0, -0.02 }, { 1e-4, 0, 0 } } };
    EXPECT_FALSE(triangle_defect(sweep).has_value());
    EXPECT_GT(triangle_quality(sweep), 1e-3);
}

} // namespace
} // namespace polycut::protocol
