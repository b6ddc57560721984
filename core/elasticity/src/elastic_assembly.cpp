// ElasticModel's assembly loop: the per-cell kernels (the batched P1 one in p1_batch.cpp, the
// general one below), the threads' cell lists and the shared cells (elastic_partition.cpp), and
// the implicit step's matrix straight from the kernels (assemble_step, decision 0073).
#include "nodal_dilatation.hpp"
#include "p1_batch.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/elasticity/rotation.hpp"

#include <algorithm>
#include <vector>

namespace polycut::elasticity {
namespace {
/// Per-cell force and stiffness kernel; N = number of nodes when known at compile time
/// (4 for tets, 8 for hexes) so that Eigen uses fixed-size 12x12 / 24x24 products.
template <int N>
void cell_kernel(int n, const MatX& Ke, const std::vector<Index>& nodes, const MatX3& G,
    const MatX3& Xr, const MatX3& x, bool corotated, Mat3& R, double* ubuf, double* fbuf,
    const int* scatter, double* Kvals, double* fint, const detail::StepProduct* step) {
    constexpr int D = (N == Eigen::Dynamic) ? Eigen::Dynamic : 3 * N;
    const int d = 3 * n;
    const Eigen::Map<const Eigen::Matrix<double, D, D>> K(Ke.data(), d, d);
    Eigen::Map<Eigen::Matrix<double, D, 1>> u(ubuf, d), fl(fbuf, d);
    Vec3 xc = Vec3::Zero();
    for (int i = 0; i < n; ++i)
        xc += x.row(nodes[std::size_t(i)]).transpose();
    xc /= double(n);
    if (corotated) {
        Mat3 A = Mat3::Zero();
        for (int i = 0; i < n; ++i)
            A.noalias() += (x.row(nodes[std::size_t(i)]).transpose() - xc) * G.row(i);
        R = polar_rotation_warm(A, R);
        for (int i = 0; i < n; ++i)
            u.template segment<3>(3 * i)
                = R.transpose() * (x.row(nodes[std::size_t(i)]).transpose() - xc)
                - Xr.row(i).transpose();
    } else {
        for (int i = 0; i < n; ++i)
            u.template segment<3>(3 * i)
                = x.row(nodes[std::size_t(i)]).transpose() - xc - Xr.row(i).transpose();
    }
    if (fint) {
        fl.noalias() = K * u;
        for (int i = 0; i < n; ++i) {
            const Vec3 fi = corotated ? Vec3(R * fl.template segment<3>(3 * i))
                                      : Vec3(fl.template segment<3>(3 * i));
            double* dst = fint + 3 * std::size_t(nodes[std::size_t(i)]);
            dst[0] -= fi.x();
            dst[1] -= fi.y();
            dst[2] -= fi.z();
        }
    }
    if (Kvals) {
        // K is symmetric (element_stiffness), so block (j, i) of R K R^T is block (i, j)
        // transposed: each pair of blocks is rotated once.
        // With a step product the blocks are scaled and their product with v is summed in
        // fl (free again: the forces are out).
        const double scale = step ? step->scale : 1.0;
        const double* v = step && step->kv ? step->v : nullptr;
        if (v)
            fl.setZero();
        const auto scatter_block = [&](int i, int j, const Mat3& B) {
            const int* row = scatter + std::size_t(3 * i) * std::size_t(d) + std::size_t(3 * j);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    if (const int s = row[std::size_t(a) * std::size_t(d) + std::size_t(b)]; s >= 0)
                        Kvals[s] += B(a, b);
            if (v)
                fl.template segment<3>(3 * i)
                    += B * Eigen::Map<const Vec3>(v + 3 * std::size_t(nodes[std::size_t(j)]));
        };
        for (int j = 0; j < n; ++j)
            for (int i = 0; i <= j; ++i) {
                const Mat3 B = scale
                    * (corotated ? Mat3(R * K.template block<3, 3>(3 * i, 3 * j) * R.transpose())
                                 : Mat3(K.template block<3, 3>(3 * i, 3 * j)));
                scatter_block(i, j, B);
                if (i != j)
                    scatter_block(j, i, B.transpose());
            }
        if (v)
            for (int i = 0; i < n; ++i) {
                double* dst = step->kv + 3 * std::size_t(nodes[std::size_t(i)]);
                dst[0] += fl(3 * i);
                dst[1] += fl(3 * i + 1);
                dst[2] += fl(3 * i + 2);
            }
    }
}

} // namespace

void ElasticModel::assemble_cells(const std::vector<Index>& cells, const MatX3& x, bool corotated,
    double* Kvals, double* fint, const detail::StepProduct* step) {
    const double mu = m_material.mu();
    // NodalAverage: the P1 kernel takes the deviatoric part (kappa = lambda + 2 mu / 3 moves to
    // the nodal term), as element_stiffness() does for the other cells.
    const double lambda = m_nodal ? -2.0 * mu / 3.0 : m_material.lambda();
    double ubuf[24], fbuf[24];
    std::vector<double> ubig, fbig;
    // P1 tets go through the batched kernel kP1Lanes at a time (p1_batch.hpp).
    detail::P1TetView batch[detail::kP1Lanes];
    int pending = 0;
    for (const Index cell : cells) {
        const std::size_t c = std::size_t(cell);
        const CellData& cd = m_cells[c];
        const int n = int(cd.nodes.size());
        const int* sc = m_scatter.data() + m_scatter_offset[c];
        Mat3& R = m_rotation[c];
        if (const P1Cell& t = m_p1[c]; t.valid) {
            const int* blk = m_block_scatter.data() + 20 * c;
            batch[pending++]
                = { t.nodes, t.g, t.c0, t.volume, &R, sc, blk[0] >= 0 ? blk : nullptr };
            if (pending == detail::kP1Lanes) {
                detail::p1_batch(
                    batch, pending, lambda, mu, x.data(), corotated, Kvals, fint, step);
                pending = 0;
            }
        } else if (n == 4)
            cell_kernel<4>(n, cd.stiffness, cd.nodes, cd.fit, cd.rest_local, x, corotated, R, ubuf,
                fbuf, sc, Kvals, fint, step);
        else if (n == 8)
            cell_kernel<8>(n, cd.stiffness, cd.nodes, cd.fit, cd.rest_local, x, corotated, R, ubuf,
                fbuf, sc, Kvals, fint, step);
        else {
            ubig.resize(3 * std::size_t(n));
            fbig.resize(3 * std::size_t(n));
            cell_kernel<Eigen::Dynamic>(n, cd.stiffness, cd.nodes, cd.fit, cd.rest_local, x,
                corotated, R, ubig.data(), fbig.data(), sc, Kvals, fint, step);
        }
    }
    if (pending > 0)
        detail::p1_batch(batch, pending, lambda, mu, x.data(), corotated, Kvals, fint, step);
}

void ElasticModel::assemble(const MatX3& x, ForceMode mode, SparseMatrix* K, VecX* f_int) {
    assemble_impl(x, mode, K, f_int, nullptr);
}

bool ElasticModel::assemble_step(const MatX3& x, ForceMode mode, double scale, const VecX& diagonal,
    const MatX3& v, SparseMatrix& A, VecX& f_int, VecX& kv) {
    if (m_nodal || v.rows() != x.rows() || diagonal.size() != m_num_free)
        return false; // the nodal term has no step product: the caller scales K itself
    kv.setZero(3 * x.rows());
    const detail::StepProduct step { scale, v.data(), kv.data() };
    assemble_impl(x, mode, &A, &f_int, &step);
    double* values = A.valuePtr();
    for (Index r = 0; r < m_num_free; ++r)
        values[m_diag_slots[std::size_t(r)]] += diagonal(r);
    return true;
}

void ElasticModel::assemble_impl(
    const MatX3& x, ForceMode mode, SparseMatrix* K, VecX* f_int, const detail::StepProduct* step) {
    double* Kvals = nullptr;
    if (K) {
        if (K->rows() != m_num_free || K->nonZeros() != Index(m_inner.size()) || !K->isCompressed())
            *K = make_matrix();
        Kvals = K->valuePtr();
    }
    double* fint = nullptr;
    if (f_int) {
        f_int->setZero(3 * x.rows());
        fint = f_int->data();
    }
    const bool corotated = mode == ForceMode::Corotated;
    const int T = int(m_thread_cells.size());
    const std::ptrdiff_t nnz = std::ptrdiff_t(m_inner.size());
    if (T <= 1) {
        if (Kvals)
            std::fill(Kvals, Kvals + nnz, 0.0);
        if (T == 1)
            assemble_cells(m_thread_cells[0], x, corotated, Kvals, fint, step);
        if (m_nodal) // after the cells: their rotations are current
            m_nodal->assemble(x, m_rotation, corotated, Kvals, fint);
        return;
    }
    // One list per loop index whatever the team size OpenMP grants: each list is assembled
    // once, serially, so the order of every sum depends on T only.
#pragma omp parallel num_threads(T)
    {
        if (Kvals) {
#pragma omp for schedule(static)
            for (int t = 0; t < T; ++t)
                std::fill(Kvals + nnz * t / T, Kvals + nnz * (t + 1) / T, 0.0);
        }
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            assemble_cells(m_thread_cells[std::size_t(t)], x, corotated, Kvals, fint, step);
        // the shared cells on either side of the band's split (split_shared_cells), after the
        // barrier of the loop above
        const int G = int(m_shared_groups.size());
#pragma omp for schedule(static, 1)
        for (int g = 0; g < G; ++g)
            assemble_cells(m_shared_groups[std::size_t(g)], x, corotated, Kvals, fint, step);
    }
    assemble_cells(m_shared_cells, x, corotated, Kvals, fint, step);
    if (m_nodal)
        m_nodal->assemble(x, m_rotation, corotated, Kvals, fint);
}

} // namespace polycut::elasticity
