// The hot path allocates nothing after warm-up (STYLE.md "hot loop"): repeated CHOLMOD solves,
// PCG solves of a fixed size with every preconditioner, and CG relaxations. malloc and friends
// are interposed for this executable only and forward to glibc; a counter is armed around the
// calls under test. Skipped under sanitizers, which interpose malloc themselves.
#include "grid_matrix.hpp"
#include "polycut/solve/cg_relaxation.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <atomic>
#include <cstddef>
#include <gtest/gtest.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define POLYCUT_COUNT_MALLOC 0
#else
#define POLYCUT_COUNT_MALLOC 1
#endif

namespace {
std::atomic<bool> g_counting { false };
std::atomic<long> g_allocations { 0 };
} // namespace

#if POLYCUT_COUNT_MALLOC
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);

void* malloc(size_t size) {
    if (g_counting.load(std::memory_order_relaxed))
        g_allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_malloc(size);
}

void* calloc(size_t count, size_t size) {
    if (g_counting.load(std::memory_order_relaxed))
        g_allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_calloc(count, size);
}

void* realloc(void* pointer, size_t size) {
    if (g_counting.load(std::memory_order_relaxed))
        g_allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_realloc(pointer, size);
}
}
#endif

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

/// Allocations made by f().
template <typename F> long allocations_in(F&& f) {
    g_allocations = 0;
    g_counting = true;
    f();
    g_counting = false;
    return g_allocations.load();
}

} // namespace

TEST(NoAllocation, CounterSeesAllocations) {
    if (!POLYCUT_COUNT_MALLOC)
        GTEST_SKIP() << "sanitizer build";
    const long n = allocations_in([] {
        Vector v(1000);
        v.setOnes();
        EXPECT_EQ(v.sum(), 1000.0);
    });
    EXPECT_GE(n, 1); // the interposition works, so the zeros below mean something
}

TEST(NoAllocation, RepeatedCholmodSolves) {
    if (!POLYCUT_COUNT_MALLOC)
        GTEST_SKIP() << "sanitizer build";
    const SparseMatrix A = grid_matrix(6, 6, 6, 1e-2);
    const Vector b = random_vector(A.rows(), 1);
    CholmodSolver solver;
    ASSERT_EQ(solver.factorize(A), SolveStatus::Ok);
    Vector x;
    ASSERT_EQ(solver.solve(b, x), SolveStatus::Ok); // warm-up: workspace
    SolveStatus status = SolveStatus::NotReady;
    EXPECT_EQ(allocations_in([&] { status = solver.solve(b, x); }), 0);
    EXPECT_EQ(status, SolveStatus::Ok);
}

TEST(NoAllocation, PcgSolvesOfFixedSize) {
    if (!POLYCUT_COUNT_MALLOC)
        GTEST_SKIP() << "sanitizer build";
    const SparseMatrix A = grid_matrix(6, 6, 6, 1e-2, 1);
    const SparseMatrix B = grid_matrix(6, 6, 6, 1e-2, 2); // same pattern, other values
    const Vector b = random_vector(A.rows(), 2);
    for (Preconditioner p : { Preconditioner::None, Preconditioner::Jacobi,
             Preconditioner::BlockJacobi3, Preconditioner::LaggedCholesky }) {
        PcgSolver pcg({ .relative_tolerance = 1e-8, .preconditioner = p });
        Vector x;
        ASSERT_EQ(pcg.solve(A, b, x).status, SolveStatus::Ok); // warm-up
        x.setZero();
        PcgResult r;
        EXPECT_EQ(allocations_in([&] { r = pcg.solve(B, b, x); }), 0) << to_string(p);
        EXPECT_EQ(r.status, SolveStatus::Ok);
        EXPECT_GT(r.iterations, 0);
    }
}

TEST(NoAllocation, CgRelaxation) {
    if (!POLYCUT_COUNT_MALLOC)
        GTEST_SKIP() << "sanitizer build";
    const SparseMatrix K = grid_matrix(5, 5, 5, 0.0);
    const long n = K.rows();
    std::vector<bool> fixed(static_cast<size_t>(n), false);
    for (int c = 0; c < 9; ++c)
        fixed[static_cast<size_t>(c)] = true;
    const Vector f = random_vector(n, 3);
    const StiffnessProduct apply_K
        = [&](const Vector& x, Vector& Kx) { multiply_symmetric(K, x, Kx); };
    CgRelaxation relaxation;
    Vector u = Vector::Zero(n);
    relaxation.relax(apply_K, f, fixed, u, 1e-8, 1000); // warm-up
    u.setZero();
    RelaxationResult r;
    EXPECT_EQ(allocations_in([&] { r = relaxation.relax(apply_K, f, fixed, u, 1e-8, 1000); }), 0);
    EXPECT_TRUE(r.converged);
}
