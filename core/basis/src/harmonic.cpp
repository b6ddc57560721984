// Harmonic basis of a polyhedral cell by the method of fundamental solutions (seed 001 sec. 5):
// N(x) = sum_j w_j / |x - k_j| + a_1 . x + a_0 (eq. 11), kernels k_j offset outside the cell
// (eq. 12), fitted in the least-squares sense (eq. 13-14) to Dirichlet data that are the faces'
// 2D harmonic coordinates (harmonic_face.cpp), linear on the edges and delta at the nodes.
#include "harmonic_detail.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <cmath>
#include <map>
#include <numbers>

namespace polycut::basis {

namespace {
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Ericson, Real-Time Collision Detection, sec. 5.1.5.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
        return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
        return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return a + d1 / (d1 - d3) * ab;
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
        return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return a + d2 / (d2 - d6) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}
} // namespace

double HarmonicCell::Impl::winding(const Vec3& p) const {
    // Sum of signed solid angles (van Oosterom & Strackee 1983) / 4 pi: 1 inside, 0 outside.
    double omega = 0;
    for (const auto& t : triangles) {
        const Vec3 a = group_pos[std::size_t(t.nodes[0])] - p;
        const Vec3 b = group_pos[std::size_t(t.nodes[1])] - p;
        const Vec3 c = group_pos[std::size_t(t.nodes[2])] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        omega += 2
            * std::atan2(
                a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
    }
    return omega / (4 * std::numbers::pi);
}

double HarmonicCell::Impl::surface_distance(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : triangles)
        best = std::min(best,
            (p
                - closest_on_triangle(p, group_pos[std::size_t(t.nodes[0])],
                    group_pos[std::size_t(t.nodes[1])], group_pos[std::size_t(t.nodes[2])]))
                .norm());
    return best;
}

double HarmonicCell::Impl::max_plane_distance(const Vec3& p) const {
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < triangles.size(); ++t)
        best = std::max(
            best, (p - group_pos[std::size_t(triangles[t].nodes[0])]).dot(tri_normal[t]));
    return best;
}

HarmonicCell::HarmonicCell(const CellGeometry& cell, const HarmonicOptions& options)
    : HarmonicCell(cell.nodes, cell.loops, options) { }

HarmonicCell::~HarmonicCell() = default;
HarmonicCell::HarmonicCell(HarmonicCell&&) noexcept = default;
HarmonicCell& HarmonicCell::operator=(HarmonicCell&&) noexcept = default;

HarmonicCell::HarmonicCell(std::vector<Vec3> nodes, const std::vector<std::vector<Index>>& loops,
    const HarmonicOptions& options)
    : m_impl(std::make_unique<Impl>()) {
    Impl& c = *m_impl;
    c.options = options;
    c.nodes = std::move(nodes);
    const std::size_t nn = c.nodes.size();
    for (std::size_t f = 0; f < loops.size(); ++f)
        for (Index v : loops[f])
            if (v < 0 || std::size_t(v) >= nn)
                throw MeshError(kNone, long(f), "face node index out of range");
    c.size = cell_size(c.nodes);
    c.volume = geometry::polyhedron_volume(c.nodes, loops);
    if (!(c.volume > 0) || !(c.size > 0))
        throw MeshError(kNone, kNone, "harmonic cell of non-positive volume");
    c.centroid = geometry::polyhedron_centroid(c.nodes, loops);

    // 001 sec. 5 "degenerate edges": coincident nodes share one joint function.
    c.group.assign(nn, kNone);
    for (std::size_t i = 0; i < nn; ++i) {
        if (c.group[i] != kNone)
            continue;
        c.group[i] = Index(c.group_pos.size());
        for (std::size_t j = i + 1; j < nn; ++j)
            if (c.group[j] == kNone
                && (c.nodes[j] - c.nodes[i]).norm() <= options.merge_tolerance * c.size)
                c.group[j] = c.group[i];
        c.group_pos.push_back(c.nodes[i]);
    }
    const std::size_t ng = c.group_pos.size();
    if (ng < 4)
        throw MeshError(kNone, kNone, "harmonic cell with fewer than 4 distinct nodes");
    std::vector<int> count(ng, 0);
    for (Index g : c.group)
        ++count[std::size_t(g)];
    for (std::size_t i = 0; i < nn; ++i)
        c.share.push_back(1.0 / count[std::size_t(c.group[i])]);

    c.face_of_loop.assign(loops.size(), kNone);
    for (std::size_t f = 0; f < loops.size(); ++f) {
        std::vector<Index> gl;
        for (Index v : loops[f]) {
            const Index g = c.group[std::size_t(v)];
            if (gl.empty() || gl.back() != g)
                gl.push_back(g);
        }
        while (gl.size() > 1 && gl.front() == gl.back())
            gl.pop_back();
        c.loops.push_back(gl);
        if (gl.size() < 3)
            continue;
        const auto pts = geometry::gather(c.group_pos, gl);
        if (geometry::polygon_area(pts) <= 1e-14 * c.size * c.size)
            continue;
        c.face_of_loop[f] = Index(c.faces.size());
        c.faces.emplace_back(pts, options);
        c.face_groups.push_back(gl);
    }
    c.triangles = fan_triangulation(c.group_pos, c.loops, 1e-14 * c.size * c.size);
    for (const auto& t : c.triangles) {
        const Vec3& a = c.group_pos[std::size_t(t.nodes[0])];
        c.tri_normal.push_back((c.group_pos[std::size_t(t.nodes[1])] - a)
                                   .cross(c.group_pos[std::size_t(t.nodes[2])] - a)
                                   .normalized());
    }
    c.convex = geometry::polyhedron_is_convex(c.group_pos, c.loops, 1e-9);

    // Edges (group pairs) and their incident faces.
    std::map<std::pair<Index, Index>, std::vector<Index>> edges;
    for (std::size_t f = 0; f < c.faces.size(); ++f) {
        const auto& gl = c.face_groups[f];
        for (std::size_t i = 0; i < gl.size(); ++i) {
            const Index a = gl[i], b = gl[(i + 1) % gl.size()];
            edges[{ std::min(a, b), std::max(a, b) }].push_back(Index(f));
        }
    }
    std::vector<Vec3> vertex_normal(ng, Vec3::Zero());
    for (std::size_t f = 0; f < c.faces.size(); ++f)
        for (Index g : c.face_groups[f])
            vertex_normal[std::size_t(g)] += c.faces[f].normal();
    double mean_edge = 0;
    for (const auto& [e, fs] : edges)
        mean_edge
            += (c.group_pos[std::size_t(e.second)] - c.group_pos[std::size_t(e.first)]).norm();
    mean_edge /= double(std::max<std::size_t>(edges.size(), 1));

    // 001 eq. 12: kernel centres = boundary samples + xi * size * normal, size = 1 in scaled
    // coordinates. Centres inside (non-convex cells) or too close to the surface move less, or
    // are dropped.
    const int ne = std::max(0, options.edge_samples);
    // Non-convex cells keep their kernels near the re-entrant edges, where the exact functions
    // are singular (the L prism's boundary error grows from 5 % to 7 % at xi = 0.15).
    const double xi
        = c.convex ? options.offset : std::min(options.offset, options.nonconvex_offset);
    const double min_spacing = 0.3 * mean_edge / (ne + 1) / c.size; // scaled units
    auto place = [&](const Vec3& s, const Vec3& normal) {
        const Vec3 n = normal.normalized();
        for (double f : { 1.0, 0.5, 0.25 }) {
            const Vec3 k = s + f * xi * c.size * n;
            const double need = 0.5 * f * xi * c.size;
            const bool ok = c.convex ? c.max_plane_distance(k) >= need
                                     : c.winding(k) < 0.5 && c.surface_distance(k) >= need;
            if (ok) {
                const Vec3 y = c.scaled(k);
                for (const auto& other : c.kernels)
                    if ((other - y).norm() < min_spacing)
                        return; // near-duplicate kernel (short edges, small faces): drop it
                c.kernels.push_back(y);
                return;
            }
        }
    };
    for (std::size_t g = 0; g < ng; ++g)
        place(c.group_pos[g], vertex_normal[g]);
    for (const auto& [e, fs] : edges) {
        Vec3 n = Vec3::Zero();
        for (Index f : fs)
            n += c.faces[std::size_t(f)].normal();
        for (int j = 1; j <= ne; ++j) {
            const double t = double(j) / (ne + 1);
            place((1 - t) * c.group_pos[std::size_t(e.first)]
                    + t * c.group_pos[std::size_t(e.second)],
                n);
        }
    }
    // Face interiors carry smooth data (the faces' harmonic coordinates): a coarser kernel grid
    // there costs little accuracy and the dense solve scales with the cube of the kernel count.
    const double hk = mean_edge / (ne + 1); // kernel spacing on the edges [m]
    const double hf = std::max(1.0, options.face_spacing) * hk; // on the faces [m]
    for (const auto& face : c.faces)
        for (const auto& q :
            detail::polygon_grid(face.polygon(), hf / face.scale(), 0.5 * hf / face.scale()))
            place(face.to_3d(q), face.normal());

    // 001 eq. 13-14: collocation points at ~ratio x the kernel density with Dirichlet data:
    // delta at the nodes, linear along the edges, the face's 2D harmonic coordinates inside.
    const Index n = Index(c.kernels.size());
    const int mc = std::max(1, int(std::lround(options.collocation_ratio * (ne + 1))) - 1);
    const double hc = hk
        * std::sqrt(std::max(1.0, options.face_spacing) / std::max(1.0, options.collocation_ratio));
    std::vector<Vec3> colloc;
    std::vector<std::array<Index, 2>> edge_of;
    std::vector<double> t_of;
    std::vector<Index> face_of;
    for (std::size_t g = 0; g < ng; ++g) {
        colloc.push_back(c.group_pos[g]);
        edge_of.push_back({ Index(g), Index(g) });
        t_of.push_back(0);
        face_of.push_back(kNone);
    }
    for (const auto& [e, fs] : edges)
        for (int j = 1; j <= mc; ++j) {
            const double t = double(j) / (mc + 1);
            colloc.push_back((1 - t) * c.group_pos[std::size_t(e.first)]
                + t * c.group_pos[std::size_t(e.second)]);
            edge_of.push_back({ e.first, e.second });
            t_of.push_back(t);
            face_of.push_back(kNone);
        }
    for (std::size_t f = 0; f < c.faces.size(); ++f) {
        const auto& face = c.faces[f];
        for (const auto& q :
            detail::polygon_grid(face.polygon(), hc / face.scale(), 0.5 * hc / face.scale())) {
            colloc.push_back(face.to_3d(q));
            edge_of.push_back({ kNone, kNone });
            t_of.push_back(0);
            face_of.push_back(Index(f));
        }
    }
    const Index m = Index(colloc.size());
    c.num_collocation = m;
    if (m < n + 4)
        throw MeshError(kNone, kNone, "harmonic cell: fewer collocation points than unknowns");
    MatX A(m, n + 4);
    MatX B = MatX::Zero(m, Index(ng));
    VecX fvals;
    for (Index i = 0; i < m; ++i) {
        const Vec3 y = c.scaled(colloc[std::size_t(i)]);
        for (Index j = 0; j < n; ++j)
            A(i, j) = 1.0 / (y - c.kernels[std::size_t(j)]).norm();
        A.block<1, 3>(i, n) = y.transpose();
        A(i, n + 3) = 1.0;
        const Index f = face_of[std::size_t(i)];
        if (f == kNone) {
            const auto [a, b] = edge_of[std::size_t(i)];
            const double t = t_of[std::size_t(i)];
            B(i, a) += 1 - t;
            B(i, b) += t;
        } else {
            const auto& gl = c.face_groups[std::size_t(f)];
            fvals.resize(Index(gl.size()));
            c.faces[std::size_t(f)].evaluate(colloc[std::size_t(i)], fvals);
            for (std::size_t v = 0; v < gl.size(); ++v)
                B(i, gl[v]) += fvals[Index(v)];
        }
    }
    MatX X(Index(ng), 4);
    for (std::size_t g = 0; g < ng; ++g)
        X.row(Index(g)) << c.scaled(c.group_pos[g]).transpose(), 1.0;
    c.coef = detail::solve_mfs(std::move(A), B, X, n, options.solver);
    if (!c.coef.allFinite())
        throw MeshError(kNone, kNone, "harmonic cell: singular collocation system");
}

void HarmonicCell::Impl::evaluate_groups(const Vec3& x, VecX& phi, MatX3* grad) const {
    const Vec3 y = scaled(x);
    const Index n = Index(kernels.size());
    thread_local VecX psi;
    thread_local MatX dpsi;
    psi.resize(n + 4);
    for (Index j = 0; j < n; ++j)
        psi[j] = 1.0 / (y - kernels[std::size_t(j)]).norm();
    psi.segment<3>(n) = y;
    psi[n + 3] = 1.0;
    phi.noalias() = coef.transpose() * psi;
    if (!grad)
        return;
    dpsi.resize(n + 4, 3);
    for (Index j = 0; j < n; ++j) {
        const double r = psi[j];
        dpsi.row(j) = -(r * r * r / size) * (y - kernels[std::size_t(j)]).transpose();
    }
    dpsi.bottomRows(4).setZero();
    dpsi.block<3, 3>(n, 0) = Mat3::Identity() / size;
    grad->noalias() = coef.transpose() * dpsi;
}

void HarmonicCell::Impl::to_nodes(const VecX& g, VecX& phi) const {
    phi.resize(Index(nodes.size()));
    for (std::size_t i = 0; i < nodes.size(); ++i)
        phi[Index(i)] = share[i] * g[group[i]];
}

void HarmonicCell::evaluate(const Vec3& x, VecX& phi, MatX3* grad) const {
    const Impl& c = *m_impl;
    thread_local VecX g;
    thread_local MatX3 gg;
    c.evaluate_groups(x, g, grad ? &gg : nullptr);
    c.to_nodes(g, phi);
    if (grad) {
        grad->resize(Index(c.nodes.size()), 3);
        for (std::size_t i = 0; i < c.nodes.size(); ++i)
            grad->row(Index(i)) = c.share[i] * gg.row(c.group[i]);
    }
}

void HarmonicCell::boundary_values(Index face, const Vec3& x, VecX& b) const {
    const Impl& c = *m_impl;
    VecX g = VecX::Zero(Index(c.group_pos.size()));
    const Index f = c.face_of_loop.at(std::size_t(face));
    if (f != kNone) {
        const auto& gl = c.face_groups[std::size_t(f)];
        VecX vals(Index(gl.size()));
        c.faces[std::size_t(f)].evaluate(x, vals);
        for (std::size_t v = 0; v < gl.size(); ++v)
            g[gl[v]] += vals[Index(v)];
    }
    c.to_nodes(g, b);
}

Index HarmonicCell::num_nodes() const {
    return Index(m_impl->nodes.size());
}
const std::vector<Vec3>& HarmonicCell::nodes() const {
    return m_impl->nodes;
}
Index HarmonicCell::num_kernels() const {
    return Index(m_impl->kernels.size());
}
Index HarmonicCell::num_collocation() const {
    return m_impl->num_collocation;
}
double HarmonicCell::volume() const {
    return m_impl->volume;
}
double HarmonicCell::size() const {
    return m_impl->size;
}

} // namespace polycut::basis
