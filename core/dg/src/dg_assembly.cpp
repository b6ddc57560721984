// DG assembly into a fixed sparsity pattern (dg_model.hpp, docs/decisions/0021): the pattern of
// cell blocks coupled through shared faces is built once; the penalty terms, which corotation
// leaves unrotated (003 sec. 7), form a constant matrix; what each cell's strain carries (its
// volume term and the consistency terms of its faces, K_f1/K_f2 of 003 sec. 7) is kept as one
// diagonal block and one block per face neighbour, warped per step with the cell's rotation and
// scattered through precomputed value slots: no triplets, no allocation after the first step.
#include "polycut/dg/dg_model.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace polycut::dg {
namespace {

/// out(3x3 block) = R M(3x3 block) R^T for every block.
void rotate_into(const MatX& M, const Mat3& R, MatX& out) {
    out.resize(M.rows(), M.cols());
    for (Index i = 0; i < M.rows(); i += 3)
        for (Index j = 0; j < M.cols(); j += 3)
            out.block<3, 3>(i, j).noalias() = R * M.block<3, 3>(i, j) * R.transpose();
}

/// Adds the column-major entries of M to values[slots[k]].
void scatter(const MatX& M, const std::vector<int>& slots, double* values) {
    const double* m = M.data();
    for (std::size_t k = 0; k < slots.size(); ++k)
        values[slots[k]] += m[k];
}

/// Adds the entries of M^T (M column-major, slots of M^T's positions in M's order).
void scatter_transposed(const MatX& M, const std::vector<int>& slots_t, double* values) {
    scatter(M, slots_t, values);
}

} // namespace

int DgModel::slot(Index i, Index j) const {
    const int* outer = m_pattern.outerIndexPtr();
    const int* inner = m_pattern.innerIndexPtr();
    const int* begin = inner + outer[j];
    const int* end = inner + outer[j + 1];
    const int* it = std::lower_bound(begin, end, int(i));
    return int(it - inner);
}

void DgModel::build_operator() {
    const Index n_cells = num_cells();
    const Index n = 3 * m_num_coeffs;
    m_dof_map.resize(std::size_t(n));
    for (Index k = 0; k < n; ++k)
        m_dof_map[std::size_t(k)] = k;
    m_reduced_mass.resize(n);
    for (Index r = 0; r < m_num_coeffs; ++r)
        m_reduced_mass.segment<3>(3 * r).setConstant(m_mass(r));

    // Pattern: every pair of cells that share a term-carrying face, and every cell with itself.
    std::vector<std::vector<Index>> neighbours(static_cast<std::size_t>(n_cells));
    for (const FaceData& fd : m_faces)
        if (fd.sides == 2) {
            neighbours[std::size_t(fd.cells[0])].push_back(fd.cells[1]);
            neighbours[std::size_t(fd.cells[1])].push_back(fd.cells[0]);
        }
    std::vector<Eigen::Triplet<double, int>> triplets;
    for (Index c = 0; c < n_cells; ++c) {
        auto& nb = neighbours[std::size_t(c)];
        std::sort(nb.begin(), nb.end());
        nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
        const Index nc = 3 * basis(c).size();
        auto add_block = [&](Index d) {
            const Index nd = 3 * basis(d).size();
            for (Index j = 0; j < nc; ++j)
                for (Index i = 0; i < nd; ++i)
                    triplets.emplace_back(int(3 * offset(d) + i), int(3 * offset(c) + j), 0.0);
        };
        add_block(c);
        for (Index d : nb)
            add_block(d);
    }
    m_pattern.resize(int(n), int(n));
    m_pattern.setFromTriplets(triplets.begin(), triplets.end());
    m_pattern.makeCompressed();
    m_pattern.coeffs().setZero();
    triplets.clear();
    triplets.shrink_to_fit();

    // Slots of a block (rows of cell d, columns of cell c), column-major.
    auto block_slots = [&](Index d, Index c, bool transposed) {
        const Index nd = 3 * basis(d).size(), nc = 3 * basis(c).size();
        std::vector<int> s(std::size_t(nd * nc));
        for (Index j = 0; j < nc; ++j)
            for (Index i = 0; i < nd; ++i) {
                const Index row = 3 * offset(d) + i, col = 3 * offset(c) + j;
                s[std::size_t(j * nd + i)] = transposed ? slot(col, row) : slot(row, col);
            }
        return s;
    };

    // Cell terms: the volume stiffness, then the consistency terms carried by each side.
    m_terms.assign(std::size_t(n_cells), CellTerms {});
    for (Index c = 0; c < n_cells; ++c) {
        CellTerms& t = m_terms[std::size_t(c)];
        t.diagonal = m_volume_K[std::size_t(c)];
        t.diagonal_slots = block_slots(c, c, false);
        t.neighbours = neighbours[std::size_t(c)];
        for (Index d : t.neighbours) {
            t.off.push_back(MatX::Zero(3 * basis(d).size(), 3 * basis(c).size()));
            t.off_slots.push_back(block_slots(d, c, false));
            t.off_slots_t.push_back(block_slots(d, c, true));
        }
    }
    m_penalty = m_pattern;
    double* pen = m_penalty.valuePtr();
    for (const FaceData& fd : m_faces) {
        const int sides = fd.sides;
        for (int s = 0; s < sides; ++s)
            for (int t = 0; t < sides; ++t) {
                const MatX B = penalty_block(fd, s, t); // rows of side s, columns of side t
                scatter(B, block_slots(fd.cells[s], fd.cells[t], false), pen);
            }
        if (m_options.flux != Flux::InteriorPenalty)
            continue;
        // Side t's term: -(A^{tt} + A^{tt}^T) on (t, t), -A^{st} on (s, t) and its transpose.
        for (int t = 0; t < sides; ++t) {
            CellTerms& ct = m_terms[std::size_t(fd.cells[t])];
            const MatX Att = consistency_block(fd, t, t);
            ct.diagonal -= Att + Att.transpose();
            if (sides == 2) {
                const int s = 1 - t;
                const auto it
                    = std::lower_bound(ct.neighbours.begin(), ct.neighbours.end(), fd.cells[s]);
                ct.off[std::size_t(it - ct.neighbours.begin())] -= consistency_block(fd, s, t);
            }
        }
    }
    m_linear = m_penalty;
    double* lin = m_linear.valuePtr();
    for (const CellTerms& t : m_terms) {
        scatter(t.diagonal, t.diagonal_slots, lin);
        for (std::size_t k = 0; k < t.neighbours.size(); ++k) {
            scatter(t.off[k], t.off_slots[k], lin);
            scatter_transposed(t.off[k], t.off_slots_t[k], lin);
        }
    }
}

void DgModel::assemble(const MatX3& x, Warp warp, SparseMatrix* K, VecX* f_int) {
    const Index n = 3 * m_num_coeffs;
    const MatX3 u = x - m_rest;
    if (warp == Warp::Linear) {
        if (K) {
            *K = m_linear;
            m_k_rotation.assign(std::size_t(num_cells()), Mat3::Identity());
        }
        if (f_int)
            *f_int = -(m_linear * flat(u));
        return;
    }
    for (Index c = 0; c < num_cells(); ++c)
        m_rotation[std::size_t(c)] = fit_rotation(x, c, m_rotation[std::size_t(c)]);
    if (K) {
        if (K->nonZeros() != m_pattern.nonZeros() || K->rows() != n)
            *K = m_pattern;
        std::copy_n(m_penalty.valuePtr(), m_penalty.nonZeros(), K->valuePtr());
    }
    if (f_int)
        *f_int = -(m_penalty * flat(u)); // the penalty is not rotated
    double* values = K ? K->valuePtr() : nullptr;
    MatX rotated;
    for (Index c = 0; c < num_cells(); ++c) {
        if (f_int)
            add_cell_forces(x, c, *f_int);
        if (values) {
            const CellTerms& t = m_terms[std::size_t(c)];
            const Mat3& R = m_rotation[std::size_t(c)];
            rotate_into(t.diagonal, R, rotated);
            scatter(rotated, t.diagonal_slots, values);
            for (std::size_t k = 0; k < t.neighbours.size(); ++k) {
                rotate_into(t.off[k], R, rotated);
                scatter(rotated, t.off_slots[k], values);
                scatter_transposed(rotated, t.off_slots_t[k], values);
            }
        }
    }
    if (K)
        m_k_rotation = m_rotation;
}

void DgModel::add_cell_forces(const MatX3& x, Index c, VecX& f_int) const {
    // Local displacements in c's frame: R^T x - X0 on c and its neighbours.
    const CellTerms& t = m_terms[std::size_t(c)];
    const Mat3& R = m_rotation[std::size_t(c)];
    const int nbc = basis(c).size();
    VecX &uc = m_uc, &ud = m_ud, &fc = m_fc, &fd = m_fd; // scratch, kept between cells
    uc.resize(3 * nbc);
    for (int i = 0; i < nbc; ++i)
        uc.segment<3>(3 * i) = R.transpose() * x.row(offset(c) + i).transpose()
            - m_rest.row(offset(c) + i).transpose();
    fc.noalias() = t.diagonal * uc;
    for (std::size_t k = 0; k < t.neighbours.size(); ++k) {
        const Index d = t.neighbours[k];
        const int nbd = basis(d).size();
        ud.resize(3 * nbd);
        for (int i = 0; i < nbd; ++i)
            ud.segment<3>(3 * i) = R.transpose() * x.row(offset(d) + i).transpose()
                - m_rest.row(offset(d) + i).transpose();
        fc.noalias() += t.off[k].transpose() * ud;
        fd.noalias() = t.off[k] * uc;
        for (int i = 0; i < nbd; ++i)
            f_int.segment<3>(3 * (offset(d) + i)) -= R * fd.segment<3>(3 * i);
    }
    for (int i = 0; i < nbc; ++i)
        f_int.segment<3>(3 * (offset(c) + i)) -= R * fc.segment<3>(3 * i);
}

bool DgModel::assemble_in_turns(
    const MatX3& x, SparseMatrix& K, VecX& f_int, int phase, int period) {
    const Index n = 3 * m_num_coeffs;
    if (period < 1 || m_k_rotation.size() != std::size_t(num_cells()) || K.rows() != n
        || K.nonZeros() != m_pattern.nonZeros())
        return false;
    for (Index c = 0; c < num_cells(); ++c)
        m_rotation[std::size_t(c)] = fit_rotation(x, c, m_rotation[std::size_t(c)]);
    f_int = -(m_penalty * flat(x - m_rest)); // the penalty is not rotated
    for (Index c = 0; c < num_cells(); ++c)
        add_cell_forces(x, c, f_int);
    // This turn's cells: their warped blocks move from the old rotation to the new one.
    double* values = K.valuePtr();
    MatX now, before;
    for (Index c = phase % period; c < num_cells(); c += period) {
        const CellTerms& t = m_terms[std::size_t(c)];
        const Mat3& R = m_rotation[std::size_t(c)];
        const Mat3& R0 = m_k_rotation[std::size_t(c)];
        rotate_into(t.diagonal, R, now);
        rotate_into(t.diagonal, R0, before);
        now -= before;
        scatter(now, t.diagonal_slots, values);
        for (std::size_t k = 0; k < t.neighbours.size(); ++k) {
            rotate_into(t.off[k], R, now);
            rotate_into(t.off[k], R0, before);
            now -= before;
            scatter(now, t.off_slots[k], values);
            scatter_transposed(now, t.off_slots_t[k], values);
        }
        m_k_rotation[std::size_t(c)] = R;
    }
    return true;
}

SparseMatrix DgModel::stiffness() const {
    return m_linear;
}

void DgModel::add_gravity(const Vec3& g, VecX& full) const {
    for (Index c = 0; c < num_cells(); ++c)
        full.segment<3>(3 * offset(c)) += m_material.density * basis(c).volume * g;
}

double DgModel::elastic_energy(const MatX3& x, elasticity::ForceMode mode) const {
    const MatX3 u = x - m_rest;
    if (mode == elasticity::ForceMode::Linear)
        return 0.5 * flat(u).dot(m_linear * flat(u));
    double e = 0.5 * flat(u).dot(m_penalty * flat(u));
    VecX uc, ud;
    for (Index c = 0; c < num_cells(); ++c) {
        const CellTerms& t = m_terms[std::size_t(c)];
        const Mat3 R = fit_rotation(x, c, m_rotation[std::size_t(c)]);
        auto local = [&](Index cell, VecX& out) {
            const int nb = basis(cell).size();
            out.resize(3 * nb);
            for (int i = 0; i < nb; ++i)
                out.segment<3>(3 * i) = R.transpose() * x.row(offset(cell) + i).transpose()
                    - m_rest.row(offset(cell) + i).transpose();
        };
        local(c, uc);
        e += 0.5 * uc.dot(t.diagonal * uc);
        for (std::size_t k = 0; k < t.neighbours.size(); ++k) {
            local(t.neighbours[k], ud);
            e += ud.dot(t.off[k] * uc); // (d, c) and (c, d) blocks: 2 x 1/2
        }
    }
    return e;
}

void DgModel::cell_stretch_squared(const MatX3& x, std::vector<double>& out) const {
    out.resize(std::size_t(num_cells()));
    for (Index c = 0; c < num_cells(); ++c) {
        const CellBasis& b = basis(c);
        Mat3 F = Mat3::Zero();
        for (int i = 1; i <= 3; ++i)
            F += x.row(offset(c) + i).transpose() * (b.T.block<1, 3>(i, 1) / b.scale);
        if (!F.allFinite()) {
            out[std::size_t(c)] = std::numeric_limits<double>::infinity();
            continue;
        }
        const Eigen::SelfAdjointEigenSolver<Mat3> eig(F.transpose() * F, Eigen::EigenvaluesOnly);
        out[std::size_t(c)] = std::max(eig.eigenvalues().maxCoeff(), 1.0);
    }
}

std::vector<long> DgModel::dof_blocks() const {
    std::vector<long> starts;
    starts.reserve(std::size_t(num_cells()) + 1);
    for (Index c = 0; c < num_cells(); ++c)
        starts.push_back(long(3 * offset(c)));
    starts.push_back(long(3 * m_num_coeffs));
    return starts;
}

double DgModel::max_cell_stretch(const MatX3& x) const {
    std::vector<double> s2;
    cell_stretch_squared(x, s2);
    double worst = 1;
    for (double v : s2)
        worst = std::max(worst, v);
    return std::sqrt(worst);
}

} // namespace polycut::dg
