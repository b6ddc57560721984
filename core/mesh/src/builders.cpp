#include "polycut/mesh/builders.hpp"

#include "polycut/common/error.hpp"

namespace polycut::mesh {
namespace {
std::vector<Vec3> grid_points(const BoxGrid& g) {
    if ((g.cells.array() < 1).any())
        throw InputError("cells", "a box grid needs at least one block along each axis");
    if (!((g.hi - g.lo).array() > 0).all() || !g.lo.allFinite() || !g.hi.allFinite())
        throw InputError("size", "a box grid needs finite hi > lo along each axis");
    std::vector<Vec3> X;
    X.reserve(std::size_t((g.cells.array() + 1).prod()));
    const Vec3 h = (g.hi - g.lo).cwiseQuotient(g.cells.cast<double>());
    for (int k = 0; k <= g.cells.z(); ++k)
        for (int j = 0; j <= g.cells.y(); ++j)
            for (int i = 0; i <= g.cells.x(); ++i)
                X.push_back(g.lo + Vec3(i * h.x(), j * h.y(), k * h.z()));
    // Exact far faces (no round-off from the multiplication).
    for (int k = 0; k <= g.cells.z(); ++k)
        for (int j = 0; j <= g.cells.y(); ++j)
            for (int i = 0; i <= g.cells.x(); ++i) {
                Vec3& p = X[std::size_t(grid_node(g, i, j, k))];
                if (i == g.cells.x())
                    p.x() = g.hi.x();
                if (j == g.cells.y())
                    p.y() = g.hi.y();
                if (k == g.cells.z())
                    p.z() = g.hi.z();
            }
    return X;
}

std::array<Index, 8> block(const BoxGrid& g, int i, int j, int k) {
    return { grid_node(g, i, j, k), grid_node(g, i + 1, j, k), grid_node(g, i + 1, j + 1, k),
        grid_node(g, i, j + 1, k), grid_node(g, i, j, k + 1), grid_node(g, i + 1, j, k + 1),
        grid_node(g, i + 1, j + 1, k + 1), grid_node(g, i, j + 1, k + 1) };
}
} // namespace

Mesh hex_grid(const BoxGrid& g) {
    auto X = grid_points(g);
    std::vector<std::array<Index, 8>> hexes;
    for (int k = 0; k < g.cells.z(); ++k)
        for (int j = 0; j < g.cells.y(); ++j)
            for (int i = 0; i < g.cells.x(); ++i)
                hexes.push_back(block(g, i, j, k));
    return Mesh::from_hexes(std::move(X), hexes);
}

Mesh tet_grid(const BoxGrid& g, TetSplit split) {
    auto X = grid_points(g);
    // Kuhn: the six monotone edge paths from local node 0 to node 6 (VTK hex numbering).
    static constexpr int kKuhn[6][4] = { { 0, 1, 2, 6 }, { 0, 1, 5, 6 }, { 0, 4, 5, 6 },
        { 0, 4, 7, 6 }, { 0, 3, 7, 6 }, { 0, 3, 2, 6 } };
    // Five: four corner tets and a central one; the odd pattern is the mirror image.
    static constexpr int kFiveEven[5][4]
        = { { 1, 0, 2, 5 }, { 3, 0, 2, 7 }, { 4, 0, 5, 7 }, { 6, 2, 5, 7 }, { 0, 2, 5, 7 } };
    static constexpr int kFiveOdd[5][4]
        = { { 0, 1, 3, 4 }, { 2, 1, 3, 6 }, { 5, 1, 4, 6 }, { 7, 3, 4, 6 }, { 1, 3, 4, 6 } };
    std::vector<std::array<Index, 4>> tets;
    for (int k = 0; k < g.cells.z(); ++k)
        for (int j = 0; j < g.cells.y(); ++j)
            for (int i = 0; i < g.cells.x(); ++i) {
                const auto b = block(g, i, j, k);
                auto emit = [&](const int(&t)[4]) {
                    tets.push_back({ b[std::size_t(t[0])], b[std::size_t(t[1])],
                        b[std::size_t(t[2])], b[std::size_t(t[3])] });
                };
                if (split == TetSplit::Kuhn6)
                    for (const auto& t : kKuhn)
                        emit(t);
                else if ((i + j + k) % 2 == 0)
                    for (const auto& t : kFiveEven)
                        emit(t);
                else
                    for (const auto& t : kFiveOdd)
                        emit(t);
            }
    return Mesh::from_tets(std::move(X), tets); // orients each tet positively
}

} // namespace polycut::mesh
