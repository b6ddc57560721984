// Swept area inside the tissue and cut-face area (see completeness.hpp).
#include "polycut/cut/completeness.hpp"

#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::cut {

namespace {

/// Keeps the part of the convex polygon `poly` with n . x <= d (Sutherland-Hodgman, one plane).
void clip(std::vector<Vec3>& poly, const Vec3& n, double d) {
    std::vector<Vec3> out;
    out.reserve(poly.size() + 1);
    for (std::size_t j = 0; j < poly.size(); ++j) {
        const Vec3& p = poly[j];
        const Vec3& q = poly[(j + 1) % poly.size()];
        const double sp = n.dot(p) - d, sq = n.dot(q) - d;
        if (sp <= 0)
            out.push_back(p);
        if ((sp <= 0) != (sq <= 0))
            out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    poly = std::move(out);
}

double area_in_cell(const mesh::Mesh& m, Index c, const Triangle& t, const Vec3& t_normal) {
    const mesh::Cell& cell = m.cells[std::size_t(c)];
    Vec3 centre = Vec3::Zero();
    for (Index n : cell.nodes)
        centre += m.rest[std::size_t(n)];
    centre /= double(cell.nodes.size());
    std::vector<Vec3> poly(t.begin(), t.end());
    for (Index f : cell.faces) {
        const std::vector<Vec3> loop = geometry::gather(m.rest, m.faces[std::size_t(f)].nodes);
        Vec3 n = geometry::polygon_normal(loop);
        const Vec3 p = geometry::polygon_centroid(loop);
        if (n.dot(centre - p) > 0)
            n = -n; // outward
        const double d = n.dot(p);
        // A triangle lying in an interior face is counted for the face's owner only, so a blade
        // in a plane of faces is not counted twice; one lying in a skin face is not inside.
        const double scale = std::max((t[1] - t[0]).norm(), (t[2] - t[0]).norm());
        const bool coplanar = std::abs(std::abs(n.dot(t_normal)) - 1.0) < 1e-9
            && std::abs(n.dot(t[0]) - d) < 1e-9 * scale;
        if (coplanar) {
            if (m.faces[std::size_t(f)].boundary() || m.faces[std::size_t(f)].owner != c)
                return 0.0;
            continue;
        }
        clip(poly, n, d);
        if (poly.size() < 3)
            return 0.0;
    }
    return geometry::polygon_area(poly);
}

} // namespace

double area_inside(const mesh::Mesh& m, std::span<const Index> cells, const Triangle& t) {
    geometry::Aabb box;
    for (const Vec3& p : t)
        box.extend(p);
    const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
    if (!(normal.norm() > 0))
        return 0.0;
    const Vec3 unit = normal.normalized();
    double area = 0;
    for (Index c : cells) {
        geometry::Aabb cb;
        for (Index n : m.cells[std::size_t(c)].nodes)
            cb.extend(m.rest[std::size_t(n)]);
        if (cb.overlaps(box))
            area += area_in_cell(m, c, t, unit);
    }
    return area;
}

double area_inside(const mesh::Mesh& m, const Triangle& t) {
    std::vector<Index> all(std::size_t(m.num_cells()));
    for (Index c = 0; c < m.num_cells(); ++c)
        all[std::size_t(c)] = c;
    return area_inside(m, all, t);
}

double area_on_cut_faces(
    const mesh::Mesh& m, std::span<const Index> cells, const Triangle& t, double tol) {
    const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
    if (!(normal.norm() > 0))
        return 0.0;
    const Vec3 unit = normal.normalized();
    const Vec3 centre = (t[0] + t[1] + t[2]) / 3.0;
    // Per lip: the cells near a re-cut may hold one lip or both (each covers the same area).
    double area[2] = { 0, 0 };
    std::vector<Index> seen;
    for (Index c : cells)
        for (Index f : m.cells[std::size_t(c)].faces) {
            const mesh::Face& face = m.faces[std::size_t(f)];
            if (!face.boundary() || face.tag != mesh::FaceTag::Cut)
                continue;
            std::vector<Vec3> poly = geometry::gather(m.rest, face.nodes);
            bool near = true;
            for (const Vec3& p : poly)
                near = near && std::abs(unit.dot(p - t[0])) <= tol;
            if (!near || std::find(seen.begin(), seen.end(), f) != seen.end())
                continue;
            seen.push_back(f);
            const double cosine = geometry::polygon_normal(poly).dot(unit);
            // Projected onto the triangle's plane (a face-snapped cut is a surface of mesh faces
            // beside the blade, not in its plane), then clipped by the triangle's three edge
            // planes (a convex region: Sutherland-Hodgman keeps the area of a non-convex face).
            for (Vec3& p : poly)
                p -= unit.dot(p - t[0]) * unit;
            for (int k = 0; k < 3 && poly.size() >= 3; ++k) {
                const Vec3 e = t[std::size_t((k + 1) % 3)] - t[std::size_t(k)];
                Vec3 out = e.cross(unit);
                if (out.dot(centre - t[std::size_t(k)]) > 0)
                    out = -out;
                clip(poly, out, out.dot(t[std::size_t(k)]));
            }
            if (poly.size() >= 3)
                area[cosine > 0 ? 0 : 1] += geometry::polygon_area(poly);
        }
    return std::max(area[0], area[1]);
}

double cut_face_area(const mesh::Mesh& m) {
    double area = 0;
    for (const mesh::Face& f : m.faces)
        if (f.boundary() && f.tag == mesh::FaceTag::Cut)
            area += geometry::polygon_area(geometry::gather(m.rest, f.nodes));
    return area;
}

} // namespace polycut::cut
