#include "start_space.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace polycut::solve::detail {

StartSpace::StartSpace(int capacity)
    : m_capacity(std::clamp(capacity, 0, kMaxCapacity))
    , m_gram(Small::Zero(m_capacity, m_capacity)) { }

void StartSpace::clear() {
    m_saved.clear();
    m_products.clear();
    m_next = 0;
    m_stale = false;
}

void StartSpace::set_gram(std::size_t i, std::size_t j) {
    // symmetrized: the lagged products are of different matrices
    m_gram(Eigen::Index(i), Eigen::Index(j)) = m_gram(Eigen::Index(j), Eigen::Index(i))
        = 0.5 * (m_saved[i].dot(m_products[j]) + m_saved[j].dot(m_products[i]));
}

void StartSpace::remap(const RowRemap& m) {
    const std::size_t n = m.old_of.size();
    const bool origins = m.origin_ptr.size() == n + 1;
    for (Vector& s : m_saved) {
        Vector moved = Vector::Zero(Eigen::Index(n));
        for (std::size_t r = 0; r < n; ++r) {
            const long old = m.old_of[r];
            if (old >= 0 && old < s.size()) {
                moved[Eigen::Index(r)] = s[old];
            } else if (origins) {
                double v = 0;
                for (int k = m.origin_ptr[r]; k < m.origin_ptr[r + 1]; ++k) {
                    const long o = m.origin_row[std::size_t(k)];
                    if (o >= 0 && o < s.size())
                        v += m.origin_weight[std::size_t(k)] * s[o];
                }
                moved[Eigen::Index(r)] = v;
            }
        }
        s = std::move(moved);
    }
    m_stale = !m_saved.empty();
}

void StartSpace::push(const Vector& x, const Vector& b, const Vector& r) {
    if (m_capacity == 0)
        return;
    if (!x.allFinite() || !r.allFinite()) {
        clear();
        return;
    }
    if (!m_saved.empty() && m_saved.front().size() != x.size())
        clear(); // another system
    const std::size_t j = std::size_t(m_next);
    if (j == m_saved.size()) {
        m_saved.push_back(x);
        m_products.push_back(b - r);
    } else {
        m_saved[j] = x;
        m_products[j] = b - r;
    }
    m_next = (m_next + 1) % m_capacity;
    if (m_stale) // products of the other solutions still to recompute: none valid yet
        return;
    for (std::size_t i = 0; i < m_saved.size(); ++i)
        set_gram(i, j);
}

bool StartSpace::project(const SparseMatrix& A, const Vector& b, Vector& x, int threads) {
    const Eigen::Index m = Eigen::Index(m_saved.size());
    if (m == 0 || m_saved.front().size() != x.size() || b.size() != x.size())
        return false;
    if (m_stale) {
        // one pass over A for all of them (the same products as one multiply each)
        multiply_symmetric_many(A, m_saved, m_products, threads);
        for (std::size_t i = 0; i < m_saved.size(); ++i)
            for (std::size_t j = 0; j <= i; ++j)
                set_gram(i, j);
        m_stale = false;
    }
    SmallVector g(m);
    for (Eigen::Index i = 0; i < m; ++i)
        g[i] = m_saved[std::size_t(i)].dot(b);
    const Eigen::SelfAdjointEigenSolver<Small> eig(Small(m_gram.topLeftCorner(m, m)));
    if (eig.info() != Eigen::Success)
        return false;
    // Pseudo-inverse: kept solutions may be (nearly) dependent, as on a settled body.
    const auto& lambda = eig.eigenvalues();
    const double floor = 1e-12 * std::max(lambda.cwiseAbs().maxCoeff(), 1e-300);
    SmallVector y = eig.eigenvectors().transpose() * g;
    for (Eigen::Index i = 0; i < m; ++i)
        y[i] = lambda[i] > floor ? y[i] / lambda[i] : 0.0;
    const SmallVector c = eig.eigenvectors() * y;
    if (!c.allFinite())
        return false;
    x = c[0] * m_saved[0];
    for (Eigen::Index i = 1; i < m; ++i)
        x += c[i] * m_saved[std::size_t(i)];
    return true;
}

} // namespace polycut::solve::detail
