// CHOLMOD supernodal LL^T (DESIGN.md sec. 4). The Eigen matrix is handed to CHOLMOD as a view
// (no copy): full symmetric storage with stype = +1, so CHOLMOD reads the upper triangle and
// ignores the lower one. LL^T rather than the default LDL^T because LDL^T accepts an indefinite
// matrix silently (STYLE.md "Tooling"); L->minor < n flags a non-positive pivot.
#include "polycut/solve/cholmod_solver.hpp"

#include "polycut/common/error.hpp"
#include "polycut/solve/blas_threads.hpp"

#include <algorithm>
#include <cholmod.h>
#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace polycut::solve {
namespace {

/// CHOLMOD view of an Eigen compressed column matrix; stype = +1 reads the upper triangle.
cholmod_sparse view_of(const SparseMatrix& A) {
    cholmod_sparse s {};
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.nz = nullptr;
    s.x = const_cast<double*>(A.valuePtr());
    s.z = nullptr;
    s.stype = 1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1; // Eigen keeps row indices sorted within a compressed column
    s.packed = 1;
    return s;
}

/// CHOLMOD view of a dense column vector.
cholmod_dense view_of(const Vector& b) {
    cholmod_dense d {};
    d.nrow = static_cast<size_t>(b.size());
    d.ncol = 1;
    d.nzmax = static_cast<size_t>(b.size());
    d.d = static_cast<size_t>(b.size());
    d.x = const_cast<double*>(b.data());
    d.z = nullptr;
    d.xtype = CHOLMOD_REAL;
    d.dtype = CHOLMOD_DOUBLE;
    return d;
}

void check_square(const SparseMatrix& A, const char* where) {
    if (A.rows() != A.cols() || A.rows() == 0)
        throw InputError(where,
            "matrix must be square and non-empty, got " + std::to_string(A.rows()) + " x "
                + std::to_string(A.cols()));
}

bool values_finite(const SparseMatrix& A) {
    const double* v = A.valuePtr();
    const long nnz = A.nonZeros();
    double sum = 0; // NaN/Inf propagate through the sum; one pass, vectorizable
    for (long k = 0; k < nnz; ++k)
        sum += v[k] * 0.0;
    return sum == 0.0;
}

} // namespace

struct CholmodSolver::Impl {
    cholmod_common common {};
    cholmod_factor* L = nullptr;
    // solve2 workspace, reused across solves of the same size
    cholmod_dense* X = nullptr;
    cholmod_dense* Y = nullptr;
    cholmod_dense* E = nullptr;
    std::vector<int> outer; ///< analyzed pattern: column pointers (n + 1)
    std::vector<int> inner; ///< analyzed pattern: row indices (nnz)
    SparseMatrix compressed; ///< copy of an uncompressed input (rare)
    long n = 0;
    bool ready = false;
    int analyses = 0;
    double flops = 0;

    explicit Impl(Ordering ordering) {
        init_blas_threads_once();
        cholmod_start(&common);
        common.supernodal = CHOLMOD_SUPERNODAL;
        common.final_ll = 1;
        common.print = 0; // statuses are reported to the caller, nothing goes to stdout
        if (ordering != Ordering::Auto) {
            common.nmethods = 1;
            common.method[0].ordering = ordering == Ordering::Amd ? CHOLMOD_AMD : CHOLMOD_METIS;
            common.postorder = 1;
        }
    }
    ~Impl() {
        free_workspace();
        if (L)
            cholmod_free_factor(&L, &common);
        cholmod_finish(&common);
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;

    void free_workspace() {
        if (X)
            cholmod_free_dense(&X, &common);
        if (Y)
            cholmod_free_dense(&Y, &common);
        if (E)
            cholmod_free_dense(&E, &common);
    }

    const SparseMatrix& compressed_input(const SparseMatrix& A) {
        if (A.isCompressed())
            return A;
        compressed = A;
        compressed.makeCompressed();
        return compressed;
    }

    bool same_pattern(const SparseMatrix& A) const {
        if (!L || A.rows() != n || A.cols() != n || A.nonZeros() != static_cast<long>(inner.size()))
            return false;
        return std::equal(outer.begin(), outer.end(), A.outerIndexPtr())
            && std::equal(inner.begin(), inner.end(), A.innerIndexPtr());
    }

    void analyze(const SparseMatrix& A) {
        ready = false;
        if (L)
            cholmod_free_factor(&L, &common);
        free_workspace();
        n = 0;
        outer.clear();
        inner.clear();
        cholmod_sparse view = view_of(A);
        L = cholmod_analyze(&view, &common);
        if (!L) {
            if (common.status == CHOLMOD_OUT_OF_MEMORY)
                throw std::bad_alloc();
            throw InputError("CholmodSolver::analyze",
                "CHOLMOD analysis failed with status " + std::to_string(common.status));
        }
        n = A.rows();
        outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + n + 1);
        inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
        ++analyses;
    }
};

CholmodSolver::CholmodSolver()
    : CholmodSolver(Ordering::Auto) { }

CholmodSolver::CholmodSolver(Ordering ordering)
    : m_impl(std::make_unique<Impl>(ordering)) { }

CholmodSolver::~CholmodSolver() = default;
CholmodSolver::CholmodSolver(CholmodSolver&&) noexcept = default;
CholmodSolver& CholmodSolver::operator=(CholmodSolver&&) noexcept = default;

void CholmodSolver::analyze(const SparseMatrix& A) {
    check_square(A, "CholmodSolver::analyze");
    if (!m_impl)
        m_impl = std::make_unique<Impl>(Ordering::Auto);
    m_impl->analyze(m_impl->compressed_input(A));
}

SolveStatus CholmodSolver::factorize(const SparseMatrix& A_in) {
    check_square(A_in, "CholmodSolver::factorize");
    if (!m_impl)
        m_impl = std::make_unique<Impl>(Ordering::Auto);
    Impl& impl = *m_impl;
    const SparseMatrix& A = impl.compressed_input(A_in);
    impl.ready = false;
    if (!values_finite(A))
        return SolveStatus::NonFinite;
    if (!impl.same_pattern(A))
        impl.analyze(A);

    cholmod_sparse view = view_of(A);
    const int ok = cholmod_factorize(&view, impl.L, &impl.common);
    impl.flops = impl.common.fl;
    if (impl.common.status == CHOLMOD_OUT_OF_MEMORY)
        throw std::bad_alloc();
    if (impl.L->minor < static_cast<size_t>(impl.n) || impl.common.status == CHOLMOD_NOT_POSDEF)
        return SolveStatus::NotPositiveDefinite;
    if (!ok || impl.common.status < CHOLMOD_OK)
        throw InputError("CholmodSolver::factorize",
            "CHOLMOD factorization failed with status " + std::to_string(impl.common.status));
    impl.ready = true;
    return SolveStatus::Ok;
}

SolveStatus CholmodSolver::solve(const Vector& b, Vector& x) const {
    if (!ready())
        return SolveStatus::NotReady;
    Impl& impl = *m_impl;
    if (b.size() != impl.n)
        throw InputError("CholmodSolver::solve",
            "right-hand side has " + std::to_string(b.size()) + " rows, the factor "
                + std::to_string(impl.n));
    if (!b.allFinite())
        return SolveStatus::NonFinite;
    cholmod_dense B = view_of(b);
    if (!cholmod_solve2(
            CHOLMOD_A, impl.L, &B, nullptr, &impl.X, nullptr, &impl.Y, &impl.E, &impl.common)) {
        if (impl.common.status == CHOLMOD_OUT_OF_MEMORY)
            throw std::bad_alloc();
        throw InputError("CholmodSolver::solve",
            "CHOLMOD solve failed with status " + std::to_string(impl.common.status));
    }
    x.resize(impl.n);
    std::memcpy(x.data(), impl.X->x, sizeof(double) * static_cast<size_t>(impl.n));
    return x.allFinite() ? SolveStatus::Ok : SolveStatus::NonFinite;
}

bool CholmodSolver::ready() const {
    return m_impl && m_impl->ready;
}

long CholmodSolver::size() const {
    return m_impl ? m_impl->n : 0;
}

bool CholmodSolver::same_pattern(const SparseMatrix& A) const {
    if (!m_impl)
        return false;
    if (A.isCompressed())
        return m_impl->same_pattern(A);
    SparseMatrix copy = A;
    copy.makeCompressed();
    return m_impl->same_pattern(copy);
}

int CholmodSolver::analyses() const {
    return m_impl ? m_impl->analyses : 0;
}

long CholmodSolver::factor_nonzeros() const {
    return m_impl && m_impl->L ? static_cast<long>(m_impl->common.lnz) : 0;
}

double CholmodSolver::factor_flops() const {
    return m_impl ? m_impl->flops : 0;
}

} // namespace polycut::solve
