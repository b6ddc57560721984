// Swept area inside the tissue and cut-face area (see completeness.hpp).
#include "polycut/cut/completeness.hpp"

#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::cut {

namespace {

/// Reused buffers: these run for every sweep triangle of a cut over every cell near it, and
/// the allocations of a loop per face and a polygon per clip were most of their cost.
struct Scratch {
    std::vector<Vec3> poly, out, loop;
};
Scratch& scratch() {
    thread_local Scratch s;
    return s;
}

/// The positions of `ids` into `loop` (geometry::gather without a new vector).
template <class Ids>
void gather_into(const std::vector<Vec3>& points, const Ids& ids, std::vector<Vec3>& loop) {
    loop.clear();
    for (Index i : ids)
        loop.push_back(points[std::size_t(i)]);
}

/// Keeps the part of the convex polygon `poly` with n . x <= d (Sutherland-Hodgman, one plane);
/// `out` is scratch.
void clip(std::vector<Vec3>& poly, std::vector<Vec3>& out, const Vec3& n, double d) {
    out.clear();
    for (std::size_t j = 0; j < poly.size(); ++j) {
        const Vec3& p = poly[j];
        const Vec3& q = poly[(j + 1) % poly.size()];
        const double sp = n.dot(p) - d, sq = n.dot(q) - d;
        if (sp <= 0)
            out.push_back(p);
        if ((sp <= 0) != (sq <= 0))
            out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    poly.swap(out);
}

double area_in_cell(const mesh::Mesh& m, Index c, const Triangle& t, const Vec3& t_normal) {
    const mesh::Cell& cell = m.cells[std::size_t(c)];
    Vec3 centre = Vec3::Zero();
    for (Index n : cell.nodes)
        centre += m.rest[std::size_t(n)];
    centre /= double(cell.nodes.size());
    Scratch& sc = scratch();
    std::vector<Vec3>& poly = sc.poly;
    poly.assign(t.begin(), t.end());
    const double scale = std::max((t[1] - t[0]).norm(), (t[2] - t[0]).norm());
    for (Index f : cell.faces) {
        gather_into(m.rest, m.faces[std::size_t(f)].nodes, sc.loop);
        Vec3 n = geometry::polygon_normal(sc.loop);
        const Vec3 p = geometry::polygon_centroid(sc.loop);
        if (n.dot(centre - p) > 0)
            n = -n; // outward
        const double d = n.dot(p);
        // A triangle lying in an interior face is counted for the face's owner only, so a blade
        // in a plane of faces is not counted twice; one lying in a skin face is not inside.
        const bool coplanar = std::abs(std::abs(n.dot(t_normal)) - 1.0) < 1e-9
            && std::abs(n.dot(t[0]) - d) < 1e-9 * scale;
        if (coplanar) {
            if (m.faces[std::size_t(f)].boundary() || m.faces[std::size_t(f)].owner != c)
                return 0.0;
            continue;
        }
        clip(poly, sc.out, n, d);
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
    // A boundary face belongs to one cell: unique cells visit each face once (a list of the
    // faces seen, searched per face, grew quadratic with the cut faces of repeated strokes).
    std::vector<Index> unique(cells.begin(), cells.end());
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    Scratch& sc = scratch();
    std::vector<Vec3>& poly = sc.poly;
    for (Index c : unique)
        for (Index f : m.cells[std::size_t(c)].faces) {
            const mesh::Face& face = m.faces[std::size_t(f)];
            if (!face.boundary() || face.tag != mesh::FaceTag::Cut)
                continue;
            gather_into(m.rest, face.nodes, poly);
            bool near = true;
            for (const Vec3& p : poly)
                near = near && std::abs(unit.dot(p - t[0])) <= tol;
            if (!near)
                continue;
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
                clip(poly, sc.out, out, out.dot(t[std::size_t(k)]));
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
