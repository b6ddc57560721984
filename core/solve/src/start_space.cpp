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
}

void StartSpace::push(const Vector& x, const Vector& b, const Vector& r) {
    if (m_capacity == 0)
        return;
    if (!x.allFinite() || !r.allFinite()
        || (!m_saved.empty() && m_saved.front().size() != x.size()))
        clear();
    if (!x.allFinite() || !r.allFinite())
        return;
    const std::size_t j = std::size_t(m_next);
    if (j == m_saved.size()) {
        m_saved.push_back(x);
        m_products.push_back(b - r);
    } else {
        m_saved[j] = x;
        m_products[j] = b - r;
    }
    m_next = (m_next + 1) % m_capacity;
    for (std::size_t i = 0; i < m_saved.size(); ++i)
        m_gram(Eigen::Index(i), Eigen::Index(j)) = m_gram(Eigen::Index(j), Eigen::Index(i))
            = 0.5 * (m_saved[i].dot(m_products[j]) + m_saved[j].dot(m_products[i]));
}

bool StartSpace::project(const Vector& b, Vector& x) const {
    const Eigen::Index m = Eigen::Index(m_saved.size());
    if (m == 0 || m_saved.front().size() != x.size() || b.size() != x.size())
        return false;
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
