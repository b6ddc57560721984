// Camera conventions and automatic framing.
#include "polycut/common/error.hpp"
#include "polycut/render/camera.hpp"

#include <gtest/gtest.h>

namespace polycut::render::test {
namespace {

TEST(Camera, TargetProjectsToImageCentre) {
    Camera camera;
    camera.position = Vec3(1, 2, 3);
    camera.target = Vec3(0.5, -1, 0.2);
    const Vec3 p = camera.project(camera.target, 640, 480);
    EXPECT_NEAR(p.x(), 320, 1e-9);
    EXPECT_NEAR(p.y(), 240, 1e-9);
    EXPECT_NEAR(p.z(), (camera.target - camera.position).norm(), 1e-12);
}

TEST(Camera, UpIsUpAndRightIsRight) {
    Camera camera;
    camera.position = Vec3(0, -1, 0); // looking along +y, z up: x is to the right
    camera.target = Vec3(0, 0, 0);
    EXPECT_LT(camera.project(Vec3(0, 0, 0.1), 100, 100).y(), 50);
    EXPECT_GT(camera.project(Vec3(0.1, 0, 0), 100, 100).x(), 50);
}

TEST(Camera, FieldOfViewMatchesProjection) {
    // A point on the edge of the vertical field of view projects to the top row.
    Camera camera;
    camera.position = Vec3(0, 0, 0);
    camera.target = Vec3(0, 1, 0);
    camera.fov_y_deg = 60;
    const Vec3 edge(0, 1, std::tan(30 * std::numbers::pi / 180));
    EXPECT_NEAR(camera.project(edge, 200, 100).y(), 0, 1e-9);
}

/// Framing an elongated box at several aspects keeps all corners inside the image and
/// fills at least 60 % of its width or height (1 / margin = 87 % on the limiting side; the
/// box centre stays at the image centre, so perspective leaves slack on the far side).
TEST(Camera, FrameFitsTheBoxTightly) {
    const Vec3 lo(-0.2, 0.1, 0.0);
    for (const Vec3& size : { Vec3(0.1, 0.06, 0.04), Vec3(0.5, 0.02, 0.02), Vec3(0.01, 0.01, 0.3) })
        for (const auto& [w, h] : { std::pair { 640, 480 }, { 480, 640 }, { 1000, 200 } }) {
            const Camera camera = frame(lo, lo + size, double(w) / h);
            EXPECT_NO_THROW(camera.validate());
            double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
            for (int c = 0; c < 8; ++c) {
                const Vec3 corner
                    = lo + Vec3(c & 1 ? size.x() : 0, c & 2 ? size.y() : 0, c & 4 ? size.z() : 0);
                const Vec3 p = camera.project(corner, w, h);
                x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
                y_min = std::min(y_min, p.y()), y_max = std::max(y_max, p.y());
                EXPECT_GT(p.z(), camera.near);
                EXPECT_LT(p.z(), camera.far);
            }
            EXPECT_GE(x_min, 0);
            EXPECT_LE(x_max, w);
            EXPECT_GE(y_min, 0);
            EXPECT_LE(y_max, h);
            EXPECT_GE(std::max((x_max - x_min) / w, (y_max - y_min) / h), 0.6)
                << "size " << size.transpose() << " image " << w << "x" << h;
            // Seen from above: the top of the box is nearer the top of the image.
            EXPECT_LT(
                camera.project(lo + Vec3(0, 0, size.z()), w, h).y(), camera.project(lo, w, h).y());
        }
}

TEST(Camera, BadCamerasAreRejected) {
    Camera camera;
    camera.target = camera.position;
    EXPECT_THROW(camera.validate(), InputError);
    camera = Camera {};
    camera.up = camera.target - camera.position;
    EXPECT_THROW(camera.validate(), InputError);
    camera = Camera {};
    camera.fov_y_deg = 0;
    EXPECT_THROW(camera.validate(), InputError);
    camera = Camera {};
    camera.far = camera.near;
    EXPECT_THROW(camera.validate(), InputError);
    camera = Camera {};
    camera.position.x() = std::nan("");
    EXPECT_THROW(camera.validate(), InputError);
    EXPECT_THROW(frame(Vec3(1, 0, 0), Vec3(0, 1, 1), 1.0), InputError);
}

} // namespace
} // namespace polycut::render::test
