// The snap cutter's spatial index of tet rest bounds (State::candidates): a uniform grid built
// from every tet's bounds, with the tets touched since then listed apart. A triangle's
// candidates are the tets in the buckets its box overlaps, the touched ones and the ones
// appended since the build, so each triangle costs what lies near it instead of a pass over
// the mesh (issue 12 item 5). The grid is built again when the touched list grows past a
// sixteenth of the mesh or after a compaction renumbered the tets (rebuild_faces()).
#include "checks.hpp"
#include "snap_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace polycut::cut::snap {

namespace {

void build(State& s) {
    State::Grid& g = s.grid;
    const Index n = s.m.num_cells();
    geometry::Aabb all;
    for (Index c = 0; c < n; ++c)
        all.extend(s.bounds(c));
    g.ok = true;
    g.built = n;
    g.dirty.clear();
    g.in_dirty.assign(std::size_t(n), 0);
    g.start.clear();
    g.cells.clear();
    if (all.empty()) {
        g.dims = { 0, 0, 0 };
        return;
    }
    // About one tet per bucket: a tet's bounds then overlap a few buckets.
    const Vec3 ext = all.extent().cwiseMax(1e-12);
    g.h = std::max(std::cbrt(ext.prod() / double(std::max<Index>(n, 1))), 1e-12);
    g.lo = all.lo;
    for (int k = 0; k < 3; ++k)
        g.dims[std::size_t(k)] = std::clamp(int(std::ceil(ext[k] / g.h)), 1, 1024);
    const std::size_t buckets
        = std::size_t(g.dims[0]) * std::size_t(g.dims[1]) * std::size_t(g.dims[2]);
    g.start.assign(buckets + 1, 0);
    auto range = [&](const geometry::Aabb& b, std::array<int, 3>& lo, std::array<int, 3>& hi) {
        for (int k = 0; k < 3; ++k) {
            const int d = g.dims[std::size_t(k)];
            lo[std::size_t(k)] = std::clamp(int(std::floor((b.lo[k] - g.lo[k]) / g.h)), 0, d - 1);
            hi[std::size_t(k)] = std::clamp(int(std::floor((b.hi[k] - g.lo[k]) / g.h)), 0, d - 1);
        }
    };
    auto each = [&](Index c, auto&& f) {
        const geometry::Aabb& box = s.bounds(c);
        if (box.empty())
            return; // a deleted tet, compacted away before the next query
        std::array<int, 3> lo {}, hi {};
        range(box, lo, hi);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x)
                    f((std::size_t(z) * std::size_t(g.dims[1]) + std::size_t(y))
                            * std::size_t(g.dims[0])
                        + std::size_t(x));
    };
    for (Index c = 0; c < n; ++c)
        each(c, [&](std::size_t b) { ++g.start[b + 1]; });
    for (std::size_t b = 0; b < buckets; ++b)
        g.start[b + 1] += g.start[b];
    g.cells.resize(std::size_t(g.start[buckets]));
    std::vector<int> fill(g.start.begin(), g.start.end() - 1);
    for (Index c = 0; c < n; ++c)
        each(c, [&](std::size_t b) { g.cells[std::size_t(fill[b]++)] = c; });
}

} // namespace

const std::vector<Index>& State::candidates(const geometry::Aabb& b) {
    Grid& g = grid;
    const Index n = m.num_cells();
    if (!g.ok || std::size_t(g.built) > std::size_t(n) + g.dirty.size() + 1024
        || g.dirty.size() > 32 + std::size_t(n) / 16)
        build(*this);
    g.found.clear();
    if (g.stamp.size() < std::size_t(n))
        g.stamp.resize(std::size_t(n), g.now);
    if (++g.now == 0) { // wrapped: forget every old stamp
        std::fill(g.stamp.begin(), g.stamp.end(), 0u);
        g.now = 1;
    }
    auto take = [&](Index c) {
        if (c < n && at(g.stamp, c) != g.now) {
            at(g.stamp, c) = g.now;
            g.found.push_back(c);
        }
    };
    if (!b.empty() && g.dims[0] > 0) {
        std::array<int, 3> lo {}, hi {};
        bool outside = false;
        for (int k = 0; k < 3; ++k) {
            const int d = g.dims[std::size_t(k)];
            const double l = std::floor((b.lo[k] - g.lo[k]) / g.h);
            const double h = std::floor((b.hi[k] - g.lo[k]) / g.h);
            outside = outside || h < 0 || l > d - 1;
            lo[std::size_t(k)] = int(std::clamp(l, 0.0, double(d - 1)));
            hi[std::size_t(k)] = int(std::clamp(h, 0.0, double(d - 1)));
        }
        for (int z = lo[2]; !outside && z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    const std::size_t k = (std::size_t(z) * std::size_t(g.dims[1]) + std::size_t(y))
                            * std::size_t(g.dims[0])
                        + std::size_t(x);
                    for (int i = g.start[k]; i < g.start[k + 1]; ++i)
                        take(g.cells[std::size_t(i)]);
                }
    }
    for (Index c : g.dirty)
        take(c);
    for (Index c = g.built; c < n; ++c)
        take(c);
    std::sort(g.found.begin(), g.found.end());
    if (detail::incremental_checks()) {
        // Every tet whose bounds overlap b must be among the candidates.
        for (Index c = 0; c < n; ++c)
            if (bounds(c).overlaps(b) && !std::binary_search(g.found.begin(), g.found.end(), c))
                throw std::logic_error(
                    "snap cutter: the cell grid misses tet " + std::to_string(c));
    }
    return g.found;
}

} // namespace polycut::cut::snap
