// BoomerAMG (hypre) as a PCG preconditioner for the reduced elasticity systems. One process, on
// MPI_COMM_SELF: the matrix is one ParCSR block (no off-processor part). Per application: copy r
// into hypre's vector, one V-cycle from zero, copy the result out. The cycle is symmetric (forward
// l1-Gauss-Seidel down, backward up, Galerkin coarse operators P^T A P, exact coarsest solve),
// so PCG's theory holds. Systems AMG for elasticity: `functions` interleaved unknowns per node,
// nodal coarsening on the row-sum norms of the node blocks (hypre "nodal 4"), the classic
// recommendation for 3D elasticity with BoomerAMG (hypre manual, "systems of PDEs").
#include "amg_preconditioner.hpp"

#include "amg_cycle.hpp"
#include "hypre_runtime.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#ifdef POLYCUT_HAVE_HYPRE
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h>
#include <_hypre_parcsr_mv.h>
#endif

namespace polycut::solve::detail {

#ifdef POLYCUT_HAVE_HYPRE

struct AmgPreconditioner::Impl {
    AmgOptions options;
    bool runtime = false; ///< holds a reference on the MPI/hypre runtime
    std::string error;
    long n = -1;
    HYPRE_IJMatrix ij_matrix = nullptr;
    HYPRE_IJVector ij_b = nullptr, ij_x = nullptr;
    HYPRE_ParCSRMatrix matrix = nullptr;
    HYPRE_ParVector b = nullptr, x = nullptr;
    HYPRE_Solver amg = nullptr;
    std::vector<HYPRE_Int> row_sizes, rows;
    Vector coordinates; ///< set_coordinates()
    AmgCycle cycle; ///< options.fused_cycle: our V-cycle over the copied hierarchy
    bool use_cycle = false;
    int cycle_levels = 0;
    // rigid-body rotations handed to hypre (it keeps pointers until the solver is destroyed)
    std::vector<HYPRE_IJVector> ij_modes;
    std::vector<HYPRE_ParVector> modes;

    explicit Impl(AmgOptions o)
        : options(o) { }

    ~Impl() { clear(); }

    void set_threads(int threads) { cycle.set_threads(threads); }

    /// Frees the BoomerAMG solver and the rigid-body modes (lock held).
    void destroy_solver_locked() {
        if (amg)
            HYPRE_BoomerAMGDestroy(amg);
        amg = nullptr;
        for (HYPRE_IJVector v : ij_modes)
            HYPRE_IJVectorDestroy(v);
        ij_modes.clear();
        modes.clear();
    }

    /// Frees the hypre objects (lock held by the caller or not needed).
    void destroy_locked() {
        destroy_solver_locked();
        if (ij_matrix)
            HYPRE_IJMatrixDestroy(ij_matrix);
        if (ij_b)
            HYPRE_IJVectorDestroy(ij_b);
        if (ij_x)
            HYPRE_IJVectorDestroy(ij_x);
        ij_matrix = nullptr;
        ij_b = ij_x = nullptr;
        matrix = nullptr;
        b = x = nullptr;
        n = -1;
    }

    void clear() {
        {
            std::lock_guard lock(hypre_mutex());
            destroy_locked();
        }
        cycle.clear();
        use_cycle = false;
        if (runtime) {
            hypre_release();
            runtime = false;
        }
    }

    HYPRE_ParVector make_vector(HYPRE_IJVector& ij, HYPRE_Int size) {
        HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, size - 1, &ij);
        HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR);
        HYPRE_IJVectorInitialize(ij);
        HYPRE_IJVectorAssemble(ij);
        void* object = nullptr;
        HYPRE_IJVectorGetObject(ij, &object);
        return static_cast<HYPRE_ParVector>(object);
    }

    static double* data(HYPRE_ParVector v) {
        return hypre_VectorData(hypre_ParVectorLocalVector(reinterpret_cast<hypre_ParVector*>(v)));
    }

    /// The rigid-body modes can be used (options, 3 functions, coordinates of this size).
    bool modes_wanted() const {
        return options.rigid_body_modes && options.functions == 3 && n % 3 == 0
            && coordinates.size() == n;
    }

    /// Creates and configures the BoomerAMG solver (lock held); `with_modes`: add the rigid-body
    /// rotations of `coordinates` to the interpolation.
    void configure_locked(bool with_modes) {
        const AmgOptions& o = options;
        HYPRE_BoomerAMGCreate(&amg);
        HYPRE_BoomerAMGSetPrintLevel(amg, 0);
        HYPRE_BoomerAMGSetLogging(amg, 0);
        HYPRE_BoomerAMGSetMaxIter(amg, 1); // one V-cycle per application...
        HYPRE_BoomerAMGSetTol(amg, 0.0); // ...and no residual norm computed for a stopping test
        HYPRE_BoomerAMGSetCoarsenType(amg, 10); // HMIS
        HYPRE_BoomerAMGSetInterpType(amg, 6); // extended+i
        HYPRE_BoomerAMGSetPMaxElmts(amg, o.interpolation_max_elements);
        HYPRE_BoomerAMGSetStrongThreshold(amg, o.strong_threshold);
        HYPRE_BoomerAMGSetAggNumLevels(amg, o.aggressive_levels);
        HYPRE_BoomerAMGSetAggInterpType(amg, 4); // multipass on the aggressive levels
        HYPRE_BoomerAMGSetNumSweeps(amg, o.sweeps);
        switch (o.smoother) {
        case AmgSmoother::GaussSeidel:
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 13, 1); // down: forward l1-Gauss-Seidel
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 14, 2); // up: backward (the adjoint: symmetric)
            HYPRE_BoomerAMGSetRelaxOrder(amg, o.cf_order ? 1 : 0);
            break;
        case AmgSmoother::L1Jacobi:
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 18, 1);
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 18, 2);
            HYPRE_BoomerAMGSetRelaxOrder(amg, 0);
            break;
        case AmgSmoother::Chebyshev:
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 16, 1);
            HYPRE_BoomerAMGSetCycleRelaxType(amg, 16, 2);
            HYPRE_BoomerAMGSetChebyOrder(amg, 2);
            break;
        }
        HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3); // coarsest: Gaussian elimination
        HYPRE_BoomerAMGSetMaxCoarseSize(amg, o.max_coarse_size);
        HYPRE_BoomerAMGSetKeepTranspose(amg, 1); // P^T stored: faster restriction
        const int functions = (o.functions > 1 && n % o.functions == 0) ? o.functions : 1;
        if (functions > 1) {
            HYPRE_BoomerAMGSetNumFunctions(amg, functions);
            HYPRE_BoomerAMGSetNodal(amg, 4); // coarsen nodes, strength from row-sum block norms
            HYPRE_BoomerAMGSetNodalDiag(amg, 1);
        }
        if (functions == 3 && with_modes) {
            // the three infinitesimal rotations w x p of the node positions p about their
            // centroid (Baker, Kolev & Yang 2010, GM-2): e_x x p = (0, -z, y), e_y x p =
            // (z, 0, -x), e_z x p = (-y, x, 0)
            const auto size = static_cast<HYPRE_Int>(n);
            Eigen::Vector3d centre = Eigen::Vector3d::Zero();
            for (long node = 0; node < n / 3; ++node)
                centre += coordinates.segment<3>(3 * node);
            centre /= double(std::max<long>(n / 3, 1));
            ij_modes.assign(3, nullptr);
            modes.assign(3, nullptr);
            for (int axis = 0; axis < 3; ++axis) {
                modes[size_t(axis)] = make_vector(ij_modes[size_t(axis)], size);
                double* m = data(modes[size_t(axis)]);
                for (long node = 0; node < n / 3; ++node) {
                    const Eigen::Vector3d p = coordinates.segment<3>(3 * node) - centre;
                    double* u = m + 3 * node;
                    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                    u[axis] = 0;
                    u[a1] = -p[a2];
                    u[a2] = p[a1];
                }
            }
            HYPRE_BoomerAMGSetInterpVecVariant(amg, 2);
            HYPRE_BoomerAMGSetInterpVecQMax(amg, o.rigid_body_max_elements);
            HYPRE_BoomerAMGSetInterpVectors(amg, 3, modes.data());
        }
    }

    SolveStatus setup(const SparseMatrix& A) {
        const long rows_n = A.rows();
        const int* outer = A.outerIndexPtr();
        const int* nnz = A.innerNonZeroPtr();
        // validate before touching hypre: NaN/Inf or a non-positive diagonal cannot be SPD
        for (long j = 0; j < rows_n; ++j) {
            const int begin = outer[j];
            const int end = nnz ? begin + nnz[j] : outer[j + 1];
            bool diagonal = false;
            for (int k = begin; k < end; ++k) {
                const double v = A.valuePtr()[k];
                if (!std::isfinite(v))
                    return SolveStatus::NonFinite;
                if (A.innerIndexPtr()[k] == j) {
                    diagonal = true;
                    if (!(v > 0))
                        return SolveStatus::NotPositiveDefinite;
                }
            }
            if (!diagonal)
                return SolveStatus::NotPositiveDefinite;
        }
        if (!runtime) {
            if (!hypre_acquire(error))
                return SolveStatus::NotReady;
            runtime = true;
        }
        const SparseMatrix* source = &A;
        SparseMatrix compressed;
        if (!A.isCompressed()) {
            compressed = A;
            compressed.makeCompressed();
            source = &compressed;
        }
        std::lock_guard lock(hypre_mutex());
        destroy_locked();
        cycle.clear();
        use_cycle = false;
        n = rows_n;
        const auto size = static_cast<HYPRE_Int>(n);
        // symmetric full storage: column j of the CSC arrays is row j of a CSR matrix
        row_sizes.resize(static_cast<size_t>(n));
        rows.resize(static_cast<size_t>(n));
        for (long j = 0; j < n; ++j) {
            rows[static_cast<size_t>(j)] = static_cast<HYPRE_Int>(j);
            row_sizes[static_cast<size_t>(j)] = static_cast<HYPRE_Int>(
                source->outerIndexPtr()[j + 1] - source->outerIndexPtr()[j]);
        }
        HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, size - 1, 0, size - 1, &ij_matrix);
        HYPRE_IJMatrixSetObjectType(ij_matrix, HYPRE_PARCSR);
        HYPRE_IJMatrixSetRowSizes(ij_matrix, row_sizes.data());
        HYPRE_IJMatrixInitialize(ij_matrix);
        HYPRE_IJMatrixSetValues(ij_matrix, size, row_sizes.data(), rows.data(),
            source->innerIndexPtr(), source->valuePtr());
        HYPRE_IJMatrixAssemble(ij_matrix);
        void* object = nullptr;
        HYPRE_IJMatrixGetObject(ij_matrix, &object);
        matrix = static_cast<HYPRE_ParCSRMatrix>(object);
        b = make_vector(ij_b, size);
        x = make_vector(ij_x, size);
        configure_locked(modes_wanted());
        HYPRE_Int status = HYPRE_BoomerAMGSetup(amg, matrix, b, x);
        const auto failed = [&] { return status != 0 && HYPRE_GetError() != HYPRE_ERROR_CONV; };
        if (failed() && !modes.empty()) {
            // hypre's GM-2 fit can fail on some node sets (seen on rest-state grids): plain
            // nodal interpolation instead
            HYPRE_ClearAllErrors();
            destroy_solver_locked();
            configure_locked(false);
            status = HYPRE_BoomerAMGSetup(amg, matrix, b, x);
        }
        if (failed()) {
            char what[256] = {};
            HYPRE_DescribeError(status, what);
            HYPRE_ClearAllErrors();
            error = std::string("BoomerAMG set-up failed: ") + what;
            destroy_locked();
            return SolveStatus::NotReady;
        }
        HYPRE_ClearAllErrors();
        use_cycle = false;
        cycle.clear();
        cycle.set_node_blocks(options.node_blocks);
        if (fused_wanted() && copy_hierarchy_locked(*source)) {
            // hypre's copies are no longer needed
            const long rows_kept = n;
            destroy_locked();
            n = rows_kept;
            use_cycle = true;
        }
        return SolveStatus::Ok;
    }

    bool fused_wanted() const {
        return options.fused_cycle && options.smoother == AmgSmoother::GaussSeidel
            && options.sweeps == 1 && !options.cf_order;
    }

    /// Copies hypre's coarse operators and interpolations into `cycle` (lock held).
    bool copy_hierarchy_locked(const SparseMatrix& A) {
        static_assert(sizeof(HYPRE_Int) == sizeof(int) && sizeof(HYPRE_Real) == sizeof(double));
        auto* data = reinterpret_cast<hypre_ParAMGData*>(amg);
        const int count = static_cast<int>(hypre_ParAMGDataNumLevels(data));
        hypre_ParCSRMatrix** A_array = hypre_ParAMGDataAArray(data);
        hypre_ParCSRMatrix** P_array = hypre_ParAMGDataPArray(data);
        for (int l = 1; l < count; ++l) {
            hypre_CSRMatrix* a = hypre_ParCSRMatrixDiag(A_array[l]);
            hypre_CSRMatrix* p = hypre_ParCSRMatrixDiag(P_array[l - 1]);
            if (hypre_CSRMatrixNumCols(p) != hypre_CSRMatrixNumRows(a)
                || hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixOffd(A_array[l])) != 0)
                return false;
            if (!cycle.add_level(hypre_CSRMatrixNumRows(a), hypre_CSRMatrixI(a),
                    hypre_CSRMatrixJ(a), hypre_CSRMatrixData(a), hypre_CSRMatrixNumRows(p),
                    hypre_CSRMatrixI(p), hypre_CSRMatrixJ(p), hypre_CSRMatrixData(p)))
                return false;
        }
        cycle_levels = count;
        return cycle.finish(A);
    }

    bool remap(const RowRemap& m) {
        if (!use_cycle || n < 0 || !cycle.remap(m))
            return false;
        n = long(m.old_of.size());
        return true;
    }

    SolveStatus apply(const SparseMatrix& A, const Vector& r, Vector& z) {
        if (n < 0 || r.size() != n)
            return SolveStatus::NotReady;
        if (use_cycle) {
            if (A.rows() != n)
                return SolveStatus::NotReady;
            if (!cycle.apply(A, r, z))
                return SolveStatus::NotPositiveDefinite;
            return z.allFinite() ? SolveStatus::Ok : SolveStatus::NonFinite;
        }
        z.resize(n);
        {
            std::lock_guard lock(hypre_mutex());
            std::memcpy(data(b), r.data(), sizeof(double) * static_cast<size_t>(n));
            std::memset(data(x), 0, sizeof(double) * static_cast<size_t>(n));
            HYPRE_BoomerAMGSolve(amg, matrix, b, x);
            HYPRE_ClearAllErrors(); // "not converged" after the one cycle asked for
            std::memcpy(z.data(), data(x), sizeof(double) * static_cast<size_t>(n));
        }
        return z.allFinite() ? SolveStatus::Ok : SolveStatus::NonFinite;
    }

    int threaded_levels() const { return use_cycle ? cycle.threaded_levels() : 0; }

    int levels() const {
        if (use_cycle)
            return cycle_levels;
        if (!amg)
            return 0;
        return static_cast<int>(
            hypre_ParAMGDataNumLevels(reinterpret_cast<hypre_ParAMGData*>(amg)));
    }
};

#else // built without hypre: every set-up reports NotReady

struct AmgPreconditioner::Impl {
    AmgOptions options;
    std::string error = "polycut was built without hypre (libhypre-dev)";
    long n = -1;
    Vector coordinates;
    explicit Impl(AmgOptions o)
        : options(o) { }
    void clear() { }
    void set_threads(int) { }
    SolveStatus setup(const SparseMatrix&) { return SolveStatus::NotReady; }
    SolveStatus apply(const SparseMatrix&, const Vector&, Vector&) { return SolveStatus::NotReady; }
    bool remap(const RowRemap&) { return false; }
    int levels() const { return 0; }
    int threaded_levels() const { return 0; }
};

#endif

AmgPreconditioner::AmgPreconditioner(AmgOptions options)
    : m_impl(std::make_unique<Impl>(options)) { }

AmgPreconditioner::~AmgPreconditioner() = default;

SolveStatus AmgPreconditioner::setup(const SparseMatrix& A) {
    return m_impl->setup(A);
}

SolveStatus AmgPreconditioner::apply(const SparseMatrix& A, const Vector& r, Vector& z) {
    return m_impl->apply(A, r, z);
}

void AmgPreconditioner::matrix_changed() {
    m_impl->cycle.matrix_changed();
}

void AmgPreconditioner::set_threads(int threads) {
    m_impl->set_threads(threads);
}

long AmgPreconditioner::size() const {
    return m_impl->n;
}

int AmgPreconditioner::levels() const {
    return m_impl->levels();
}

int AmgPreconditioner::threaded_levels() const {
    return m_impl->threaded_levels();
}

void AmgPreconditioner::set_coordinates(const Vector& coordinates) {
    m_impl->coordinates = coordinates;
}

const std::string& AmgPreconditioner::error() const {
    return m_impl->error;
}

void AmgPreconditioner::clear() {
    m_impl->clear();
}

bool AmgPreconditioner::remap(const RowRemap& m) {
    return m_impl->remap(m);
}

} // namespace polycut::solve::detail
