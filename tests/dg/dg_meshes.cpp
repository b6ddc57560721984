#include "dg_meshes.hpp"

#include "polycut/cut/random_planes.hpp"
#include "polycut/mesh/builders.hpp"

#include <random>

namespace polycut::dg::test {

std::string name(Kind k) {
    switch (k) {
    case Kind::Hex:
        return "hex";
    case Kind::Prism:
        return "prism";
    case Kind::Tet:
        return "tet";
    case Kind::JitteredTet:
        return "jittered";
    case Kind::Cut:
        return "cut";
    case Kind::Sliver:
        return "sliver";
    case Kind::NonConvex:
        return "nonconvex";
    }
    return "?";
}

namespace {
mesh::Mesh prisms(int n) {
    // Each block split along its (0,0)-(1,1) diagonal in xy into two triangular prisms along z
    // (node ids from the grid, not from the hex cells, whose stored order classify_cell sets).
    mesh::BoxGrid g;
    g.cells = { n, n, n };
    const mesh::Mesh hexes = mesh::hex_grid(g);
    std::vector<std::vector<std::vector<Index>>> cells;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Index v[8] = { mesh::grid_node(g, i, j, k), mesh::grid_node(g, i + 1, j, k),
                    mesh::grid_node(g, i + 1, j + 1, k), mesh::grid_node(g, i, j + 1, k),
                    mesh::grid_node(g, i, j, k + 1), mesh::grid_node(g, i + 1, j, k + 1),
                    mesh::grid_node(g, i + 1, j + 1, k + 1), mesh::grid_node(g, i, j + 1, k + 1) };
                for (const std::array<int, 3> tri :
                    { std::array<int, 3> { 0, 1, 2 }, std::array<int, 3> { 0, 2, 3 } }) {
                    const Index a = v[tri[0]], b = v[tri[1]], d = v[tri[2]];
                    const Index A = v[tri[0] + 4], B = v[tri[1] + 4], D = v[tri[2] + 4];
                    cells.push_back({ { a, d, b }, { A, B, D }, { a, b, B, A }, { b, d, D, B },
                        { d, a, A, D } });
                }
            }
    return mesh::Mesh::from_polyhedra(hexes.rest, cells);
}
} // namespace

mesh::Mesh box_mesh(Kind kind, int n) {
    mesh::BoxGrid g;
    g.cells = { n, n, n };
    switch (kind) {
    case Kind::Hex:
        return mesh::hex_grid(g);
    case Kind::Prism:
        return prisms(n);
    case Kind::Tet:
        return mesh::tet_grid(g);
    case Kind::JitteredTet: {
        mesh::Mesh m = mesh::tet_grid(g);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-0.25, 0.25);
        const double h = 1.0 / n;
        for (Vec3& X : m.rest)
            for (int a = 0; a < 3; ++a)
                if (X[a] > 1e-12 && X[a] < 1 - 1e-12)
                    X[a] += u(rng) * h;
        return m;
    }
    case Kind::Cut: {
        // Snapping (cut::CutOptions::snap) moves nodes onto cutting planes within 1e-3 h, which
        // leaves faces non-planar by as much; DG integrates planar faces, so the test meshes are
        // cut without it.
        cut::RandomPlanesOptions o;
        o.cut.snap = 1e-12;
        return cut::split_by_random_planes(mesh::hex_grid(g), 4 * n * n * n, 11, o);
    }
    case Kind::Sliver: {
        // Hexes whose first layer along x is 1e-3 thick: slivers of aspect 1e-3 / (1/n).
        std::vector<double> xs { 0.0, 1e-3 };
        for (int i = 1; i <= n; ++i)
            xs.push_back(double(i) / n);
        std::vector<Vec3> rest;
        const int nx = int(xs.size());
        for (int k = 0; k <= n; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i < nx; ++i)
                    rest.emplace_back(xs[std::size_t(i)], double(j) / n, double(k) / n);
        auto id = [&](int i, int j, int k) { return Index(i + nx * (j + (n + 1) * k)); };
        std::vector<std::array<Index, 8>> hexes;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i + 1 < nx; ++i)
                    hexes.push_back({ id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k),
                        id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1) });
        return mesh::Mesh::from_hexes(rest, hexes);
    }
    case Kind::NonConvex:
        return mesh::merged_hex_grid(g, 0.8, 3);
    }
    return {};
}

std::vector<Index> faces_on_plane(const mesh::Mesh& m, int axis, double value) {
    std::vector<Index> out;
    for (Index f = 0; f < m.num_faces(); ++f) {
        const mesh::Face& face = m.faces[std::size_t(f)];
        if (!face.boundary())
            continue;
        bool on = true;
        for (Index v : face.nodes)
            on = on && std::abs(m.rest[std::size_t(v)][axis] - value) < 1e-12;
        if (on)
            out.push_back(f);
    }
    return out;
}

std::vector<Index> all_boundary_faces(const mesh::Mesh& m) {
    return m.boundary_faces();
}

} // namespace polycut::dg::test
