// Degenerate sweep-triangle detection.
#include "polycut/protocol/sweep.hpp"

#include <cmath>
#include <cstdio>

namespace polycut::protocol {

namespace {
Vector3 sub(const Vector3& a, const Vector3& b) {
    return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}
double dot(const Vector3& a, const Vector3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vector3 cross(const Vector3& a, const Vector3& b) {
    return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}
bool finite(const Triangle3& t) {
    for (const auto& p : t) {
        for (double c : p) {
            if (!std::isfinite(c)) {
                return false;
            }
        }
    }
    return true;
}
} // namespace

double triangle_quality(const Triangle3& t) {
    if (!finite(t)) {
        return 0.0;
    }
    const Vector3 e0 = sub(t[1], t[0]);
    const Vector3 e1 = sub(t[2], t[1]);
    const Vector3 e2 = sub(t[0], t[2]);
    const double sum_sq = dot(e0, e0) + dot(e1, e1) + dot(e2, e2);
    if (!(sum_sq > 0.0) || !std::isfinite(sum_sq)) {
        return 0.0;
    }
    const Vector3 n = cross(e0, sub(t[2], t[0]));
    const double area = 0.5 * std::sqrt(dot(n, n));
    return 4.0 * std::sqrt(3.0) * area / sum_sq;
}

std::optional<std::string> triangle_defect(const Triangle3& t, double min_quality) {
    if (!finite(t)) {
        return "non-finite coordinate";
    }
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
        return "coincident corners";
    }
    const double q = triangle_quality(t);
    if (!(q >= min_quality)) {
        char text[160];
        std::snprintf(text, sizeof text,
            "degenerate triangle: quality %.3g < %.3g (zero area relative to its size)", q,
            min_quality);
        return std::string(text);
    }
    return std::nullopt;
}

} // namespace polycut::protocol
