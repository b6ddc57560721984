// The octree's leaves: splitting to the surface and region sizes, 2:1 balance, kept flags, and
// 1-to-8 refinement (octree_mesh.cpp turns the leaves into cells).
//
// Coordinates are integers in units of the finest allowed level (max_depth below the base
// cells), so every corner, centre and neighbour query is exact.
#include "polycut/meshing/octree.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::meshing {
namespace {
/// Levels below a cell of edge `base` [m] until its edge is at most `size` [m].
int levels_for(double base, double size) {
    if (!(size > 0) || size >= base)
        return 0;
    return int(std::ceil(std::log2(base / size) - 1e-9));
}
} // namespace

Octree::Octree(const OctreeOptions& options, SignedValue value)
    : m_options(options)
    , m_value(std::move(value)) {
    const Vec3 extent = options.hi - options.lo;
    if (!options.lo.allFinite() || !options.hi.allFinite() || !(extent.minCoeff() > 0))
        throw InputError("lo", "the domain box must have finite corners with hi > lo [m]");
    if (!(options.cell_size > 0) || !std::isfinite(options.cell_size))
        throw InputError("cell_size", "must be a finite length > 0 [m]");
    if (!(options.surface_cell_size >= 0) || !std::isfinite(options.surface_cell_size))
        throw InputError("surface_cell_size", "must be a finite length >= 0 [m]");
    if (options.max_depth < 0 || options.max_depth > kMaxDepth)
        throw InputError("max_depth", "must be in [0, " + std::to_string(kMaxDepth) + "] (levels)");
    for (int a = 0; a < 3; ++a) {
        const double n = std::max(1.0, std::round(extent[a] / options.cell_size));
        if (n > 4096)
            throw InputError("cell_size",
                "gives " + std::to_string(long(n)) + " base cells along an axis (at most 4096)");
        m_blocks[a] = int(n);
    }
    const double base = (extent.array() / m_blocks.cast<double>().array()).maxCoeff();
    m_max_depth = options.max_depth;
    m_unit = extent.array() / (m_blocks.cast<double>().array() * double(1 << m_max_depth));
    m_surface_level = std::min(m_max_depth,
        levels_for(base, options.surface_cell_size > 0 ? options.surface_cell_size : base));
    for (std::size_t i = 0; i < options.regions.size(); ++i) {
        const OctreeRegion& r = options.regions[i];
        const std::string at = "regions/" + std::to_string(i);
        if (!r.lo.allFinite() || !r.hi.allFinite() || !((r.hi - r.lo).minCoeff() > 0))
            throw InputError(at, "needs finite corners with hi > lo [m]");
        if (!(r.cell_size > 0) || !std::isfinite(r.cell_size))
            throw InputError(at + "/cell_size", "must be a finite length > 0 [m]");
        m_region_levels.push_back(std::min(m_max_depth, levels_for(base, r.cell_size)));
    }

    const int unit_per_block = 1 << m_max_depth;
    for (int k = 0; k < m_blocks.z(); ++k)
        for (int j = 0; j < m_blocks.y(); ++j)
            for (int i = 0; i < m_blocks.x(); ++i) {
                Node n;
                n.lo = { i * unit_per_block, j * unit_per_block, k * unit_per_block };
                n.size = unit_per_block;
                m_nodes.push_back(n);
            }
    const int roots = int(m_nodes.size());
    for (int r = 0; r < roots; ++r)
        split_to(r);
    balance();
    for (Node& n : m_nodes)
        if (n.first_child < 0)
            n.kept = may_overlap(n);
}

Vec3 Octree::position(const std::array<int, 3>& p) const {
    return m_options.lo + Vec3(p[0] * m_unit.x(), p[1] * m_unit.y(), p[2] * m_unit.z());
}

Vec3 Octree::leaf_size(int leaf) const {
    return m_unit * double(m_nodes[std::size_t(leaf)].size);
}

bool Octree::in_domain(const std::array<int, 3>& p) const {
    const int u = 1 << m_max_depth;
    for (int a = 0; a < 3; ++a)
        if (p[std::size_t(a)] < 0 || p[std::size_t(a)] >= m_blocks[a] * u)
            return false;
    return true;
}

bool Octree::may_overlap(const Node& n) const {
    if (!m_value)
        return true;
    const Vec3 lo = position(n.lo);
    const Vec3 size = m_unit * double(n.size);
    const double value = m_value(lo + 0.5 * size);
    return m_options.keep == OctreeOptions::Keep::Cover ? value < 0.5 * size.norm() : value < 0;
}

int Octree::target_level(const Node& n) const {
    int level = 0;
    const Vec3 lo = position(n.lo);
    const Vec3 hi = lo + m_unit * double(n.size);
    if (m_value && m_surface_level > 0) {
        // the surface may cross the cell: |value| within the half-diagonal
        const double half_diagonal = 0.5 * (hi - lo).norm();
        if (std::abs(m_value(0.5 * (lo + hi))) <= half_diagonal)
            level = m_surface_level;
    }
    for (std::size_t i = 0; i < m_region_levels.size(); ++i) {
        const OctreeRegion& r = m_options.regions[i];
        if ((lo.array() < r.hi.array()).all() && (hi.array() > r.lo.array()).all())
            level = std::max(level, m_region_levels[i]);
    }
    return level;
}

int Octree::split(int node) {
    const Node parent = m_nodes[std::size_t(node)];
    if (parent.first_child >= 0 || parent.level >= m_max_depth)
        return 0;
    const int first = int(m_nodes.size());
    const int half = parent.size / 2;
    for (int c = 0; c < 8; ++c) {
        Node child;
        child.lo = { parent.lo[0] + (c & 1) * half, parent.lo[1] + ((c >> 1) & 1) * half,
            parent.lo[2] + ((c >> 2) & 1) * half };
        child.size = half;
        child.level = parent.level + 1;
        child.kept = parent.kept;
        m_nodes.push_back(child);
    }
    m_nodes[std::size_t(node)].first_child = first;
    return 1;
}

void Octree::split_to(int node) {
    std::vector<int> todo { node };
    while (!todo.empty()) {
        const int n = todo.back();
        todo.pop_back();
        if (m_nodes[std::size_t(n)].level >= target_level(m_nodes[std::size_t(n)]))
            continue;
        if (!split(n))
            continue;
        const int first = m_nodes[std::size_t(n)].first_child;
        for (int c = 0; c < 8; ++c)
            todo.push_back(first + c);
    }
}

int Octree::leaf_at(const std::array<int, 3>& p) const {
    if (!in_domain(p))
        return -1;
    const int u = 1 << m_max_depth;
    int n = (p[0] / u) + m_blocks.x() * ((p[1] / u) + m_blocks.y() * (p[2] / u));
    while (m_nodes[std::size_t(n)].first_child >= 0) {
        const Node& node = m_nodes[std::size_t(n)];
        const int half = node.size / 2;
        int c = 0;
        for (int a = 0; a < 3; ++a)
            if (p[std::size_t(a)] >= node.lo[std::size_t(a)] + half)
                c |= 1 << a;
        n = node.first_child + c;
    }
    return n;
}

// 2:1 across faces, edges and corners: a leaf's 26 neighbour points must lie in leaves at most
// one level coarser. Repeated until nothing splits (each pass only splits, so it ends).
void Octree::balance() {
    bool changed = true;
    while (changed) {
        changed = false;
        for (int n = 0; n < int(m_nodes.size()); ++n) {
            if (m_nodes[std::size_t(n)].first_child >= 0)
                continue;
            for (int d = 0; d < 27; ++d) {
                if (d == 13)
                    continue;
                const Node& node = m_nodes[std::size_t(n)];
                if (node.level < 2)
                    break;
                std::array<int, 3> p {};
                int dd = d;
                for (int a = 0; a < 3; ++a, dd /= 3) {
                    const int step = dd % 3 - 1;
                    p[std::size_t(a)] = step < 0 ? node.lo[std::size_t(a)] - 1
                        : step > 0               ? node.lo[std::size_t(a)] + node.size
                                                 : node.lo[std::size_t(a)];
                }
                const int other = leaf_at(p);
                if (other >= 0 && m_nodes[std::size_t(other)].level < node.level - 1) {
                    split(other);
                    changed = true;
                }
            }
        }
    }
}

int Octree::refine(const std::vector<int>& leaves) {
    const std::size_t before = m_nodes.size();
    for (int leaf : leaves)
        if (leaf >= 0 && leaf < int(m_nodes.size()))
            split(leaf);
    balance();
    return int((m_nodes.size() - before) / 8);
}

int Octree::num_kept() const {
    return int(std::count_if(
        m_nodes.begin(), m_nodes.end(), [](const Node& n) { return n.first_child < 0 && n.kept; }));
}

std::vector<int> Octree::kept_per_level() const {
    std::vector<int> out(std::size_t(m_max_depth + 1), 0);
    for (const Node& n : m_nodes)
        if (n.first_child < 0 && n.kept)
            ++out[std::size_t(n.level)];
    return out;
}

} // namespace polycut::meshing
