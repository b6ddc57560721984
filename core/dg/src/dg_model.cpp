// DG elasticity model (dg_model.hpp): bases, volume and face matrices, assembly, loads.
//
// Face terms (003 eq. 11-13), with the owner K- as side s = 0 (sign +1), the neighbour K+ as
// side 1 (sign -1), n the owner's outward normal, [[u]] = u- - u+ and {sigma n} the average:
//   IP:  a_F(u, v) = - int_F ([[v]] . {sigma(u) n} + [[u]] . {sigma(v) n}) + int_F eta [[u]] .
//   [[v]] BZ:  a_F(u, v) = int_F eta [[u]] . [[v]]
// The consistency block A^{st}, the part of int_F [[v]] . {sigma(u) n} coupling test side s to
// trial side t, is for coefficient rows (i, a) and (j, c)
//   A^{st}_{ia,jc} = sign_s w (lambda n_a P_c + mu delta_ac n.P + mu n_c P_a)(i, j),
// P_k = P^{st}_k = int_F phi^s_i d_k phi^t_j, w = 1/2 on interior faces and 1 on Dirichlet faces
// (where {sigma n} is the cell's own traction and [[u]] = u - g).
#include "polycut/dg/dg_model.hpp"

#include "polycut/common/error.hpp"
#include "polycut/dg/polyhedron_moments.hpp"
#include "polycut/dg/polynomial.hpp"
#include "polycut/elasticity/rotation.hpp"

#include <algorithm>
#include <map>
#include <string>

namespace polycut::dg {
namespace {
constexpr double kSign[2] = { 1.0, -1.0 };

} // namespace

DgModel::DgModel(const mesh::Mesh& mesh, const elasticity::Material& material,
    const DgOptions& options, std::vector<Index> dirichlet_faces,
    std::vector<std::uint8_t> dirichlet_axes)
    : m_mesh(&mesh)
    , m_material(material)
    , m_options(options)
    , m_dirichlet(std::move(dirichlet_faces)) {
    build(nullptr, {}, dirichlet_axes);
}

DgModel::DgModel(const DgModel& old, const mesh::Mesh& mesh, const std::vector<Index>& source,
    const std::vector<std::uint8_t>& unchanged, std::vector<Index> dirichlet_faces,
    std::vector<std::uint8_t> dirichlet_axes)
    : m_mesh(&mesh)
    , m_material(old.m_material)
    , m_options(old.m_options)
    , m_dirichlet(std::move(dirichlet_faces)) {
    // Old id of every cell whose integrals carry over (kNone: computed afresh).
    std::vector<Index> reuse(std::size_t(mesh.num_cells()), kNone);
    for (Index c = 0; c < mesh.num_cells(); ++c)
        if (std::size_t(c) < source.size() && std::size_t(c) < unchanged.size()
            && unchanged[std::size_t(c)] && source[std::size_t(c)] >= 0
            && source[std::size_t(c)] < old.num_cells())
            reuse[std::size_t(c)] = source[std::size_t(c)];
    build(&old, reuse, dirichlet_axes);
}

void DgModel::build(const DgModel* old, const std::vector<Index>& reuse,
    const std::vector<std::uint8_t>& dirichlet_axes) {
    const mesh::Mesh& mesh = *m_mesh;
    const elasticity::Material& material = m_material;
    const DgOptions& options = m_options;
    auto reused = [&](Index c) { return old ? reuse[std::size_t(c)] : kNone; };
    elasticity::validate(material);
    if (options.degree < 1 || options.degree > 2)
        throw InputError("basis.degree", "DG degree must be 1 or 2");
    if (!(options.penalty > 0) || !std::isfinite(options.penalty))
        throw InputError("penalty", "DG penalty alpha must be positive and finite");
    if (!(options.dirichlet_penalty > 0) || !std::isfinite(options.dirichlet_penalty))
        throw InputError(
            "dirichlet_penalty", "DG Dirichlet penalty alpha must be positive and finite");
    if (!dirichlet_axes.empty() && dirichlet_axes.size() != m_dirichlet.size())
        throw InputError("dirichlet_axes", "needs one entry per Dirichlet face");
    std::vector<std::uint8_t> axes_of(std::size_t(mesh.num_faces()), 0);
    for (std::size_t k = 0; k < m_dirichlet.size(); ++k)
        if (m_dirichlet[k] >= 0 && m_dirichlet[k] < mesh.num_faces())
            axes_of[std::size_t(m_dirichlet[k])]
                |= dirichlet_axes.empty() ? std::uint8_t(7) : dirichlet_axes[k];
    std::sort(m_dirichlet.begin(), m_dirichlet.end());
    m_dirichlet.erase(std::unique(m_dirichlet.begin(), m_dirichlet.end()), m_dirichlet.end());
    for (Index f : m_dirichlet)
        if (f < 0 || f >= mesh.num_faces() || !mesh.faces[std::size_t(f)].boundary())
            throw InputError("dirichlet_faces",
                "face " + std::to_string(f) + " is not a boundary face of the mesh");

    const Index n_cells = mesh.num_cells();
    m_bases.reserve(std::size_t(n_cells));
    m_offset.resize(std::size_t(n_cells));
    for (Index c = 0; c < n_cells; ++c) {
        m_offset[std::size_t(c)] = m_num_coeffs;
        if (const Index o = reused(c); o != kNone)
            m_bases.push_back(old->m_bases[std::size_t(o)]);
        else {
            m_bases.push_back(
                make_cell_basis(mesh.rest, mesh.cell_face_loops(c), options.degree, c));
            ++m_cells_integrated;
        }
        m_num_coeffs += m_bases.back().size();
    }
    m_rest.resize(m_num_coeffs, 3);
    m_mass.resize(m_num_coeffs);
    m_volume_K.reserve(std::size_t(n_cells));
    for (Index c = 0; c < n_cells; ++c) {
        const CellBasis& b = m_bases[std::size_t(c)];
        m_rest.middleRows(offset(c), b.size()) = rest_coefficients(b);
        m_mass.segment(offset(c), b.size()).setConstant(material.density * b.volume);
        const Index o = reused(c);
        m_volume_K.push_back(o != kNone ? old->m_volume_K[std::size_t(o)] : volume_stiffness(b));
    }
    // Old faces between (or of) carried-over cells, by their old cells: a face whose cells both
    // carry over (a Dirichlet face: whose cell does) keeps its integrals (003 sec. 10: only the
    // faces the cut touched are integrated again). A face is matched only when its cells share
    // exactly one face in both meshes, with the same node count and Dirichlet role.
    std::map<std::pair<Index, Index>, std::vector<std::size_t>> old_faces;
    if (old)
        for (std::size_t k = 0; k < old->m_faces.size(); ++k) {
            const FaceData& fd = old->m_faces[k];
            old_faces[{ fd.cells[0], fd.sides == 2 ? fd.cells[1] : kNone }].push_back(k);
        }
    std::map<std::pair<Index, Index>, int> new_count;
    if (old)
        for (Index f = 0; f < mesh.num_faces(); ++f) {
            const mesh::Face& face = mesh.faces[std::size_t(f)];
            const Index o0 = reused(face.owner);
            const Index o1 = face.boundary() ? kNone : reused(face.neighbour);
            if (o0 != kNone && (face.boundary() || o1 != kNone))
                ++new_count[{ o0, o1 }];
        }
    auto carried_face = [&](Index f, bool dirichlet) -> const FaceData* {
        if (!old)
            return nullptr;
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        const Index o0 = reused(face.owner);
        const Index o1 = face.boundary() ? kNone : reused(face.neighbour);
        if (o0 == kNone || (!face.boundary() && o1 == kNone))
            return nullptr;
        const auto it = old_faces.find({ o0, o1 });
        if (it == old_faces.end() || it->second.size() != 1 || new_count[{ o0, o1 }] != 1)
            return nullptr;
        const FaceData& fd = old->m_faces[it->second.front()];
        if ((fd.sides == 1) != dirichlet || fd.node_count != Index(face.nodes.size()))
            return nullptr;
        return &fd;
    };
    m_rotation.assign(std::size_t(n_cells), Mat3::Identity());

    const double p2 = double(options.degree * options.degree);
    m_face_eta.assign(std::size_t(mesh.num_faces()), 0.0);
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        const bool dirichlet
            = face.boundary() && std::binary_search(m_dirichlet.begin(), m_dirichlet.end(), f);
        if (face.boundary() && !dirichlet)
            continue;
        FaceData fd;
        if (const FaceData* was = carried_face(f, dirichlet))
            fd.parts = was->parts;
        else {
            fd.parts = face_integral_parts(mesh.rest, face.nodes, m_bases[std::size_t(face.owner)],
                face.boundary() ? nullptr : &m_bases[std::size_t(face.neighbour)]);
            ++m_faces_integrated;
        }
        fd.face = f;
        fd.node_count = Index(face.nodes.size());
        fd.cells[0] = face.owner;
        fd.cells[1] = face.neighbour;
        fd.sides = fd.parts.front().sides;
        for (const FaceIntegrals& part : fd.parts)
            fd.area += part.area;
        double volume = m_bases[std::size_t(face.owner)].volume;
        if (!face.boundary())
            volume = std::min(volume, m_bases[std::size_t(face.neighbour)].volume);
        fd.eta = (dirichlet ? options.dirichlet_penalty : options.penalty) * p2 * fd.area / volume;
        if (dirichlet)
            for (int a = 0; a < 3; ++a)
                fd.axes[a] = (axes_of[std::size_t(f)] >> a) & 1 ? 1.0 : 0.0;
        m_face_eta[std::size_t(f)] = fd.eta;
        m_faces.push_back(std::move(fd));
    }
    build_operator();
}

double DgModel::face_penalty(Index f) const {
    return m_face_eta[std::size_t(f)];
}

MatX DgModel::volume_stiffness(const CellBasis& b) const {
    // D_{ik,jl} = int_K d_k phi_i d_l phi_j from the gradient polynomials and the cell's moments.
    const int p = b.degree, nb = b.size(), ng = num_monomials(p - 1);
    MatX Gd(3 * nb, ng);
    for (int k = 0; k < 3; ++k) {
        const MatX g = b.T * derivative_matrix(p, k) / b.scale;
        for (int i = 0; i < nb; ++i)
            Gd.row(3 * i + k) = g.row(i);
    }
    const MatX D = Gd * monomial_gram(b.moments, p - 1) * Gd.transpose();
    const double lambda = m_material.lambda(), mu = m_material.mu();
    MatX K(3 * nb, 3 * nb);
    for (int i = 0; i < nb; ++i)
        for (int j = 0; j < nb; ++j) {
            const double trace
                = D(3 * i, 3 * j) + D(3 * i + 1, 3 * j + 1) + D(3 * i + 2, 3 * j + 2);
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c)
                    K(3 * i + a, 3 * j + c) = lambda * D(3 * i + a, 3 * j + c)
                        + mu * D(3 * i + c, 3 * j + a) + (a == c ? mu * trace : 0.0);
        }
    return K;
}

MatX DgModel::consistency_block(const FaceData& fd, int s, int t) const {
    const double w = kSign[s] * (fd.sides == 2 ? 0.5 : 1.0);
    const double lambda = m_material.lambda(), mu = m_material.mu();
    MatX A;
    for (const FaceIntegrals& fi : fd.parts) { // a warped face: its triangles, each with its n
        const auto& P = fi.P[std::size_t(s)][std::size_t(t)];
        const Vec3& n = fi.normal;
        const MatX nP = n[0] * P[0] + n[1] * P[1] + n[2] * P[2];
        const Index ns = P[0].rows(), nt = P[0].cols();
        if (A.size() == 0)
            A.setZero(3 * ns, 3 * nt);
        for (Index i = 0; i < ns; ++i)
            for (Index j = 0; j < nt; ++j)
                for (int a = 0; a < 3; ++a)
                    for (int c = 0; c < 3; ++c)
                        A(3 * i + a, 3 * j + c) += w * fd.axes[a]
                            * (lambda * n[a] * P[std::size_t(c)](i, j)
                                + mu * n[c] * P[std::size_t(a)](i, j)
                                + (a == c ? mu * nP(i, j) : 0.0));
    }
    return A;
}

MatX DgModel::penalty_block(const FaceData& fd, int s, int t) const {
    MatX B;
    for (const FaceIntegrals& fi : fd.parts) {
        const MatX part = penalty_part(fd, fi, s, t);
        if (B.size() == 0)
            B = part;
        else
            B += part;
    }
    return B;
}

MatX DgModel::penalty_part(const FaceData& fd, const FaceIntegrals& fi, int s, int t) const {
    const MatX& S = fi.S[std::size_t(s)][std::size_t(t)];
    const Vec3& n = fi.normal;
    const double lambda = m_material.lambda(), mu = m_material.mu();
    const bool normal_only = m_options.lambda_penalty == LambdaPenalty::Normal;
    const double w_full = normal_only ? 2.0 * mu : lambda + 2.0 * mu;
    const double w_normal = normal_only ? lambda : 0.0;
    const Mat3 P = fd.axes.asDiagonal();
    const Mat3 W = P * (w_full * Mat3::Identity() + w_normal * n * n.transpose()) * P;
    const double scale = fd.eta * kSign[s] * kSign[t];
    MatX B(3 * S.rows(), 3 * S.cols());
    for (Index i = 0; i < S.rows(); ++i)
        for (Index j = 0; j < S.cols(); ++j)
            B.block<3, 3>(3 * i, 3 * j) = scale * S(i, j) * W;
    return B;
}

Mat3 DgModel::fit_rotation(const MatX3& x, Index cell, const Mat3& guess) const {
    // Affine part of the cell's map: the L2 projection onto P1, rows 0..3 (the first four
    // orthonormal functions span P1); its gradient F = sum_{i=1..3} x_i grad(phi_i)^T.
    const CellBasis& b = basis(cell);
    Mat3 F = Mat3::Zero();
    for (int i = 1; i <= 3; ++i)
        F += x.row(offset(cell) + i).transpose() * (b.T.block<1, 3>(i, 1) / b.scale);
    return elasticity::polar_rotation_warm(F, guess);
}

VecX DgModel::body_load(const Vec3& b) const {
    // int_K b phi_i = b |K| delta_i0 (phi_0 = 1, the others orthogonal to it).
    VecX F = VecX::Zero(3 * m_num_coeffs);
    for (Index c = 0; c < num_cells(); ++c)
        F.segment<3>(dof(offset(c), 0)) = b * basis(c).volume;
    return F;
}

VecX DgModel::traction_load(const std::vector<Index>& faces, const Vec3& t) const {
    VecX F = VecX::Zero(3 * m_num_coeffs);
    for (Index f : faces) {
        if (f < 0 || f >= m_mesh->num_faces() || !m_mesh->faces[std::size_t(f)].boundary())
            throw InputError("faces", "face " + std::to_string(f) + " is not a boundary face");
        const mesh::Face& face = m_mesh->faces[std::size_t(f)];
        for (const FaceIntegrals& fi :
            face_integral_parts(m_mesh->rest, face.nodes, basis(face.owner), nullptr))
            for (Index i = 0; i < fi.mean[0].size(); ++i)
                F.segment<3>(dof(offset(face.owner) + i, 0)) += t * fi.mean[0][i];
    }
    return F;
}

VecX DgModel::polynomial_body_load(const std::array<VecX, 3>& components, int degree) const {
    VecX F = VecX::Zero(3 * m_num_coeffs);
    for (Index c = 0; c < num_cells(); ++c) {
        const CellBasis& b = basis(c);
        const VecX M = polyhedron_moments(
            m_mesh->rest, m_mesh->cell_face_loops(c), b.center, b.scale, b.degree + degree);
        const MatX R = rebase_matrix(degree, b.center, b.scale); // x = c + h xi
        for (int a = 0; a < 3; ++a) {
            const VecX fa = (components[std::size_t(a)].transpose() * R).transpose();
            for (int i = 0; i < b.size(); ++i) {
                const VecX prod = multiply(b.T.row(i).transpose(), b.degree, fa, degree);
                F[dof(offset(c) + i, a)] += prod.dot(M);
            }
        }
    }
    return F;
}

VecX DgModel::dirichlet_load(const Vec3& g0, const Mat3& G) const {
    VecX F = VecX::Zero(3 * m_num_coeffs);
    const double lambda = m_material.lambda(), mu = m_material.mu();
    const bool normal_only = m_options.lambda_penalty == LambdaPenalty::Normal;
    const double w_full = normal_only ? 2.0 * mu : lambda + 2.0 * mu;
    const double w_normal = normal_only ? lambda : 0.0;
    for (const FaceData& fd : m_faces) {
        if (fd.sides != 1)
            continue;
        for (const FaceIntegrals& fi : fd.parts) {
            const CellBasis& b = basis(fd.cells[0]);
            const int p = b.degree;
            const MatX Q = monomial_gram(fi.moments, p);
            // g in the face frame: g(origin + scale zeta), degree 1, padded to num_monomials(p).
            std::array<VecX, 3> g;
            for (int a = 0; a < 3; ++a) {
                g[std::size_t(a)] = VecX::Zero(num_monomials(p));
                g[std::size_t(a)][0] = g0[a] + G.row(a).dot(fi.origin);
                for (int k = 0; k < 3; ++k)
                    g[std::size_t(a)][1 + k] = fi.scale * G(a, k);
                g[std::size_t(a)] *= fd.axes[a]; // P g: only the fixed components
            }
            const Vec3& n = fi.normal;
            const Mat3 P = fd.axes.asDiagonal();
            const Mat3 W = P * (w_full * Mat3::Identity() + w_normal * n * n.transpose()) * P;
            const Index ng = num_monomials(p - 1);
            for (int i = 0; i < b.size(); ++i) {
                Vec3 value; // int_F g_c phi_i
                Mat3 grad; // grad(c, k) = int_F g_c d_k phi_i
                for (int c = 0; c < 3; ++c) {
                    value[c] = fi.values[0].row(i) * Q * g[std::size_t(c)];
                    for (int k = 0; k < 3; ++k)
                        grad(c, k) = fi.gradients[0][std::size_t(k)].row(i) * Q.topRows(ng)
                            * g[std::size_t(c)];
                }
                for (int a = 0; a < 3; ++a) {
                    double rhs = fd.eta * W.row(a).dot(value);
                    if (m_options.flux == Flux::InteriorPenalty)
                        // - int_F g . sigma(phi_i e_a) n
                        for (int c = 0; c < 3; ++c)
                            rhs -= lambda * n[c] * grad(c, a) + mu * n[a] * grad(c, c)
                                + (c == a ? mu * n.dot(grad.row(c)) : 0.0);
                    F[dof(offset(fd.cells[0]) + i, a)] += rhs;
                }
            }
        }
    }
    return F;
}

Vec3 DgModel::displacement(const MatX3& x, Index cell, const Vec3& X) const {
    const CellBasis& b = basis(cell);
    const VecX phi = b.values(X);
    const auto rows
        = x.middleRows(offset(cell), b.size()) - m_rest.middleRows(offset(cell), b.size());
    return (phi.transpose() * rows).transpose();
}

Mat3 DgModel::displacement_gradient(const MatX3& x, Index cell, const Vec3& X) const {
    const CellBasis& b = basis(cell);
    const MatX3 g = b.gradients(X);
    const MatX3 rows
        = x.middleRows(offset(cell), b.size()) - m_rest.middleRows(offset(cell), b.size());
    return rows.transpose() * g;
}

} // namespace polycut::dg
