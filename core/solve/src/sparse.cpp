// Names of solver outcomes, and the symmetric sparse products of the solvers and integrators.
#include "polycut/solve/sparse.hpp"

#include "polycut/common/error.hpp"

#include <array>
#include <string>

namespace polycut::solve {

const char* to_string(SolveStatus s) {
    switch (s) {
    case SolveStatus::Ok:
        return "ok";
    case SolveStatus::NotPositiveDefinite:
        return "not_positive_definite";
    case SolveStatus::NotConverged:
        return "not_converged";
    case SolveStatus::NonFinite:
        return "non_finite";
    case SolveStatus::NotReady:
        return "not_ready";
    }
    return "unknown";
}

} // namespace polycut::solve

namespace polycut::solve {

void multiply_symmetric(const SparseMatrix& A, const Vector& x, Vector& y, int threads) {
    const long n = A.cols();
    y.resize(n);
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* values = A.valuePtr();
    const int* counts = A.innerNonZeroPtr(); // null when compressed
    const double* xs = x.data();
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (long j = 0; j < n; ++j) {
        const int begin = outer[j];
        const int end = counts ? begin + counts[j] : outer[j + 1];
        // two accumulators: the additions of one row form two dependency chains, not one
        double even = 0, odd = 0;
        int k = begin;
        for (; k + 1 < end; k += 2) {
            even += values[k] * xs[inner[k]];
            odd += values[k + 1] * xs[inner[k + 1]];
        }
        if (k < end)
            even += values[k] * xs[inner[k]];
        y[j] = even + odd;
    }
}

void multiply_symmetric_many(
    const SparseMatrix& A, std::span<const Vector> xs, std::span<Vector> ys, int threads) {
    const std::size_t m = xs.size();
    if (m != ys.size() || m > kMaxMultiply)
        throw InputError("multiply_symmetric_many",
            std::to_string(m) + " vectors and " + std::to_string(ys.size()) + " results (at most "
                + std::to_string(kMaxMultiply) + ")");
    const long n = A.cols();
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* values = A.valuePtr();
    const int* counts = A.innerNonZeroPtr(); // null when compressed
    std::array<const double*, kMaxMultiply> x {};
    std::array<double*, kMaxMultiply> y {};
    for (std::size_t i = 0; i < m; ++i) {
        ys[i].resize(n);
        x[i] = xs[i].data();
        y[i] = ys[i].data();
    }
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (long j = 0; j < n; ++j) {
        const int begin = outer[j];
        const int end = counts ? begin + counts[j] : outer[j + 1];
        // the even / odd accumulators of multiply_symmetric, per vector: the same sums
        std::array<double, kMaxMultiply> even {}, odd {};
        int k = begin;
        for (; k + 1 < end; k += 2) {
            const double v0 = values[k], v1 = values[k + 1];
            const int c0 = inner[k], c1 = inner[k + 1];
            for (std::size_t i = 0; i < m; ++i) {
                even[i] += v0 * x[i][c0];
                odd[i] += v1 * x[i][c1];
            }
        }
        if (k < end)
            for (std::size_t i = 0; i < m; ++i)
                even[i] += values[k] * x[i][inner[k]];
        for (std::size_t i = 0; i < m; ++i)
            y[i][j] = even[i] + odd[i];
    }
}

void scale_shift_multiply(const SparseMatrix& K, double a, const Vector& d, const Vector& x,
    SparseMatrix& A, Vector& y, int threads) {
    const long n = K.cols();
    y.resize(n);
    const int* outer = K.outerIndexPtr();
    const int* inner = K.innerIndexPtr();
    const double* values = K.valuePtr();
    const int* counts = K.innerNonZeroPtr(); // null when compressed
    double* out = A.valuePtr();
    const double* xs = x.data();
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (long j = 0; j < n; ++j) {
        const int begin = outer[j];
        const int end = counts ? begin + counts[j] : outer[j + 1];
        double even = 0, odd = 0; // two dependency chains, as in multiply_symmetric
        int k = begin;
        for (; k + 1 < end; k += 2) {
            const double v0 = values[k], v1 = values[k + 1];
            even += v0 * xs[inner[k]];
            odd += v1 * xs[inner[k + 1]];
            out[k] = a * v0 + (inner[k] == j ? d[j] : 0.0);
            out[k + 1] = a * v1 + (inner[k + 1] == j ? d[j] : 0.0);
        }
        if (k < end) {
            even += values[k] * xs[inner[k]];
            out[k] = a * values[k] + (inner[k] == j ? d[j] : 0.0);
        }
        y[j] = even + odd;
    }
}

} // namespace polycut::solve
