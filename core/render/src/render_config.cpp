// Validation of RenderConfig: every setting in range, with the field named on error.
#include "polycut/common/error.hpp"
#include "polycut/render/renderer.hpp"

#include <cmath>
#include <string>

namespace polycut::render {

namespace {

void check_colour(const Rgb& colour, const char* field) {
    for (const float c : colour)
        if (!(c >= 0 && c <= 1))
            throw InputError(field, "colour channels must be in [0, 1]");
}

void check_non_negative(double value, const char* field) {
    if (!(value >= 0) || !std::isfinite(value))
        throw InputError(field, "must be finite and >= 0");
}

} // namespace

void RenderConfig::validate() const {
    constexpr int kMaxSide = 8192;
    if (width < 1 || width > kMaxSide)
        throw InputError("/width", "must be in [1, 8192] px, got " + std::to_string(width));
    if (height < 1 || height > kMaxSide)
        throw InputError("/height", "must be in [1, 8192] px, got " + std::to_string(height));
    if (msaa_samples < 0 || msaa_samples > 16)
        throw InputError(
            "/msaa_samples", "must be in [0, 16], got " + std::to_string(msaa_samples));
    check_colour(background, "/background");
    check_colour(skin_colour, "/skin_colour");
    check_colour(cut_colour, "/cut_colour");
    check_colour(interior_colour, "/interior_colour");
    check_colour(line_colour, "/line_colour");
    check_colour(blade_colour, "/blade_colour");
    check_colour(arrow_colour, "/arrow_colour");
    const double light = std::hypot(light_direction[0], light_direction[1], light_direction[2]);
    if (!(light > 0) || !std::isfinite(light))
        throw InputError("/light_direction", "must be finite and non-zero");
    check_non_negative(ambient, "/ambient");
    check_non_negative(key, "/key");
    check_non_negative(fill, "/fill");
    check_non_negative(specular, "/specular");
    check_non_negative(shininess, "/shininess");
    if (!(crease_angle_deg >= 0 && crease_angle_deg <= 180))
        throw InputError("/crease_angle_deg", "must be in [0, 180]");
    if (!(line_width > 0 && line_width <= 64))
        throw InputError("/line_width", "must be in (0, 64] px");
    check_non_negative(overlay_radius, "/overlay_radius");
}

} // namespace polycut::render
