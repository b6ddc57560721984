#include "polycut/geometry/polygon.hpp"

#include <algorithm>

namespace polycut::geometry {

Vec3 newell_vector(std::span<const Vec3> loop)
{
    Vec3 n = Vec3::Zero();
    const std::size_t k = loop.size();
    for (std::size_t i = 0; i < k; ++i)
        n += loop[i].cross(loop[(i + 1) % k]);
    return n;
}

Vec3 polygon_normal(std::span<const Vec3> loop)
{
    const Vec3 n = newell_vector(loop);
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double polygon_area(std::span<const Vec3> loop) { return 0.5 * newell_vector(loop).norm(); }

Vec3 polygon_centroid(std::span<const Vec3> loop)
{
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : loop)
        mean += p;
    mean /= double(std::max<std::size_t>(loop.size(), 1));
    // Fan from the vertex mean, weighting each triangle by its signed area along the normal.
    const Vec3 n = polygon_normal(loop);
    double total = 0;
    Vec3 c = Vec3::Zero();
    const std::size_t k = loop.size();
    for (std::size_t i = 0; i < k; ++i) {
        const Vec3& a = loop[i];
        const Vec3& b = loop[(i + 1) % k];
        const double w = 0.5 * (a - mean).cross(b - mean).dot(n);
        total += w;
        c += w * (mean + a + b) / 3.0;
    }
    return total > 0 ? Vec3(c / total) : mean;
}

double planarity_error(std::span<const Vec3> loop)
{
    const Vec3 n = polygon_normal(loop);
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : loop)
        mean += p;
    mean /= double(std::max<std::size_t>(loop.size(), 1));
    double err = 0;
    for (const Vec3& p : loop)
        err = std::max(err, std::abs((p - mean).dot(n)));
    return err;
}

} // namespace polycut::geometry
