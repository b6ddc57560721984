// Camera matrices (gluLookAt / gluPerspective conventions) and automatic framing of a box.
#include "polycut/render/camera.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace polycut::render {

namespace {

double radians(double deg) {
    return deg * std::numbers::pi / 180.0;
}

bool finite(const Vec3& v) {
    return v.allFinite();
}

} // namespace

void Camera::validate() const {
    if (!finite(position))
        throw InputError("/camera/position", "not finite");
    if (!finite(target))
        throw InputError("/camera/target", "not finite");
    if (!finite(up) || up.norm() == 0)
        throw InputError("/camera/up", "not finite or zero");
    const Vec3 forward = target - position;
    if (!(forward.norm() > 0))
        throw InputError("/camera/target", "equals the camera position");
    if (forward.normalized().cross(up.normalized()).norm() < 1e-6)
        throw InputError("/camera/up", "parallel to the view direction");
    if (!(fov_y_deg > 0 && fov_y_deg < 180))
        throw InputError("/camera/fov_y_deg", "must be in (0, 180)");
    if (!(near > 0) || !std::isfinite(near))
        throw InputError("/camera/near", "must be positive and finite");
    if (!(far > near) || !std::isfinite(far))
        throw InputError("/camera/far", "must be finite and greater than near");
}

Eigen::Matrix4d Camera::view_matrix() const {
    const Vec3 f = (target - position).normalized();
    const Vec3 s = f.cross(up).normalized();
    const Vec3 u = s.cross(f);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(position);
    m(1, 3) = -u.dot(position);
    m(2, 3) = f.dot(position);
    return m;
}

Eigen::Matrix4d Camera::projection_matrix(double aspect) const {
    const double t = 1.0 / std::tan(radians(fov_y_deg) / 2);
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    m(0, 0) = t / aspect;
    m(1, 1) = t;
    m(2, 2) = (far + near) / (near - far);
    m(2, 3) = 2 * far * near / (near - far);
    m(3, 2) = -1;
    return m;
}

Vec3 Camera::project(const Vec3& point, int width, int height) const {
    const Eigen::Vector4d eye = view_matrix() * point.homogeneous();
    const Eigen::Vector4d clip = projection_matrix(double(width) / height) * eye;
    const double x_ndc = clip.x() / clip.w();
    const double y_ndc = clip.y() / clip.w();
    return { (x_ndc + 1) / 2 * width, (1 - y_ndc) / 2 * height, -eye.z() };
}

Camera frame(const Vec3& lo, const Vec3& hi, double aspect, const FrameOptions& options) {
    if (!finite(lo) || !finite(hi))
        throw InputError("frame: bounds", "not finite");
    if ((hi - lo).minCoeff() < 0)
        throw InputError("frame: bounds", "hi < lo");
    if (!(aspect > 0) || !std::isfinite(aspect))
        throw InputError("frame: aspect", "must be positive");
    if (!(options.margin >= 1))
        throw InputError("frame: margin", "must be >= 1");

    const Vec3 centre = (lo + hi) / 2;
    const double radius = std::max((hi - lo).norm() / 2, 1e-6);
    const Vec3 back = options.view_direction.normalized(); // from the target to the eye
    Camera camera;
    camera.target = centre;
    camera.up = options.up;
    camera.fov_y_deg = options.fov_y_deg;
    const Vec3 right = (-back).cross(options.up).normalized();
    const Vec3 up = right.cross(-back);

    // Smallest distance d with every corner inside the view shrunk by `margin`: for a corner at
    // camera-space (x, y, z) (z towards the eye) the depth is d - z, so |x| <= tx (d - z).
    const double ty = std::tan(radians(options.fov_y_deg) / 2) / options.margin;
    const double tx = ty * aspect;
    double distance = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p { (corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
            (corner & 4) ? hi.z() : lo.z() };
        const Vec3 r = p - centre;
        const double z = r.dot(back);
        distance
            = std::max({ distance, z + std::abs(r.dot(right)) / tx, z + std::abs(r.dot(up)) / ty });
    }
    distance = std::max(distance, 1.5 * radius);
    camera.position = centre + distance * back;
    // Room for the object to move towards or away from the camera by a few radii.
    camera.near = std::max(distance - 4 * radius, 0.01 * distance);
    camera.far = distance + 4 * radius;
    return camera;
}

} // namespace polycut::render
