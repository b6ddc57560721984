#include "polycut/mesh/mesh.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

namespace polycut::mesh {
namespace {
    struct FaceKeyLess {
        bool operator()(const std::vector<Index>& a, const std::vector<Index>& b) const
        {
            return a < b;
        }
    };

    std::vector<Index> sorted_key(const std::vector<Index>& loop)
    {
        std::vector<Index> key = loop;
        std::sort(key.begin(), key.end());
        return key;
    }

    double tet_volume(const std::vector<Vec3>& X, const std::array<Index, 4>& t)
    {
        const Vec3& a = X[std::size_t(t[0])];
        return (X[std::size_t(t[1])] - a).dot((X[std::size_t(t[2])] - a).cross(X[std::size_t(t[3])] - a))
            / 6.0;
    }

    void check_node_ids(const std::vector<Vec3>& rest, long cell, const auto& ids)
    {
        for (auto i : ids)
            if (i < 0 || std::size_t(i) >= rest.size())
                throw MeshError(cell, -1, "node index " + std::to_string(i) + " out of range [0, "
                        + std::to_string(rest.size()) + ")");
    }
} // namespace

Mesh Mesh::from_polyhedra(std::vector<Vec3> rest,
    const std::vector<std::vector<std::vector<Index>>>& cells)
{
    Mesh m;
    m.rest = std::move(rest);
    m.cells.resize(cells.size());
    std::map<std::vector<Index>, Index, FaceKeyLess> by_key;
    for (std::size_t c = 0; c < cells.size(); ++c) {
        Cell& cell = m.cells[c];
        std::set<Index> nodes;
        for (std::size_t lf = 0; lf < cells[c].size(); ++lf) {
            const auto& loop = cells[c][lf];
            check_node_ids(m.rest, long(c), loop);
            if (loop.size() < 3)
                throw MeshError(long(c), long(lf), "face has fewer than 3 nodes");
            nodes.insert(loop.begin(), loop.end());
            auto key = sorted_key(loop);
            if (std::adjacent_find(key.begin(), key.end()) != key.end())
                throw MeshError(long(c), long(lf), "face repeats a node");
            auto [it, inserted] = by_key.try_emplace(std::move(key), Index(m.faces.size()));
            if (inserted) {
                Face f;
                f.nodes = loop;
                f.owner = Index(c);
                m.faces.push_back(std::move(f));
            } else {
                Face& f = m.faces[std::size_t(it->second)];
                if (f.owner == Index(c))
                    throw MeshError(long(c), long(lf), "cell repeats a face");
                if (f.neighbour != kNone)
                    throw MeshError(long(c), long(lf),
                        "face shared by more than two cells (also cells " + std::to_string(f.owner)
                            + " and " + std::to_string(f.neighbour) + ")");
                f.neighbour = Index(c);
                f.tag = FaceTag::Interior;
            }
            cell.faces.push_back(it->second);
        }
        cell.nodes.assign(nodes.begin(), nodes.end());
    }
    for (Index c = 0; c < m.num_cells(); ++c)
        m.classify_cell(c);
    return m;
}

Mesh Mesh::from_tets(std::vector<Vec3> rest, const std::vector<std::array<Index, 4>>& tets)
{
    std::vector<std::vector<std::vector<Index>>> loops(tets.size());
    for (std::size_t c = 0; c < tets.size(); ++c) {
        auto t = tets[c];
        check_node_ids(rest, long(c), t);
        if (tet_volume(rest, t) < 0)
            std::swap(t[1], t[2]);
        for (const auto& f : kTetFaces)
            loops[c].push_back({ t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])] });
    }
    return from_polyhedra(std::move(rest), loops);
}

Mesh Mesh::from_hexes(std::vector<Vec3> rest, const std::vector<std::array<Index, 8>>& hexes)
{
    std::vector<std::vector<std::vector<Index>>> loops(hexes.size());
    for (std::size_t c = 0; c < hexes.size(); ++c) {
        check_node_ids(rest, long(c), hexes[c]);
        for (const auto& f : kHexFaces) {
            std::vector<Index> loop;
            for (int i : f)
                loop.push_back(hexes[c][std::size_t(i)]);
            loops[c].push_back(std::move(loop));
        }
    }
    return from_polyhedra(std::move(rest), loops);
}

std::vector<Index> Mesh::face_loop(Index f, Index c) const
{
    const Face& face = faces[std::size_t(f)];
    std::vector<Index> loop = face.nodes;
    if (face.owner != c)
        std::reverse(loop.begin(), loop.end());
    return loop;
}

std::vector<std::vector<Index>> Mesh::cell_face_loops(Index c) const
{
    std::vector<std::vector<Index>> loops;
    for (Index f : cells[std::size_t(c)].faces)
        loops.push_back(face_loop(f, c));
    return loops;
}

double Mesh::cell_volume(Index c) const
{
    return geometry::polyhedron_volume(rest, cell_face_loops(c));
}

Vec3 Mesh::cell_centroid(Index c) const
{
    return geometry::polyhedron_centroid(rest, cell_face_loops(c));
}

double Mesh::rest_volume() const
{
    double v = 0;
    for (Index c = 0; c < num_cells(); ++c)
        v += cell_volume(c);
    return v;
}

std::vector<Index> Mesh::boundary_faces() const
{
    std::vector<Index> out;
    for (Index f = 0; f < num_faces(); ++f)
        if (faces[std::size_t(f)].boundary())
            out.push_back(f);
    return out;
}

Index Mesh::num_boundary_triangles() const
{
    Index n = 0;
    for (const Face& f : faces)
        if (f.boundary())
            n += Index(f.nodes.size()) - 2;
    return n;
}

std::vector<std::vector<Index>> Mesh::node_cells() const
{
    std::vector<std::vector<Index>> out(rest.size());
    for (Index c = 0; c < num_cells(); ++c)
        for (Index n : cells[std::size_t(c)].nodes)
            out[std::size_t(n)].push_back(c);
    return out;
}

Index Mesh::count_components() const
{
    // Union-find over cells joined through shared nodes.
    std::vector<Index> parent(cells.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](Index a) {
        while (parent[std::size_t(a)] != a) {
            parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
            a = parent[std::size_t(a)];
        }
        return a;
    };
    std::vector<Index> first(rest.size(), kNone);
    for (Index c = 0; c < num_cells(); ++c)
        for (Index n : cells[std::size_t(c)].nodes) {
            Index& f = first[std::size_t(n)];
            if (f == kNone)
                f = c;
            else
                parent[std::size_t(find(c))] = find(f);
        }
    Index count = 0;
    for (Index c = 0; c < num_cells(); ++c)
        count += find(c) == c ? 1 : 0;
    return count;
}

void Mesh::classify_cell(Index c)
{
    Cell& cell = cells[std::size_t(c)];
    const auto loops = cell_face_loops(c);
    const bool all_tri = std::all_of(loops.begin(), loops.end(), [](auto& l) { return l.size() == 3; });
    const bool all_quad = std::all_of(loops.begin(), loops.end(), [](auto& l) { return l.size() == 4; });
    if (loops.size() == 4 && all_tri && cell.nodes.size() == 4) {
        // Order: first face reversed gives (0,1,2) counter-clockwise from the apex side.
        std::array<Index, 4> t { loops[0][0], loops[0][2], loops[0][1], kNone };
        for (Index n : cell.nodes)
            if (n != t[0] && n != t[1] && n != t[2])
                t[3] = n;
        cell.nodes.assign(t.begin(), t.end());
        cell.shape = CellShape::Tet;
        return;
    }
    if (loops.size() == 6 && all_quad && cell.nodes.size() == 8) {
        // Bottom = first face reversed (0,1,2,3); top node above each bottom node is the one
        // joined to it by an edge that is not in the bottom face.
        const auto& b = loops[0];
        std::array<Index, 8> h { b[0], b[3], b[2], b[1], kNone, kNone, kNone, kNone };
        auto in_bottom = [&](Index n) { return std::find(b.begin(), b.end(), n) != b.end(); };
        for (int i = 0; i < 4; ++i) {
            for (const auto& l : loops) {
                for (std::size_t k = 0; k < 4; ++k) {
                    const Index a = l[k], d = l[(k + 1) % 4];
                    if (a == h[std::size_t(i)] && !in_bottom(d))
                        h[std::size_t(4 + i)] = d;
                    if (d == h[std::size_t(i)] && !in_bottom(a))
                        h[std::size_t(4 + i)] = a;
                }
            }
        }
        if (std::find(h.begin(), h.end(), kNone) == h.end()) {
            // Check that the six VTK faces are exactly the cell's faces.
            std::set<std::vector<Index>> have;
            for (const auto& l : loops)
                have.insert(sorted_key(l));
            bool match = true;
            for (const auto& f : kHexFaces) {
                std::vector<Index> key;
                for (int i : f)
                    key.push_back(h[std::size_t(i)]);
                match = match && have.count(sorted_key(key)) == 1;
            }
            if (match) {
                cell.nodes.assign(h.begin(), h.end());
                cell.shape = CellShape::Hex;
                return;
            }
        }
    }
    cell.shape = CellShape::Polyhedron;
}

} // namespace polycut::mesh
