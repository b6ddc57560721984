// Pinhole camera: where it is, where it looks, and how wide; plus an automatic framing that
// shows a bounding box from a three-quarter view above it.
#pragma once

#include "polycut/common/types.hpp"

namespace polycut::render {

/// A perspective camera in world space [m].
struct Camera {
    Vec3 position { 0.3, -0.4, 0.3 }; ///< eye [m]
    Vec3 target { 0, 0, 0 }; ///< point looked at [m]
    Vec3 up { 0, 0, 1 }; ///< approximate up direction (need not be unit)
    double fov_y_deg = 35; ///< vertical field of view [deg], in (0, 180)
    double near = 0.01; ///< near clip distance [m], > 0
    double far = 10; ///< far clip distance [m], > near

    /// World-to-camera rigid transform (camera looks down -z, y up), as in gluLookAt.
    Eigen::Matrix4d view_matrix() const;
    /// Camera-to-clip projection for width / height = `aspect`, as in gluPerspective.
    Eigen::Matrix4d projection_matrix(double aspect) const;
    /// Pixel coordinates of a world point in a width x height image: (x right, y down from
    /// the top-left corner [px], depth along the view direction [m]).
    Vec3 project(const Vec3& point, int width, int height) const;
    /// Throws InputError naming the field if the camera is degenerate (non-finite values,
    /// position == target, up parallel to the view direction, bad fov or clip range).
    void validate() const;
};

/// Options of `frame`.
struct FrameOptions {
    Vec3 view_direction { 1.0, -1.4, 1.1 }; ///< from target towards the eye (3/4 from above)
    Vec3 up { 0, 0, 1 }; ///< world up
    double fov_y_deg = 35; ///< vertical field of view [deg]
    double margin = 1.15; ///< >= 1; the box fills about 1/margin of the view
};

/// A camera that looks at the centre of the box [lo, hi] [m] along `view_direction` and is just
/// far enough back that every box corner projects inside the central 1/margin of a view of
/// width / height = `aspect`. Near and far leave room for the object to grow (e.g. retraction).
/// Throws InputError for non-finite or inverted bounds.
Camera frame(const Vec3& lo, const Vec3& hi, double aspect, const FrameOptions& options = {});

} // namespace polycut::render
