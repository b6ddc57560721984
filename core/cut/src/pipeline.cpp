// cut::CutPipeline: validate, map to rest space, snap, cut within a budget (see pipeline.hpp).
#include "polycut/cut/pipeline.hpp"

#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/cut/completeness.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/cut/world_to_rest.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "stroke_snap.hpp"
#include "sweep_strip.hpp"
#include "undo_journal.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace polycut::cut {

namespace {

/// Mechanical sanity after the cutter (issue 12 item 3): each cell it changed must be a closed,
/// consistently oriented polyhedron. A geometric corner case the cutter gets wrong (a fuzz input
/// left a flipped face in a re-cut hex grid) becomes a failed cut, undone, instead of a model
/// built on a broken cell. O(cells changed).
void require_closed_cells(const mesh::Mesh& mesh, const CutReport& report) {
    for (Index c : report.changed_cells) {
        if (c < 0 || c >= mesh.num_cells())
            continue;
        if (const std::string why = open_cell_problem(mesh, c); !why.empty())
            throw Error(
                "cut", "cell " + std::to_string(c) + " is not closed after the cut: " + why);
    }
}

geometry::Aabb triangle_box(const Triangle& t) {
    geometry::Aabb b;
    for (const Vec3& p : t)
        b.extend(p);
    return b;
}

geometry::Aabb grown(geometry::Aabb b, double margin) {
    b.extend(b.lo - Vec3::Constant(margin));
    b.extend(b.hi + Vec3::Constant(margin));
    return b;
}

/// Shape quality 4 sqrt(3) area / (sum of squared edges): 1 for an equilateral triangle, 0 for
/// collinear or coincident corners; scale-invariant.
double quality(const Triangle& t) {
    const double sum_sq
        = (t[1] - t[0]).squaredNorm() + (t[2] - t[1]).squaredNorm() + (t[0] - t[2]).squaredNorm();
    if (!(sum_sq > 0))
        return 0;
    return 2 * std::sqrt(3.0) * (t[1] - t[0]).cross(t[2] - t[0]).norm() / sum_sq;
}

double mean_cell_size(const mesh::Mesh& m) {
    return std::cbrt(m.rest_volume() / double(std::max<Index>(1, m.num_cells())));
}

/// A sweep corner of the current stroke already mapped to rest space, with the rest plane of the
/// triangle that mapped it.
struct StrokeCorner {
    Vec3 world; ///< [m]
    Vec3 rest; ///< [m]
    Vec3 normal; ///< unit normal of the rest plane
    double offset = 0; ///< normal . x of the rest plane [m]
    Vec3 world_normal = Vec3::Zero(); ///< unit normal of the world triangle that mapped it
    double world_offset = 0; ///< world_normal . x of that triangle's plane [m]
};

// Tolerances of the mapping, relative to the uncut mesh's mean cell size (the tolerances do not
// shrink as cuts add cells).
// A straight stroke through a deforming tissue stays in one rest plane: new corners within
// kStrokePlane of the predecessor's rest plane (or of its world plane) go onto its rest plane.
constexpr double kStrokePlane = 0.05;
// A blade within kFacePlane of the plane of a face of the cells it meets goes into that plane
// (detail::snap_to_face_plane, docs/decisions/0005); the faces of an earlier cut whose nodes lie
// within it of a sweep triangle's plane count as already cut under the triangle (the cutter's
// snapped nodes sit up to ~0.01 mm off its plane).
constexpr double kFacePlane = 0.02;
// A blade nearly parallel to the faces of an earlier cut and within kRecutPlane of their plane
// follows that cut (the re-cut rule of detail::snap_to_face_plane, docs/decisions/0054).
constexpr double kRecutPlane = 0.25;
// A face-snapped cut runs along mesh faces within about one mean cell size (~0.6 of a tet edge)
// of the blade's plane: its lips there count as the part of a re-cut already cut.
constexpr double kSnapBeside = 1.0;
// A new corner within kEdgeSnap of a node of the uncut mesh or of the chord its plane cuts from a
// face goes onto it (detail::snap_corner_to_features, docs/decisions/0007; cell splitting only).
constexpr double kEdgeSnap = 0.05;
// Below this area (relative to L^2, L the tissue's diagonal) or altitude (relative to L) a
// triangle cuts nothing; the cutters reject such rest triangles, so they are skipped here first.
constexpr double kMinSweepArea = 2 * CutOptions {}.min_area;
// A triangle whose shape quality is below this is not a triangle (collinear corners): rejected.
constexpr double kMinQuality = 1e-6;
// Corners farther than this many tissue diagonals from the tissue are rejected.
constexpr double kMaxDistance = 1e3;
// Only the recent corners can be shared by the next triangles of a stroke.
constexpr std::size_t kKeepCorners = 64;
// A coarsened strip's dropped samples stay within this fraction of the minimum advance of the
// coarse quads' edges (0.125 mm on the default block, 35 um on the 5k organ).
constexpr double kStripTolerance = 0.05;
} // namespace

struct CutPipeline::Impl {
    Impl(mesh::Mesh& m, const mesh::Mesh& u, PipelineOptions o)
        : mesh(m)
        , uncut(u)
        , opt(o)
        , cell_size(mean_cell_size(u))
        , journal(m) { }

    mesh::Mesh& mesh;
    const mesh::Mesh& uncut;
    PipelineOptions opt;
    double cell_size = 0;
    std::unique_ptr<Cutter> splitter;
    std::unique_ptr<SnapCutter> snapper;
    /// Corners of the current stroke: a corner the blade shares with an earlier triangle reuses
    /// its rest image, so consecutive triangles meet exactly in rest space.
    std::vector<StrokeCorner> corners;
    /// Uniform grid over the deformed cell bounds (refitted once per call, when first needed).
    std::unique_ptr<WorldToRest> world_grid;
    /// Uniform grid over the uncut mesh at rest (built once).
    std::unique_ptr<WorldToRest> rest_grid;
    /// The current stroke began on the plane of an earlier cut (it follows that cut).
    bool following = false;
    /// Per mapped rest triangle of the last map(): its area on earlier Cut faces [m^2].
    std::vector<double> overlap;
    /// The mesh before the last call that changed it (undo()).
    detail::UndoJournal journal;

    bool snap() const { return opt.method == CutMethod::Snap; }

    void ensure_cutter() {
        if (snap() && !snapper)
            snapper = std::make_unique<SnapCutter>(mesh, opt.snap);
        else if (!snap() && !splitter)
            splitter = std::make_unique<Cutter>(mesh, opt.split);
    }

    /// Tells the world grid which cells a call changed (its flat node lists).
    void cells_changed(const CutReport& r) {
        if (!world_grid)
            return;
        const bool renumbered = !r.cell_map.empty() || !r.node_map.empty()
            || !r.removed_cells.empty() || !r.removed_nodes.empty() || r.slivers_merged > 0;
        world_grid->cells_changed(r.changed_cells, renumbered);
    }

    const WorldToRest& rest_cells() {
        if (!rest_grid) {
            rest_grid = std::make_unique<WorldToRest>(uncut);
            rest_grid->refit(uncut.rest, false);
        }
        return *rest_grid;
    }

    const StrokeCorner* cached(const Vec3& p, double same) const {
        for (const StrokeCorner& c : corners)
            if ((c.world - p).norm() <= same)
                return &c;
        return nullptr;
    }

    /// Checks every world triangle (nothing changes on rejection).
    bool validate(
        std::span<const Triangle> world, std::span<const Vec3> positions, CutResult& result) const {
        auto reject = [&](std::size_t t, int corner, std::string reason) {
            result.status = CutStatus::Rejected;
            result.rejected_triangle = std::ptrdiff_t(t);
            result.rejected_corner = corner;
            result.reason = std::move(reason);
            return false;
        };
        if (world.empty())
            return reject(0, -1, "needs at least one sweep triangle");
        geometry::Aabb tissue;
        for (const Vec3& p : positions)
            tissue.extend(p);
        const double L = tissue.diagonal();
        for (std::size_t t = 0; t < world.size(); ++t) {
            for (std::size_t k = 0; k < 3; ++k) {
                if (!world[t][k].allFinite())
                    return reject(t, int(k), "must be finite");
                if ((world[t][k] - tissue.center()).norm() > kMaxDistance * L)
                    return reject(t, int(k), "is absurdly far from the tissue");
            }
            if (world[t][0] == world[t][1] || world[t][1] == world[t][2]
                || world[t][2] == world[t][0])
                return reject(t, -1, "coincident corners");
            if (const double q = quality(world[t]); !(q >= kMinQuality))
                return reject(t, -1,
                    "degenerate triangle: quality " + std::to_string(q) + " < "
                        + std::to_string(kMinQuality) + " (zero area relative to its size)");
        }
        return true;
    }

    /// Whether the rest image r of world triangle w is longer or larger than kMaxRestStretch
    /// times w: mapped through folded or crushed tissue.
    static bool stretched(const Triangle& w, const Triangle& r) {
        const auto longest = [](const Triangle& t) {
            return std::max({ (t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm() });
        };
        const auto area
            = [](const Triangle& t) { return 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm(); };
        return longest(r) > kMaxRestStretch * longest(w) || area(r) > kMaxRestStretch * area(w);
    }

    /// Tets (of `near`) whose world positions have turned them inside out, for the call's
    /// CutResult::inverted_cells. Polyhedral cells are not checked (an affine fit per cell would
    /// cost more than the mapping).
    std::vector<Index> inverted;
    void note_inverted(const std::vector<Index>& near, std::span<const Vec3> positions) {
        for (Index c : near) {
            const auto& n = mesh.cells[std::size_t(c)].nodes;
            if (n.size() != 4)
                continue;
            const auto x = [&](std::size_t k) { return positions[std::size_t(n[k])]; };
            const auto X = [&](std::size_t k) { return mesh.rest[std::size_t(n[k])]; };
            const double world = (x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0));
            const double rest = (X(1) - X(0)).cross(X(2) - X(0)).dot(X(3) - X(0));
            if (world * rest < 0)
                inverted.push_back(c);
        }
    }

    /// World to rest (DESIGN.md sec. 3): each triangle through ONE least-squares affine fit of
    /// the nodes of the cells whose deformed bounds it touches. WorldToRest::map_triangle maps
    /// each corner through its own cell instead; for sweeps whose corners lie far outside the
    /// tissue that extrapolates from single boundary cells and tilts the plane, so the joint fit
    /// stays. Exact where the deformation is affine over those cells (always at rest). Corners
    /// shared with earlier triangles of the stroke reuse their rest image; new corners close to
    /// the predecessor's plane go onto it (a straight stroke is one rest plane, and does not
    /// re-split the cells along its crack into slivers every tick). `source[i]`: the input index
    /// of rest triangle i.
    std::vector<Triangle> map(std::span<const Triangle> world, std::span<const Vec3> positions,
        std::vector<std::size_t>& source, CutResult& result) {
        geometry::Aabb tissue;
        for (const Vec3& p : positions)
            tissue.extend(p);
        const double L = tissue.diagonal();
        const double same = 1e-9 * L;
        bool located = false;
        std::vector<Triangle> rest;
        overlap.clear();
        for (std::size_t t = 0; t < world.size(); ++t) {
            const Triangle& tri = world[t];
            // A sliver of a sweep (the blade barely moved between two samples) cuts nothing at
            // the tissue's scale: skipped, not an error, so a slow stroke is never rejected.
            const double area = 0.5 * (tri[1] - tri[0]).cross(tri[2] - tri[0]).norm();
            if (!(area > kMinSweepArea * L * L)) {
                ++result.skipped;
                continue;
            }
            Triangle r;
            bool mapped = false; // a corner of it went through the world grid's fit
            std::array<bool, 3> known {};
            const StrokeCorner* previous = nullptr;
            for (std::size_t k = 0; k < 3; ++k)
                if (const StrokeCorner* c = cached(tri[k], same)) {
                    r[k] = c->rest;
                    known[k] = true;
                    previous = previous ? previous : c;
                }
            if (!(known[0] && known[1] && known[2])) {
                if (!world_grid)
                    world_grid = std::make_unique<WorldToRest>(mesh);
                if (!located) {
                    // Only the cells around this call's triangles are indexed.
                    geometry::Aabb region;
                    for (std::size_t u = t; u < world.size(); ++u)
                        region.extend(grown(triangle_box(world[u]), cell_size));
                    world_grid->refit_near(positions, region);
                    located = true;
                }
                const std::vector<Index> near = world_grid->candidates(triangle_box(tri));
                mapped = true;
                const std::size_t inverted_before = inverted.size();
                note_inverted(near, positions);
                const bool folded = inverted.size() > inverted_before;
                std::set<Index> nodes;
                for (Index c : near)
                    nodes.insert(mesh.cells[std::size_t(c)].nodes.begin(),
                        mesh.cells[std::size_t(c)].nodes.end());
                if (nodes.size() < 4) {
                    ++result.skipped; // outside the tissue: nothing to cut
                    continue;
                }
                std::vector<Vec3> X, x;
                for (Index n : nodes) {
                    X.push_back(mesh.rest[std::size_t(n)]);
                    x.push_back(positions[std::size_t(n)]);
                }
                const geometry::AffineFit fit = geometry::fit_affine(X, x);
                if (!fit.ok || std::abs(fit.A.determinant()) < 1e-12) {
                    ++result.skipped;
                    continue;
                }
                const Mat3 Ainv = fit.A.inverse();
                for (std::size_t k = 0; k < 3; ++k)
                    if (!known[k])
                        r[k] = Ainv * (tri[k] - fit.t);
                if (!folded && stretched(tri, r)) {
                    // One fit over every node of the cells the triangle's bounds meet averages
                    // a deformation that varies across them (a soft block pressed flat above its
                    // fixed base: a 6 cm blade came out 15-23 cm long and was not cut at all):
                    // the triangle's own map, fitted to the points of it inside the tissue. Not
                    // through a fold (tets turned inside out around it): there no map is one to
                    // one, and the own fit's images cut what the blade did not pass (the pressed
                    // organ_5k's lips came out 2.2 times the swept area in world space, 0.65
                    // with those triangles skipped).
                    if (const auto own = world_grid->fit_triangle(tri, positions, 0.5 * cell_size))
                        for (std::size_t k = 0; k < 3; ++k)
                            if (!known[k])
                                r[k] = (*own)[k];
                }
                for (std::size_t k = 0; k < 3; ++k)
                    if (!known[k]) {
                        if (previous) {
                            // In the previous triangle's plane in world space (a straight
                            // stroke), or close to its rest plane: onto that rest plane. The
                            // first test does not depend on the fit, which extrapolates for
                            // corners outside the tissue and errs by a few percent of a cell on
                            // a sagging body.
                            const double dw
                                = previous->world_normal.dot(tri[k]) - previous->world_offset;
                            const double d = previous->normal.dot(r[k]) - previous->offset;
                            if (std::abs(dw) <= kStrokePlane * cell_size
                                || std::abs(d) <= kStrokePlane * cell_size)
                                r[k] -= d * previous->normal;
                        }
                    }
                // The re-cut rule at the stroke's first triangle only: later corners follow the
                // stroke's plane, and the stroke's own cut faces must not pull them back.
                const bool first = !known[0] && !known[1] && !known[2];
                const bool on_cut = detail::snap_to_face_plane(mesh, near, r, known,
                    kFacePlane * cell_size, same, first ? kRecutPlane * cell_size : 0.0, L);
                if (first)
                    following = on_cut;
                // Cell splitting only: face snapping moves nodes onto the blade itself.
                const Vec3 rn = (r[1] - r[0]).cross(r[2] - r[0]).normalized();
                for (std::size_t k = 0; k < 3 && !snap(); ++k) {
                    if (known[k] || !rn.allFinite())
                        continue;
                    geometry::Aabb around;
                    around.extend(r[k] - Vec3::Constant(kEdgeSnap * cell_size));
                    around.extend(r[k] + Vec3::Constant(kEdgeSnap * cell_size));
                    detail::snap_corner_to_features(uncut, rest_cells().candidates(around), r[k],
                        rn, rn.dot(r[(k + 1) % 3]), kEdgeSnap * cell_size, same);
                }
            }
            const Vec3 normal = (r[1] - r[0]).cross(r[2] - r[0]);
            const double longest
                = std::max({ (r[1] - r[0]).norm(), (r[2] - r[1]).norm(), (r[0] - r[2]).norm() });
            if (!(0.5 * normal.norm() > kMinSweepArea * L * L)
                || !(normal.norm() / longest > kMinSweepArea * L)) {
                ++result.skipped; // collapsed in rest space: nothing to cut
                continue;
            }
            if (mapped && stretched(tri, r)) {
                ++result.skipped; // through a fold: see kMaxRestStretch
                ++result.stretched;
                continue;
            }
            const Vec3 n = normal.normalized();
            const Vec3 world_n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
            for (std::size_t k = 0; k < 3; ++k)
                if (!known[k])
                    corners.push_back(
                        { tri[k], r[k], n, n.dot(r[k]), world_n, world_n.dot(tri[k]) });
            // The part already cut (a stroke along an earlier cut) is not swept again; the cells
            // around it from a cell farther out: both lips, however far the body opened them.
            double on_cut = 0;
            if (following && mapped)
                on_cut = area_on_cut_faces(mesh,
                    world_grid->candidates(grown(triangle_box(tri), cell_size)), r,
                    (snap() ? kSnapBeside : kFacePlane) * cell_size);
            overlap.push_back(on_cut);
            rest.push_back(r);
            source.push_back(t);
        }
        if (corners.size() > kKeepCorners)
            corners.erase(corners.begin(), corners.end() - std::ptrdiff_t(kKeepCorners));
        return rest;
    }
};

CutPipeline::CutPipeline(mesh::Mesh& mesh, const mesh::Mesh& uncut, PipelineOptions options)
    : m_impl(std::make_unique<Impl>(mesh, uncut, options)) { }

CutPipeline::~CutPipeline() = default;

double CutPipeline::cell_size() const {
    return m_impl->cell_size;
}

void CutPipeline::prepare() {
    Impl& s = *m_impl;
    s.ensure_cutter();
    s.rest_cells();
    // Room for what cuts append to the mesh, so the first cut does not move every cell and
    // face (a no-op where the room is there).
    s.mesh.cells.reserve(s.mesh.cells.size() + s.mesh.cells.size() / 2 + 64);
    s.mesh.faces.reserve(s.mesh.faces.size() + s.mesh.faces.size() / 2 + 64);
    s.mesh.rest.reserve(s.mesh.rest.size() + s.mesh.rest.size() / 2 + 64);
    // The world grid's copy of the node lists, made here and not in the first cut's tick.
    if (!s.world_grid)
        s.world_grid = std::make_unique<WorldToRest>(s.mesh);
    s.world_grid->prepare();
}

void CutPipeline::undo() {
    Impl& s = *m_impl;
    s.journal.undo(s.mesh);
    forget();
}

void CutPipeline::accept() {
    m_impl->journal.accept(m_impl->mesh);
}

void CutPipeline::undo_all() {
    Impl& s = *m_impl;
    s.journal.undo_all(s.mesh);
    forget();
}

std::uint64_t CutPipeline::whole_mesh_copies() const {
    return m_impl->journal.whole_copies();
}

std::uint64_t CutPipeline::mirror_face_moves() const {
    return m_impl->journal.face_moves();
}

void CutPipeline::forget() {
    Impl& s = *m_impl;
    s.splitter.reset();
    s.snapper.reset();
    s.corners.clear();
    s.following = false;
    s.world_grid.reset();
}

CutResult CutPipeline::cut(std::span<const Triangle> world, std::span<const Vec3> positions,
    Index max_changed_cells, const std::function<void()>& before_change,
    std::size_t max_triangles) {
    Impl& s = *m_impl;
    CutResult result;
    if (!s.validate(world, positions, result))
        return result;
    // A cap on the triangles of one call bounds the work that grows faster than the cells
    // changed (issue 14 item 1). Every triangle is validated above; only the first
    // max_triangles are mapped and cut now (mapping is per call: mapping all of a long request
    // at every tick would cost O(T) per tick), and the rest is deferred like the cell budget's.
    const std::span<const Triangle> now
        = max_triangles > 0 && world.size() > max_triangles ? world.first(max_triangles) : world;
    // A strip sampled finer than the blade resolution is swept as the server sweeps scalpel
    // samples (sweep_strip.hpp): `first` maps each coarse triangle back to the input.
    const detail::CoarseSweep coarse = detail::coarsen_strips(
        now, s.snap() ? 0.0 : s.opt.strip_min_advance, kStripTolerance * s.opt.strip_min_advance);
    std::vector<std::size_t> source;
    s.inverted.clear();
    const std::vector<Triangle> rest = s.map(coarse.triangles, positions, source, result);
    std::sort(s.inverted.begin(), s.inverted.end());
    result.inverted_cells
        = std::size_t(std::unique(s.inverted.begin(), s.inverted.end()) - s.inverted.begin());
    result.consumed = now.size();
    if (now.size() < world.size()) {
        result.status = CutStatus::Deferred;
        result.deferred = world.size() - now.size();
    }
    if (rest.empty())
        return result;
    // Rest area the first `count` triangles sweep inside the uncut tissue, less what lies on
    // earlier cuts; a failed call reports it too (the blade swept it; get_stats counts it).
    const auto swept = [&](std::size_t count) {
        double area = 0;
        for (std::size_t i = 0; i < count; ++i)
            area += std::max(0.0,
                area_inside(s.uncut, s.rest_cells().candidates(triangle_box(rest[i])), rest[i])
                    - s.overlap[i]);
        return area;
    };
    // The previous call is accepted now: the undo mirror takes what it changed.
    s.journal.commit(s.mesh);
    try {
        s.ensure_cutter();
        if (before_change)
            before_change();
        std::vector<char> may_stop(rest.size());
        for (std::size_t i = 0; i < rest.size(); ++i)
            may_stop[i] = coarse.may_stop[source[i]];
        result.report = s.snap() ? s.snapper->cut(rest, max_changed_cells)
                                 : s.splitter->cut(rest, max_changed_cells, may_stop);
        s.journal.record(result.report);
        s.cells_changed(result.report);
        require_closed_cells(s.mesh, result.report);
    } catch (const std::exception& e) {
        result.status = CutStatus::Failed;
        result.reason = e.what();
        result.swept_area = swept(rest.size());
        return result;
    }
    const std::size_t applied = std::size_t(result.report.triangles);
    result.cut = applied;
    if (applied < rest.size()) {
        // The budget was reached after rest triangle applied-1: the input from the next mapped
        // triangle on waits (its corners stay mapped, so it cuts the same rest triangle later).
        result.status = CutStatus::Deferred;
        const std::size_t resume = source[applied]; // a coarse triangle
        result.skipped = 0;
        for (std::size_t t = 0, i = 0; t < resume; ++t)
            if (i < applied && source[i] == t)
                ++i;
            else
                ++result.skipped;
        result.consumed = coarse.first[resume];
        result.deferred = world.size() - result.consumed;
    }
    result.swept_area = swept(applied);
    return result;
}

CutResult CutPipeline::end_stroke(const std::function<void()>& before_change) {
    Impl& s = *m_impl;
    s.corners.clear();
    s.following = false;
    CutResult result;
    if (!s.snapper)
        return result;
    s.journal.commit(s.mesh);
    try {
        if (before_change)
            before_change();
        result.report = s.snapper->finish_sweep();
        s.journal.record(result.report);
        s.cells_changed(result.report);
        require_closed_cells(s.mesh, result.report);
    } catch (const std::exception& e) {
        result.status = CutStatus::Failed;
        result.reason = e.what();
    }
    return result;
}

} // namespace polycut::cut
