// Stress-based 1-to-8 refinement of DG hex cells and the exact field transfer (refine.hpp).
#include "polycut/dg/refine.hpp"

#include "polycut/common/error.hpp"
#include "polycut/dg/dg_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <map>

namespace polycut::dg {

std::vector<double> principal_stress(
    const DgModel& model, const MatX3& x, std::vector<Vec3>* directions) {
    const double lambda = model.material().lambda(), mu = model.material().mu();
    std::vector<double> out(std::size_t(model.num_cells()));
    if (directions)
        directions->assign(std::size_t(model.num_cells()), Vec3::UnitX());
    for (Index c = 0; c < model.num_cells(); ++c) {
        const Vec3 X = model.basis(c).center;
        const Mat3& R = model.rotation(c);
        const Mat3 F = Mat3::Identity() + model.displacement_gradient(x, c, X);
        const Mat3 G = R.transpose() * F - Mat3::Identity();
        const Mat3 eps = 0.5 * (G + G.transpose());
        const Mat3 sigma = lambda * eps.trace() * Mat3::Identity() + 2.0 * mu * eps;
        const Eigen::SelfAdjointEigenSolver<Mat3> eig(sigma);
        Index k = 0;
        out[std::size_t(c)] = eig.eigenvalues().cwiseAbs().maxCoeff(&k);
        if (directions)
            (*directions)[std::size_t(c)] = eig.eigenvectors().col(k);
    }
    return out;
}

namespace {
/// Outward face loops of a VTK-ordered hex n[0..7].
std::vector<std::vector<Index>> hex_loops(const std::array<Index, 8>& n) {
    return { { n[0], n[3], n[2], n[1] }, { n[4], n[5], n[6], n[7] }, { n[0], n[1], n[5], n[4] },
        { n[1], n[2], n[6], n[5] }, { n[2], n[3], n[7], n[6] }, { n[3], n[0], n[4], n[7] } };
}

std::vector<Index> sorted(std::vector<Index> v) {
    std::sort(v.begin(), v.end());
    return v;
}
} // namespace

Refinement refine_hexes(const mesh::Mesh& m, const std::vector<Index>& cells) {
    Refinement out;
    std::vector<Vec3> rest = m.rest;
    std::map<std::pair<Index, Index>, Index> edge_mid;
    std::map<std::vector<Index>, Index> face_mid;
    auto node = [&](const Vec3& p) {
        rest.push_back(p);
        return Index(rest.size() - 1);
    };
    auto mid = [&](Index a, Index b) {
        const auto key = std::minmax(a, b);
        auto it = edge_mid.find(key);
        if (it == edge_mid.end())
            it = edge_mid
                     .emplace(key, node(0.5 * (m.rest[std::size_t(a)] + m.rest[std::size_t(b)])))
                     .first;
        return it->second;
    };
    std::vector<std::uint8_t> split(std::size_t(m.num_cells()), 0);
    std::vector<std::vector<std::vector<Index>>> loops;
    std::vector<Index> source;
    std::vector<std::uint8_t> child;
    for (Index c : cells) {
        if (c < 0 || c >= m.num_cells() || split[std::size_t(c)]
            || m.cells[std::size_t(c)].shape != mesh::CellShape::Hex)
            continue;
        split[std::size_t(c)] = 1;
        ++out.split;
        const auto& n = m.cells[std::size_t(c)].nodes;
        // 3 x 3 x 3 lattice: corners, edge midpoints, face centres, body centre.
        Index L[3][3][3];
        const int corner[8][3] = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 2, 0 }, { 0, 2, 0 }, { 0, 0, 2 },
            { 2, 0, 2 }, { 2, 2, 2 }, { 0, 2, 2 } };
        for (int k = 0; k < 8; ++k)
            L[corner[k][0]][corner[k][1]][corner[k][2]] = n[std::size_t(k)];
        // Edge midpoints between lattice corners that differ in one index by 2.
        for (int i = 0; i < 3; i += 2)
            for (int j = 0; j < 3; j += 2) {
                L[1][i][j] = mid(L[0][i][j], L[2][i][j]);
                L[i][1][j] = mid(L[i][0][j], L[i][2][j]);
                L[i][j][1] = mid(L[i][j][0], L[i][j][2]);
            }
        // Face centres, keyed by the face's corner set (shared with a split neighbour).
        auto face_centre = [&](Index a, Index b, Index cc, Index d) {
            const std::vector<Index> key = sorted({ a, b, cc, d });
            auto it = face_mid.find(key);
            if (it == face_mid.end()) {
                const Vec3 p = 0.25
                    * (m.rest[std::size_t(a)] + m.rest[std::size_t(b)] + m.rest[std::size_t(cc)]
                        + m.rest[std::size_t(d)]);
                it = face_mid.emplace(key, node(p)).first;
            }
            return it->second;
        };
        for (int s = 0; s < 3; s += 2) {
            L[s][1][1] = face_centre(L[s][0][0], L[s][2][0], L[s][2][2], L[s][0][2]);
            L[1][s][1] = face_centre(L[0][s][0], L[2][s][0], L[2][s][2], L[0][s][2]);
            L[1][1][s] = face_centre(L[0][0][s], L[2][0][s], L[2][2][s], L[0][2][s]);
        }
        Vec3 centre = Vec3::Zero();
        for (Index v : n)
            centre += m.rest[std::size_t(v)] / 8.0;
        L[1][1][1] = node(centre);
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int d = 0; d < 2; ++d) {
                    const std::array<Index, 8> h = { L[a][b][d], L[a + 1][b][d], L[a + 1][b + 1][d],
                        L[a][b + 1][d], L[a][b][d + 1], L[a + 1][b][d + 1], L[a + 1][b + 1][d + 1],
                        L[a][b + 1][d + 1] };
                    loops.push_back(hex_loops(h));
                    source.push_back(c);
                    child.push_back(1);
                }
    }
    // Unsplit cells: split faces they share with a split cell into the same four quads, and
    // give every face through a split edge the edge's midpoint.
    for (Index c = 0; c < m.num_cells(); ++c) {
        if (split[std::size_t(c)])
            continue;
        std::vector<std::vector<Index>> cell_loops;
        for (const auto& loop : m.cell_face_loops(c)) {
            const auto f = face_mid.find(sorted(loop));
            if (loop.size() == 4 && f != face_mid.end()) {
                const Index F = f->second;
                for (std::size_t k = 0; k < 4; ++k) {
                    const Index a = loop[k], b = loop[(k + 1) % 4], p = loop[(k + 3) % 4];
                    cell_loops.push_back({ a, mid(a, b), F, mid(p, a) });
                }
                continue;
            }
            std::vector<Index> with;
            for (std::size_t k = 0; k < loop.size(); ++k) {
                const Index a = loop[k], b = loop[(k + 1) % loop.size()];
                with.push_back(a);
                if (const auto e = edge_mid.find(std::minmax(a, b)); e != edge_mid.end())
                    with.push_back(e->second);
            }
            cell_loops.push_back(std::move(with));
        }
        loops.push_back(std::move(cell_loops));
        source.push_back(c);
        child.push_back(0);
    }
    // Cells keep no particular order: the source map says where each came from.
    out.mesh = mesh::Mesh::from_polyhedra(std::move(rest), loops);
    out.source = std::move(source);
    out.child = std::move(child);
    return out;
}

namespace {
std::vector<Vec3> fit_points(const mesh::Mesh& m, Index c, const Vec3& centroid) {
    const auto& nodes = m.cells[std::size_t(c)].nodes;
    std::vector<Vec3> pts;
    for (std::size_t a = 0; a < nodes.size(); ++a) {
        pts.push_back(m.rest[std::size_t(nodes[a])]);
        for (std::size_t b = a + 1; b < nodes.size(); ++b)
            pts.push_back(0.5 * (m.rest[std::size_t(nodes[a])] + m.rest[std::size_t(nodes[b])]));
    }
    pts.push_back(centroid);
    return pts;
}
} // namespace

MatX3 transfer_field(const DgModel& old_model, const MatX3& field, const DgModel& new_model,
    const std::vector<Index>& source, const std::vector<std::uint8_t>& unchanged) {
    const mesh::Mesh& m = new_model.mesh();
    if (Index(source.size()) != new_model.num_cells())
        throw InputError("source", "needs one entry per cell of the new model");
    MatX3 out(new_model.num_coefficients(), 3);
    for (Index c = 0; c < new_model.num_cells(); ++c) {
        const Index o = source[std::size_t(c)];
        if (o < 0 || o >= old_model.num_cells())
            throw MeshError(long(c), long(kNone), "has no cell it came from");
        const CellBasis& bn = new_model.basis(c);
        const CellBasis& bo = old_model.basis(o);
        const auto rows_o = field.middleRows(old_model.offset(o), bo.size());
        if (std::size_t(c) < unchanged.size() && unchanged[std::size_t(c)]
            && bo.size() == bn.size()) {
            out.middleRows(new_model.offset(c), bn.size()) = rows_o;
            continue;
        }
        const std::vector<Vec3> pts = fit_points(m, c, bn.center);
        MatX Phi(Index(pts.size()), bn.size());
        MatX U(Index(pts.size()), 3);
        for (std::size_t k = 0; k < pts.size(); ++k) {
            Phi.row(Index(k)) = bn.values(pts[k]).transpose();
            U.row(Index(k)) = bo.values(pts[k]).transpose() * rows_o;
        }
        out.middleRows(new_model.offset(c), bn.size()) = Phi.colPivHouseholderQr().solve(U);
    }
    return out;
}

} // namespace polycut::dg
