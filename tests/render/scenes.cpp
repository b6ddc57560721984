// Procedural renderer test scenes (see scenes.hpp).
#include "scenes.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace polycut::render::test {

namespace {

/// Appends an (nu x nv)-cell grid over point(i, j), i in [0, nu], j in [0, nv]; cell (i, j)
/// gets tag(i, j). `flip` reverses the winding so the normal points outwards.
void add_grid(TestSurface& s, int nu, int nv, const std::function<Vec3(int, int)>& point,
    const std::function<std::uint8_t(int, int)>& tag, bool flip) {
    const auto first = static_cast<std::uint32_t>(s.positions.size() / 3);
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const Vec3 p = point(i, j);
            for (int c = 0; c < 3; ++c)
                s.positions.push_back(static_cast<float>(p[c]));
        }
    auto id = [&](int i, int j) { return first + static_cast<std::uint32_t>(j * (nu + 1) + i); };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            if (flip)
                std::swap(b, d);
            s.triangles.insert(s.triangles.end(), { a, b, c, a, c, d });
            s.tags.insert(s.tags.end(), 2, tag(i, j));
        }
}

} // namespace

TestSurface make_block(const BlockSpec& spec) {
    constexpr double kStep = 0.004;
    const int nx = static_cast<int>(std::lround(spec.length / kStep));
    const int ny = static_cast<int>(std::lround(spec.width / kStep));
    const int nz = static_cast<int>(std::lround(spec.height / kStep));
    const double dx = spec.length / nx, dy = spec.width / ny;
    const double x_lo = spec.notch_x - spec.notch_half_width;
    const double x_hi = spec.notch_x + spec.notch_half_width;
    const double eps = 1e-9;
    auto top = [&](double x) {
        return spec.height
            - spec.notch_depth
            * std::max(0.0, 1 - std::abs(x - spec.notch_x) / spec.notch_half_width);
    };
    auto skin = [](int, int) { return std::uint8_t(1); };
    auto top_tag = [&](int i, int) {
        const bool in_notch
            = spec.notch_depth > 0 && i * dx >= x_lo - eps && (i + 1) * dx <= x_hi + eps;
        return std::uint8_t(in_notch ? 2 : 1);
    };

    TestSurface s;
    add_grid(
        s, nx, ny, [&](int i, int j) { return Vec3(i * dx, j * dy, top(i * dx)); }, top_tag, false);
    add_grid(
        s, nx, ny, [&](int i, int j) { return Vec3(i * dx, j * dy, 0); }, skin, true);
    for (const double y : { 0.0, spec.width })
        add_grid(
            s, nx, nz, [&](int i, int k) { return Vec3(i * dx, y, top(i * dx) * k / nz); }, skin,
            y > 0);
    for (const double x : { 0.0, spec.length })
        add_grid(
            s, ny, nz, [&](int j, int k) { return Vec3(x, j * dy, top(x) * k / nz); }, skin,
            x == 0);

    if (spec.opening != 0)
        for (std::size_t v = 0; v < s.positions.size(); v += 3)
            if (s.positions[v] > spec.notch_x + eps) {
                const double z = s.positions[v + 2] / spec.height;
                const double fade
                    = 1 - (s.positions[v] - spec.notch_x) / (spec.length - spec.notch_x);
                s.positions[v] += static_cast<float>(spec.opening * z * z * fade);
            }
    return s;
}

TestSurface make_blob(int slices, int stacks, double radius) {
    TestSurface s;
    auto point = [&](int i, int j) {
        const double theta = std::numbers::pi * j / stacks; // polar angle
        const double phi = 2 * std::numbers::pi * i / slices;
        const double r = radius
            * (1 + 0.08 * std::sin(3 * phi) * std::sin(2 * theta) + 0.05 * std::cos(5 * theta));
        return Vec3(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
            r * std::cos(theta));
    };
    for (int j = 0; j <= stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const Vec3 p = point(i, j);
            for (int c = 0; c < 3; ++c)
                s.positions.push_back(static_cast<float>(p[c]));
        }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * slices + i % slices); };
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const std::uint8_t tag = std::abs(2 * j - stacks) < stacks / 10 ? 2 : 1;
            // Skip the degenerate triangles at the poles.
            if (j > 0) {
                s.triangles.insert(s.triangles.end(), { id(i, j), id(i + 1, j), id(i + 1, j + 1) });
                s.tags.push_back(tag);
            }
            if (j < stacks - 1) {
                s.triangles.insert(s.triangles.end(), { id(i, j), id(i + 1, j + 1), id(i, j + 1) });
                s.tags.push_back(tag);
            }
        }
    return s;
}

Camera block_camera(int width, int height) {
    const BlockSpec spec;
    return frame(
        Vec3::Zero(), Vec3(spec.length, spec.width, spec.height), double(width) / double(height));
}

long count_cut_coloured(const Image& image) {
    long count = 0;
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        const int r = image.rgba[i], g = image.rgba[i + 1], b = image.rgba[i + 2];
        if (r > 40 && r > 2.5 * g && r > 2.5 * b)
            ++count;
    }
    return count;
}

} // namespace polycut::render::test
