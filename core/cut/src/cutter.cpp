#include "polycut/cut/cutter.hpp"

#include "plane_split.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/cut/fault_injection.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace polycut::cut {

using detail::at;

struct Cutter::Impl {
    Impl(mesh::Mesh& mesh, CutOptions o)
        : opt(o)
        , ed(mesh, opt) {
        measure();
    }
    CutOptions opt;
    detail::Editor ed;
    geometry::Aabb box; // rest bounds of the mesh (cuts never move nodes outside)

    void measure() {
        box = {};
        for (const Vec3& x : ed.m.rest)
            box.extend(x);
    }

    void validate(std::span<const Triangle> tris) const {
        const double L = box.diagonal();
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const std::string where = "triangle " + std::to_string(i);
            const Triangle& t = tris[i];
            for (const Vec3& p : t) {
                if (!p.allFinite())
                    throw InputError(where, "non-finite coordinate");
                if ((p - box.center()).norm() > opt.max_extent * std::max(L, 1e-300))
                    throw InputError(where, "coordinate too far from the tissue");
            }
            const double area = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
            const double longest
                = std::max({ (t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm() });
            if (!(area > opt.min_area * L * L) || !(2 * area / longest > opt.min_area * L))
                throw InputError(
                    where, "degenerate triangle (area " + std::to_string(area) + " m^2)");
        }
    }
};

Cutter::Cutter(mesh::Mesh& mesh, CutOptions options)
    : m_impl(std::make_unique<Impl>(mesh, options)) { }

Cutter::~Cutter() = default;

void Cutter::rebuild() {
    m_impl->ed.rebuild();
    m_impl->measure();
}

const CutOptions& Cutter::options() const {
    return m_impl->opt;
}
const mesh::Mesh& Cutter::mesh() const {
    return m_impl->ed.m;
}

namespace {
// The model update a call leaves: the changed cells in tet equivalents, each weighted by the
// square of its face corners / 12 (CutReport::work).
double changed_work(const detail::Editor& ed) {
    double work = 0;
    for (Index c : ed.changed_cells()) {
        if (c >= ed.m.num_cells())
            continue;
        std::size_t corners = 0;
        for (Index f : at(ed.m.cells, c).faces)
            corners += at(ed.m.faces, f).nodes.size();
        const double k = double(corners) / 12.0; // a tet: 4 faces x 3 corners
        work += k * k;
    }
    return work;
}
} // namespace

CutReport Cutter::cut(std::span<const Triangle> rest_triangles, Index max_changed_cells,
    std::span<const char> may_stop) {
    Stopwatch watch;
    m_impl->validate(rest_triangles);
    CutReport report;
    auto& ed = m_impl->ed;
    ed.begin(report);
    for (const Triangle& tri : rest_triangles) {
        ++report.triangles;
        const auto crack = detail::split_along_triangle(ed, tri);
        if (crack.empty())
            ++report.triangles_missed;
        detail::separate(ed, crack);
        const std::size_t t = std::size_t(report.triangles) - 1;
        if (max_changed_cells > 0 && (may_stop.empty() || (t < may_stop.size() && may_stop[t]))
            && (Index(ed.changed_cells().size()) >= max_changed_cells
                || changed_work(ed) >= double(max_changed_cells)))
            break;
    }
    detail::fail_if_injected();
    detail::fix_pinched_edges(ed);
    if (m_impl->opt.merge_cut_faces)
        report.cut_faces_merged = detail::merge_cut_faces(ed, ed.changed_cells());
    if (m_impl->opt.coarsen)
        report.nodes_coarsened = detail::remove_collinear_nodes(ed, ed.changed_cells());
    detail::merge_slivers(ed);
    ed.end();
    report.work = changed_work(ed);
    report.elapsed_ms = watch.ms();
    return report;
}

CutReport Cutter::split_by_plane(
    const Vec3& point, const Vec3& normal, std::span<const Index> cells) {
    Stopwatch watch;
    if (!point.allFinite() || !normal.allFinite() || !(normal.norm() > 0))
        throw InputError("plane", "non-finite point or zero normal");
    auto& ed = m_impl->ed;
    const Vec3 n = normal.normalized();
    CutReport report;
    ed.begin(report);
    detail::PlaneClassifier cls(ed, detail::Plane { n, n.dot(point) });
    std::vector<Index> todo(cells.begin(), cells.end());
    if (todo.empty())
        for (Index c = 0; c < ed.m.num_cells(); ++c)
            todo.push_back(c);
    std::vector<Index> ok;
    for (Index c : todo) {
        if (c < 0 || c >= ed.m.num_cells())
            throw InputError("cells", "cell id " + std::to_string(c) + " out of range");
        bool plus = false, minus = false;
        for (Index v : at(ed.m.cells, c).nodes) {
            plus = plus || cls.sign(v) > 0;
            minus = minus || cls.sign(v) < 0;
        }
        if (!plus || !minus)
            continue;
        if (detail::can_split_cell(ed, cls, c))
            ok.push_back(c);
        else
            ++report.cells_skipped;
    }
    std::vector<Index> interfaces;
    for (Index c : ok)
        detail::split_cell(ed, cls, c, interfaces);
    detail::fix_pinched_edges(ed);
    detail::merge_slivers(ed);
    ed.end();
    report.elapsed_ms = watch.ms();
    return report;
}

CutReport cut_rest(
    mesh::Mesh& mesh, std::span<const Triangle> rest_triangles, const CutOptions& options) {
    Cutter cutter(mesh, options);
    return cutter.cut(rest_triangles);
}

} // namespace polycut::cut
