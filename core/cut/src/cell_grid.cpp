#include "cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::cut::detail {

bool CellGrid::range(
    const geometry::Aabb& b, std::array<int, 3>& lo, std::array<int, 3>& hi) const {
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
        const int d = m_dims[std::size_t(k)];
        const double l = std::floor((b.lo[k] - m_lo[k]) / m_h);
        const double h = std::floor((b.hi[k] - m_lo[k]) / m_h);
        outside = outside || h < 0 || l > d - 1;
        lo[std::size_t(k)] = int(std::clamp(l, 0.0, double(d - 1)));
        hi[std::size_t(k)] = int(std::clamp(h, 0.0, double(d - 1)));
    }
    return !outside;
}

void CellGrid::build(Index n, const std::function<geometry::Aabb(Index)>& box_of) {
    std::vector<geometry::Aabb> boxes(static_cast<std::size_t>(n));
    geometry::Aabb all;
    for (Index c = 0; c < n; ++c) {
        boxes[std::size_t(c)] = box_of(c);
        all.extend(boxes[std::size_t(c)]);
    }
    m_ok = true;
    m_built = n;
    m_dirty.clear();
    m_in_dirty.assign(std::size_t(n), 0);
    m_start.clear();
    m_cells.clear();
    if (all.empty()) {
        m_dims = { 0, 0, 0 };
        return;
    }
    // About one cell per bucket: a cell's box then overlaps a few buckets.
    const Vec3 ext = all.extent().cwiseMax(1e-12);
    m_h = std::max(std::cbrt(ext.prod() / double(std::max<Index>(n, 1))), 1e-12);
    m_lo = all.lo;
    for (int k = 0; k < 3; ++k)
        m_dims[std::size_t(k)] = std::clamp(int(std::ceil(ext[k] / m_h)), 1, 1024);
    const std::size_t buckets
        = std::size_t(m_dims[0]) * std::size_t(m_dims[1]) * std::size_t(m_dims[2]);
    m_start.assign(buckets + 1, 0);
    const auto each = [&](Index c, auto&& f) {
        const geometry::Aabb& box = boxes[std::size_t(c)];
        std::array<int, 3> lo {}, hi {};
        if (box.empty() || !range(box, lo, hi))
            return;
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x)
                    f(bucket(x, y, z));
    };
    for (Index c = 0; c < n; ++c)
        each(c, [&](std::size_t b) { ++m_start[b + 1]; });
    for (std::size_t b = 0; b < buckets; ++b)
        m_start[b + 1] += m_start[b];
    m_cells.resize(std::size_t(m_start[buckets]));
    std::vector<int> fill(m_start.begin(), m_start.end() - 1);
    for (Index c = 0; c < n; ++c)
        each(c, [&](std::size_t b) { m_cells[std::size_t(fill[b]++)] = c; });
}

void CellGrid::renumber(const std::vector<Index>& map) {
    if (!m_ok)
        return;
    const auto to = [&](Index c) {
        return c >= 0 && std::size_t(c) < map.size() ? map[std::size_t(c)] : kNone;
    };
    // Filed cells have ids below m_built and cells added since the build ids from m_built on;
    // an order-keeping map keeps the two apart, at the survivors' count below m_built.
    Index built = 0, last = -1;
    for (Index c = 0; c < Index(map.size()); ++c)
        if (const Index t = to(c); t != kNone) {
            if (t <= last) {
                invalidate();
                return;
            }
            last = t;
            built += c < m_built ? 1 : 0;
        }
    for (Index& c : m_cells)
        c = to(c); // a removed cell stays in its buckets as kNone, skipped by query()
    std::vector<Index> dirty;
    for (Index c : m_dirty)
        if (const Index t = to(c); t != kNone)
            dirty.push_back(t);
    m_dirty = std::move(dirty);
    m_built = built;
    m_in_dirty.assign(std::size_t(built), 0);
    for (Index c : m_dirty)
        m_in_dirty[std::size_t(c)] = 1;
}

void CellGrid::touch(Index c) {
    if (m_ok && c < m_built && !m_in_dirty[std::size_t(c)]) {
        m_in_dirty[std::size_t(c)] = 1;
        m_dirty.push_back(c);
    }
}

const std::vector<Index>& CellGrid::query(const geometry::Aabb& box, Index n) {
    m_found.clear();
    if (m_stamp.size() < std::size_t(n))
        m_stamp.resize(std::size_t(n), m_now);
    if (++m_now == 0) { // wrapped: forget every old stamp
        std::fill(m_stamp.begin(), m_stamp.end(), 0u);
        m_now = 1;
    }
    const auto take = [&](Index c) {
        if (c >= 0 && c < n && m_stamp[std::size_t(c)] != m_now) {
            m_stamp[std::size_t(c)] = m_now;
            m_found.push_back(c);
        }
    };
    std::array<int, 3> lo {}, hi {};
    if (!box.empty() && m_dims[0] > 0 && range(box, lo, hi))
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    const std::size_t b = bucket(x, y, z);
                    for (int i = m_start[b]; i < m_start[b + 1]; ++i)
                        take(m_cells[std::size_t(i)]);
                }
    for (Index c : m_dirty)
        take(c);
    for (Index c = m_built; c < n; ++c)
        take(c);
    std::sort(m_found.begin(), m_found.end());
    return m_found;
}

} // namespace polycut::cut::detail
