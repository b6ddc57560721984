#include "plane_split.hpp"
#include "sweep.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace polycut::cut::detail {
namespace {
using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& a, const Vec2& b) {
    return a.x() * b.y() - a.y() * b.x();
}

// Convex hull, counter-clockwise (Andrew's monotone chain).
std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
    std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
        return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    if (p.size() < 3)
        return p;
    std::vector<Vec2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross2(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0)
            --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross2(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0)
            --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

// Area of the intersection of two counter-clockwise convex polygons (Sutherland-Hodgman).
double overlap_area(std::vector<Vec2> subject, const std::vector<Vec2>& clip) {
    for (std::size_t i = 0; i < clip.size() && !subject.empty(); ++i) {
        const Vec2 a = clip[i], b = clip[(i + 1) % clip.size()];
        std::vector<Vec2> out;
        for (std::size_t j = 0; j < subject.size(); ++j) {
            const Vec2 p = subject[j], q = subject[(j + 1) % subject.size()];
            const double sp = cross2(b - a, p - a), sq = cross2(b - a, q - a);
            if (sp >= 0)
                out.push_back(p);
            if ((sp >= 0) != (sq >= 0))
                out.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject = std::move(out);
    }
    double area = 0;
    for (std::size_t j = 0; j < subject.size(); ++j)
        area += cross2(subject[j], subject[(j + 1) % subject.size()]);
    return 0.5 * area;
}
/// Where the side line of a triangle's edge runs through a face within the snapping distance of
/// several of its nodes in a row (a blade's bottom edge along a row of face edges, the face's
/// nodes on them from its neighbours' splits), the signs s of the loop cross from + to - over
/// a run of zeros, which no chord can split (clean_pattern refuses it): such faces stayed out
/// of the crack of both triangles of a strip, a hole of a face per strip (a random-plane block
/// cut along its grid plane lost 6 % of the cut). Of each such run the node nearest the line
/// stays on it; the others take the sign of the run's end they lie towards, in s only: the
/// chord then runs through the kept node, and the nodes given a side lie within the snapping
/// distance of the line, as zeros do.
void thin_zero_runs(
    const PlaneClassifier& side, const std::vector<Index>& loop, std::vector<int>& s) {
    const std::size_t k = loop.size();
    for (std::size_t a = 0; a < k; ++a) {
        // a nonzero node followed by a run of at least two zeros and then the other sign
        if (s[a] == 0 || s[(a + 1) % k] != 0)
            continue;
        std::size_t b = (a + 1) % k, run = 0;
        while (s[b] == 0 && run < k) {
            b = (b + 1) % k;
            ++run;
        }
        if (run < 2 || s[b] == 0 || s[b] == s[a])
            continue;
        std::size_t keep = (a + 1) % k;
        for (std::size_t j = (a + 1) % k; j != b; j = (j + 1) % k)
            if (std::abs(side.distance(loop[j])) < std::abs(side.distance(loop[keep])))
                keep = j;
        bool before = true;
        for (std::size_t j = (a + 1) % k; j != b; j = (j + 1) % k) {
            if (j == keep) {
                before = false;
                continue;
            }
            s[j] = before ? s[a] : s[b];
        }
    }
}

/// Whether the face with nodes `loop` (in the plane of `cls`) may lie under the triangle whose
/// edges' side planes are `sides`: it is not wholly beyond one of them by more than a node's
/// snapping distance there (as the clip of split_along_triangle tests it), with the node's
/// distance to the cut plane on top (a skin node slides up to twice that far as it moves onto
/// the plane). Distances, not the sides' cached signs: the nodes have not moved yet.
bool may_cover(Editor& ed, const PlaneClassifier& cls, const std::vector<PlaneClassifier>& sides,
    const std::vector<Index>& loop) {
    return std::none_of(sides.begin(), sides.end(), [&](const PlaneClassifier& side) {
        return std::all_of(loop.begin(), loop.end(), [&](Index v) {
            const double eps = std::max(ed.opt.edge_snap * ed.cell_size(), ed.snap_eps(v))
                + 2 * std::abs(cls.distance(v));
            return side.distance(v) > eps;
        });
    });
}
} // namespace

std::vector<Index> split_along_triangle(Editor& ed, const Triangle& tri) {
    mesh::Mesh& m = ed.m;
    const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
    PlaneClassifier cls(ed, Plane { n, n.dot(tri[0]) });
    const Vec3 eu = (tri[1] - tri[0]).normalized();
    const Vec3 ev = n.cross(eu);
    auto to2 = [&](const Vec3& x) { return Vec2((x - tri[0]).dot(eu), (x - tri[0]).dot(ev)); };
    const std::vector<Vec2> tri2 { to2(tri[0]), to2(tri[1]), to2(tri[2]) }; // counter-clockwise

    geometry::Aabb tbox;
    for (const Vec3& p : tri)
        tbox.extend(p);

    // Cells the triangle covers with positive area: split them. Faces already in the plane:
    // candidates for the crack as they are.
    std::vector<Index> to_split, plane_faces;
    // The faces in the plane of a crossed cell the triangle leaves unsplit (below). Their nodes
    // count as in the plane within the snapping distance of the mesh's cell size too, not only
    // their own: the splits of a stroke cut the cells along its crack into slivers, which
    // shrinks their nodes' own distances, and a node that an earlier triangle could not move
    // onto its plane (a skin corner, or a cell would go out of convex) then lies off the next
    // one's by more than its own distance. The faces at it were neither split (a face of their
    // cells lies in the plane) nor in the plane: on the octree organ resting on its table, a
    // blade through its top node left a hole a cell wide all down the cut (completeness 0.936
    // -> 1.003; the cut_pencil scene 0.923 -> 1.001). A face the plane crosses by its nodes'
    // own distances is not in the plane. (Loosened for every cell, the cut faces came off the
    // plane enough to make the octree organ's embedded skin patch non-manifold.)
    PlaneClassifier loose(ed, cls.plane(), ed.opt.snap * ed.cell_size());
    const auto faces_in_plane = [&](Index c) {
        for (Index f : at(m.cells, c).faces) {
            const mesh::Face& face = at(m.faces, f);
            bool in = !face.boundary(), plus = false, minus = false;
            for (Index v : face.nodes) {
                in = in && loose.sign(v) == 0;
                plus = plus || cls.sign(v) > 0;
                minus = minus || cls.sign(v) < 0;
            }
            if (in && !(plus && minus))
                plane_faces.push_back(f);
        }
    };
    const Index ncells = m.num_cells();
    // The cells whose grown bounds can reach the triangle (Editor::cells_near, a superset in
    // id order): the tests below then run as over every cell (on the 5k organ the pass over
    // all 27k cells per triangle was half of the cutter's time in a re-cut).
    const std::vector<Index> near = ed.cells_near(tbox, ncells);
    for (Index c : near) {
        geometry::Aabb box = ed.bounds(c);
        // A cell's thickness 6 V / A is at most twice its box's diagonal (V = 1/3 sum_f A_f
        // (x_f - o).n_f with o in the box), so this box, grown by that bound, is a superset
        // test, and the thickness (a pass over the cell's faces) is computed only for the cells
        // near the triangle. Computed for every cell, it cost the first triangle of a stroke
        // on the 5k organ ~16 ms (its splitting 26.8 -> 10.3 ms; later triangles ~0.6 ms).
        const double reach = kSweepReach * ed.opt.snap * (box.hi - box.lo).norm();
        if (tbox.lo.x() > box.hi.x() + reach || tbox.hi.x() < box.lo.x() - reach
            || tbox.lo.y() > box.hi.y() + reach || tbox.hi.y() < box.lo.y() - reach
            || tbox.lo.z() > box.hi.z() + reach || tbox.hi.z() < box.lo.z() - reach)
            continue;
        const double margin = ed.opt.snap * ed.thickness(c);
        box.lo.array() -= margin;
        box.hi.array() += margin;
        if (!box.overlaps(tbox))
            continue;
        bool plus = false, minus = false;
        for (Index v : at(m.cells, c).nodes) {
            const int s = cls.sign(v);
            plus = plus || s > 0;
            minus = minus || s < 0;
        }
        if (plus && minus) {
            // Cross-section of the cell with the plane, in the plane's 2D frame.
            std::vector<Vec2> section;
            for (Index f : at(m.cells, c).faces) {
                const auto& loop = at(m.faces, f).nodes;
                for (std::size_t i = 0; i < loop.size(); ++i) {
                    const Index a = loop[i], b = loop[(i + 1) % loop.size()];
                    const int sa = cls.sign(a), sb = cls.sign(b);
                    if (sa == 0)
                        section.push_back(to2(at(m.rest, a)));
                    else if (sa * sb < 0) {
                        const double da = cls.distance(a), db = cls.distance(b);
                        const double t = da / (da - db);
                        section.push_back(to2((1 - t) * at(m.rest, a) + t * at(m.rest, b)));
                    }
                }
            }
            const auto hull = convex_hull(section);
            const double h = ed.opt.snap * ed.thickness(c);
            if (hull.size() < 3 || overlap_area(tri2, hull) <= h * h)
                continue;
            if (can_split_cell(ed, cls, c))
                to_split.push_back(c);
            else {
                // Left unsplit (a face of it lies in the plane within the snapping distance:
                // the plane of an earlier triangle of the stroke, a hair off this one's). Its
                // faces in the plane still open the crack where the triangle covers them;
                // skipping them left holes in a stroke whose plane turned by a fraction of a
                // degree (0.6 % of the organ's cut, and the same holes again on every re-cut).
                ++ed.report->cells_skipped;
                faces_in_plane(c);
            }
        } else {
            for (Index f : at(m.cells, c).faces) {
                const mesh::Face& face = at(m.faces, f);
                if (face.boundary() || face.owner != c)
                    continue; // each interior face once, from its owner
                bool flat = true;
                for (Index v : face.nodes)
                    flat = flat && cls.sign(v) == 0;
                if (flat)
                    plane_faces.push_back(f);
            }
        }
    }

    // Each edge's side plane is perpendicular to the cut plane, + outside (the clip below).
    std::vector<PlaneClassifier> sides;
    for (int i = 0; i < 3; ++i) {
        const Vec3 s = (tri[std::size_t((i + 1) % 3)] - tri[std::size_t(i)]).cross(n).normalized();
        sides.emplace_back(
            ed, Plane { s, s.dot(tri[std::size_t(i)]) }, ed.opt.edge_snap * ed.cell_size());
    }

    // Nodes snapped onto the plane move onto it (decision 0057): the interface faces the splits
    // make, and the faces found in the plane, are then in it exactly, and the stroke's next
    // triangles in the same plane find them there even after the splits have shrunk the nodes'
    // snapping distances (the holes of a straight incision, 2.3 % of the organ's cut). Only a
    // triangle that splits cells moves nodes: a blade held in a cut must not make work per tick.
    // Of the faces in the plane, only those the triangle may cover (not wholly beyond one of its
    // edges, as the clip below tests them): the uncut faces a stroke leaves in its plane along
    // the blade's bottom edge lie in the bounds of a long triangle too, and moving them onto a
    // plane turned by the deformation changed every cell at them, for nothing the clip keeps
    // (a strip through the pressed organ: 10 cells split, 140 more changed by the moves, 1,200
    // units of work against the tick's 300).
    if (!to_split.empty()) {
        for (Index c : to_split)
            for (Index v : at(m.cells, c).nodes)
                cls.project_onto_plane(v);
        for (Index f : plane_faces)
            if (may_cover(ed, cls, sides, at(m.faces, f).nodes))
                for (Index v : at(m.faces, f).nodes)
                    cls.project_onto_plane(v);
    }

    std::vector<Index> interfaces;
    for (Index c : to_split) {
        split_cell(ed, cls, c, interfaces);
        plane_faces.insert(plane_faces.end(), interfaces.begin(), interfaces.end());
    }
    std::sort(plane_faces.begin(), plane_faces.end());
    plane_faces.erase(std::unique(plane_faces.begin(), plane_faces.end()), plane_faces.end());

    // Clip each face in the plane by the triangle's edges (000 sec. 5.2: "the polygon edges are
    // intersected with edges in the simulation mesh ... faces in the cut plane are split") with
    // the side planes of its edges; the pieces outside stay interior faces, all convex.
    std::vector<Index> crack;
    for (Index f : plane_faces) {
        if (at(m.faces, f).boundary())
            continue;
        bool inside = true;
        for (auto& side : sides) {
            auto s = side.signs(at(m.faces, f).nodes);
            const bool out = std::find(s.begin(), s.end(), 1) != s.end();
            const bool in = std::find(s.begin(), s.end(), -1) != s.end();
            if (!out)
                continue;
            if (!in) {
                inside = false;
                break;
            }
            thin_zero_runs(side, at(m.faces, f).nodes, s);
            if (!clean_pattern(s)) {
                inside = false;
                break;
            }
            side.split_crossing_edges(f, at(m.faces, f).owner);
            const auto loop = at(m.faces, f).nodes;
            s = side.signs(loop);
            thin_zero_runs(side, loop, s);
            std::vector<Index> outer, inner;
            split_loop(loop, s, outer, inner);
            if (outer.size() < 3 || inner.size() < 3) {
                inside = false;
                break;
            }
            ed.split_face(f, std::move(inner), std::move(outer));
        }
        if (inside)
            crack.push_back(f);
    }
    return crack;
}

} // namespace polycut::cut::detail
