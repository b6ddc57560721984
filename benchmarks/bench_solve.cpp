// Linear solver timings (DESIGN.md sec. 4) on elasticity-like matrices: nodes on a grid with
// 3x3 blocks, the 27-point stencil of Q1 hexes or the 15-point stencil of Kuhn-6 tets.
// Sizes: 13^3 nodes (6,591 DOFs, the node count of bench_box12) and 20^3 nodes (24,000 DOFs,
// close to the 23k of DESIGN.md). Run with --benchmark_repetitions=5
// --benchmark_report_aggregates_only=true and quote the medians.
#include "../tests/solve/grid_matrix.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <benchmark/benchmark.h>
#include <map>
#include <string>
#include <tuple>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;
using polycut::solve::testing::Stencil;

namespace {

constexpr double kShift = 1e-3; // condition number ~ 1e4, like a soft stiffness-dominated step

/// Cached matrices: range(0) = nodes per side, range(1) = 0 for Hex27, 1 for Kuhn15.
const SparseMatrix& matrix(const benchmark::State& state, unsigned seed = 1) {
    static std::map<std::tuple<long, long, unsigned>, SparseMatrix> cache;
    const long side = state.range(0);
    const long stencil = state.range(1);
    auto [it, inserted] = cache.try_emplace({ side, stencil, seed });
    if (inserted)
        it->second = grid_matrix(static_cast<int>(side), static_cast<int>(side),
            static_cast<int>(side), kShift, seed, stencil ? Stencil::Kuhn15 : Stencil::Hex27);
    return it->second;
}

void label(benchmark::State& state, const SparseMatrix& A) {
    state.counters["dofs"] = static_cast<double>(A.rows());
    state.counters["nnz"] = static_cast<double>(A.nonZeros());
    state.SetLabel(state.range(1) ? "kuhn15" : "hex27");
}

void sizes(benchmark::internal::Benchmark* b) {
    b->Unit(benchmark::kMillisecond);
    for (long stencil : { 1, 0 })
        for (long side : { 13, 20 })
            b->Args({ side, stencil });
}

void BM_CholmodAnalyze(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    CholmodSolver solver;
    for (auto _ : state)
        solver.analyze(A);
    label(state, A);
    state.counters["nnz_L"] = static_cast<double>(solver.factor_nonzeros());
}
BENCHMARK(BM_CholmodAnalyze)->Apply(sizes);

void BM_CholmodFactorize(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    CholmodSolver solver;
    solver.analyze(A);
    for (auto _ : state)
        if (solver.factorize(A) != SolveStatus::Ok)
            state.SkipWithError("factorize failed");
    label(state, A);
    state.counters["gflops"] = benchmark::Counter(
        solver.factor_flops() * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_CholmodFactorize)->Apply(sizes);

void BM_CholmodSolve(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    CholmodSolver solver;
    solver.factorize(A);
    const Vector b = random_vector(A.rows(), 1);
    Vector x;
    for (auto _ : state) {
        solver.solve(b, x);
        benchmark::DoNotOptimize(x.data());
    }
    label(state, A);
}
BENCHMARK(BM_CholmodSolve)->Apply(sizes);

void BM_SpmvEigen(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    const Vector x = random_vector(A.rows(), 2);
    Vector y(A.rows());
    for (auto _ : state) {
        y.noalias() = A * x;
        benchmark::DoNotOptimize(y.data());
    }
    label(state, A);
    // bytes per product: values + row indices + x gathered + y written
    state.counters["GB/s"] = benchmark::Counter(
        (12.0 * static_cast<double>(A.nonZeros()) + 16.0 * static_cast<double>(A.rows())) * 1e-9,
        benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SpmvEigen)->Apply(sizes);

void BM_SpmvSymmetric(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    const Vector x = random_vector(A.rows(), 2);
    Vector y(A.rows());
    for (auto _ : state) {
        multiply_symmetric(A, x, y);
        benchmark::DoNotOptimize(y.data());
    }
    label(state, A);
    state.counters["GB/s"] = benchmark::Counter(
        (12.0 * static_cast<double>(A.nonZeros()) + 16.0 * static_cast<double>(A.rows())) * 1e-9,
        benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SpmvSymmetric)->Apply(sizes);

/// Cost of one PCG iteration: up to 20 iterations (tolerance unreachable; the lagged factor of a
/// nearby matrix reaches round-off, and stops, after ~6), the preconditioner set up once per
/// solve, as in a time step.
void pcg_iteration(benchmark::State& state, Preconditioner preconditioner) {
    const SparseMatrix& A = matrix(state);
    const SparseMatrix& A_old = matrix(state, 2);
    constexpr int kIterations = 20;
    PcgSolver pcg({ .relative_tolerance = 1e-30,
        .max_iterations = kIterations,
        .preconditioner = preconditioner });
    if (preconditioner == Preconditioner::LaggedCholesky) {
        CholmodSolver factor;
        factor.factorize(A_old);
        pcg.set_preconditioner_factor(std::move(factor));
    }
    const Vector b = random_vector(A.rows(), 3);
    Vector x;
    long iterations = 0;
    for (auto _ : state) {
        x.setZero(A.rows());
        iterations += pcg.solve(A, b, x).iterations;
    }
    label(state, A);
    // CPU seconds per iteration, shown with a unit (us, ms); includes the per-solve setup
    // (initial residual, Jacobi/block inverse, final true residual) spread over the iterations
    state.counters["per_iteration"] = benchmark::Counter(
        static_cast<double>(iterations), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["iterations"]
        = benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}
BENCHMARK_CAPTURE(pcg_iteration, jacobi, Preconditioner::Jacobi)->Apply(sizes);
BENCHMARK_CAPTURE(pcg_iteration, block_jacobi3, Preconditioner::BlockJacobi3)->Apply(sizes);
BENCHMARK_CAPTURE(pcg_iteration, lagged, Preconditioner::LaggedCholesky)->Apply(sizes);

/// Cost of one PCG iteration with the AMG V-cycle (hierarchy set up once on A_old before the
/// timing, lagged as in a time step), the finest level smoothed by point or by 3x3 node-block
/// Gauss-Seidel (AmgOptions::node_blocks): 20 iterations per solve, the block copy refreshed per
/// solve as in a step.
void amg_iteration(benchmark::State& state, bool node_blocks) {
    const SparseMatrix& A = matrix(state);
    const SparseMatrix& A_old = matrix(state, 2);
    constexpr int kIterations = 20;
    PcgOptions o { .relative_tolerance = 1e-30,
        .max_iterations = kIterations,
        .preconditioner = Preconditioner::Amg,
        .refactor_iterations = 100000 };
    o.amg.node_blocks = node_blocks;
    PcgSolver pcg(o);
    const Vector b = random_vector(A.rows(), 3);
    Vector x;
    pcg.solve(A_old, b, x); // the set-up
    long iterations = 0;
    for (auto _ : state) {
        x.setZero(A.rows());
        iterations += pcg.solve(A, b, x).iterations;
    }
    label(state, A);
    state.counters["per_iteration"] = benchmark::Counter(
        static_cast<double>(iterations), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(amg_iteration, point, false)->Apply(sizes);
BENCHMARK_CAPTURE(amg_iteration, node_blocks, true)->Apply(sizes);

/// Analyze + factorize with a fixed ordering: range(2) = 0 AMD, 1 METIS.
void BM_CholmodOrdering(benchmark::State& state) {
    const SparseMatrix& A = matrix(state);
    const Ordering ordering = state.range(2) ? Ordering::Metis : Ordering::Amd;
    CholmodSolver solver(ordering);
    for (auto _ : state)
        if (solver.factorize(A) != SolveStatus::Ok)
            state.SkipWithError("factorize failed");
    label(state, A);
    state.SetLabel(
        std::string(state.range(1) ? "kuhn15" : "hex27") + (state.range(2) ? " metis" : " amd"));
    state.counters["nnz_L"] = static_cast<double>(solver.factor_nonzeros());
}
BENCHMARK(BM_CholmodOrdering)
    ->Unit(benchmark::kMillisecond)
    ->Args({ 13, 1, 0 })
    ->Args({ 13, 1, 1 })
    ->Args({ 20, 1, 0 })
    ->Args({ 20, 1, 1 });

/// A full solve to 1e-6 from a warm start (the solution for the previous matrix A_old and a
/// right-hand side 1 % different), the lagged factor being that of A_old.
void pcg_solve(benchmark::State& state, Preconditioner preconditioner) {
    const SparseMatrix& A = matrix(state);
    const SparseMatrix& A_old = matrix(state, 2);
    const Vector b_old = random_vector(A.rows(), 3);
    const Vector b = b_old + 0.01 * random_vector(A.rows(), 4);
    CholmodSolver factor;
    factor.factorize(A_old);
    Vector x_old;
    factor.solve(b_old, x_old);
    PcgSolver pcg({ .relative_tolerance = 1e-6,
        .max_iterations = 10000,
        .preconditioner = preconditioner,
        .refactor_iterations = 100000 });
    if (preconditioner == Preconditioner::LaggedCholesky)
        pcg.set_preconditioner_factor(std::move(factor));
    Vector x;
    int iterations = 0;
    for (auto _ : state) {
        x = x_old;
        const PcgResult r = pcg.solve(A, b, x);
        iterations = r.iterations;
        if (r.status != SolveStatus::Ok)
            state.SkipWithError(to_string(r.status));
    }
    label(state, A);
    state.counters["iterations"] = iterations;
}
BENCHMARK_CAPTURE(pcg_solve, jacobi, Preconditioner::Jacobi)->Apply(sizes);
BENCHMARK_CAPTURE(pcg_solve, block_jacobi3, Preconditioner::BlockJacobi3)->Apply(sizes);
BENCHMARK_CAPTURE(pcg_solve, lagged, Preconditioner::LaggedCholesky)->Apply(sizes);

} // namespace

BENCHMARK_MAIN();
