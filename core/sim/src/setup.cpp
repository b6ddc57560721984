#include "setup.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/integrate/stability.hpp"

#include <cstdio>
#include <limits>

namespace polycut::sim {

elasticity::Material elasticity_material(const scene::Scene& s) {
    return s.material; // the scene reads the module's type (docs/decisions/0051)
}

basis::BasisOptions basis_options(const scene::Scene& s) {
    basis::BasisOptions b;
    const bool harmonic = s.method == scene::Method::Harmonic;
    b.poly = harmonic ? basis::PolyBasis::Harmonic : basis::PolyBasis::MeanValue;
    b.rule = s.basis.rule;
    if (harmonic && b.rule == basis::PolyRule::Heuristic)
        b.rule = basis::PolyRule::Reference; // the heuristic rule is specific to mean value cells
    b.gauss_degree = s.basis.gauss_degree;
    b.harmonic_xi = s.basis.harmonic_xi;
    b.volumetric = s.basis.volumetric;
    return b;
}

Index nearest_node(const mesh::Mesh& m, const Vec3& X) {
    std::vector<std::uint8_t> used(m.rest.size(), 0);
    for (const auto& c : m.cells)
        for (Index n : c.nodes)
            used[std::size_t(n)] = 1;
    Index best = kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (Index i = 0; i < m.num_nodes(); ++i) {
        if (!used[std::size_t(i)])
            continue;
        const double d = (m.rest[std::size_t(i)] - X).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best = i;
        }
    }
    return best;
}

std::vector<std::uint8_t> fixed_dofs_from_scene(const scene::Scene& s, const mesh::Mesh& m) {
    std::vector<std::uint8_t> mask(3 * m.rest.size(), 0);
    for (std::size_t f = 0; f < s.fixed.size(); ++f) {
        long count = 0;
        const Index nearest = s.fixed[f].at_node ? nearest_node(m, s.fixed[f].node) : kNone;
        for (std::size_t i = 0; i < m.rest.size(); ++i) {
            if (s.fixed[f].at_node ? Index(i) != nearest
                                   : !scene::selects(s.fixed[f].where, m.rest[i]))
                continue;
            ++count;
            for (int k = 0; k < 3; ++k)
                if (s.fixed[f].components[std::size_t(k)])
                    mask[3 * i + std::size_t(k)] = 1;
        }
        if (count == 0)
            throw SceneError("/fixed/" + std::to_string(f), "selects no node of the mesh");
    }
    return mask;
}

VecX scene_loads(const scene::Scene& s, const mesh::Mesh& m) {
    VecX f = VecX::Zero(3 * m.num_nodes());
    for (std::size_t i = 0; i < s.loads.forces.size(); ++i) {
        const scene::Force& force = s.loads.forces[i];
        const std::string where = "/loads/forces/" + std::to_string(i);
        if (force.kind == scene::Force::Kind::Point) {
            Vec3 X = force.point;
            if (!force.probe.empty())
                for (const auto& p : s.probes)
                    if (p.name == force.probe)
                        X = p.point;
            const Index n = nearest_node(m, X);
            f.segment<3>(3 * n) += force.force;
            continue;
        }
        std::vector<double> weight(m.rest.size(), 0.0);
        double total = 0;
        if (force.distribution == scene::Distribution::Uniform) {
            for (std::size_t n = 0; n < m.rest.size(); ++n)
                if (scene::selects(force.region, m.rest[n])) {
                    weight[n] = 1;
                    total += 1;
                }
        } else {
            // A traction: each boundary face inside the region gives its area to its nodes
            // (exact consistent load for P1 triangles, 1/3 per vertex).
            for (const auto& face : m.faces) {
                if (!face.boundary())
                    continue;
                bool inside = true;
                for (Index n : face.nodes)
                    inside = inside && scene::selects(force.region, m.rest[std::size_t(n)]);
                if (!inside)
                    continue;
                const double a = geometry::polygon_area(geometry::gather(m.rest, face.nodes));
                for (Index n : face.nodes)
                    weight[std::size_t(n)] += a / double(face.nodes.size());
                total += a;
            }
        }
        if (!(total > 0))
            throw SceneError(
                where, "selects no node (or no boundary face for \"area\") of the mesh");
        for (std::size_t n = 0; n < m.rest.size(); ++n)
            if (weight[n] > 0)
                f.segment<3>(3 * Index(n)) += force.force * (weight[n] / total);
    }
    for (std::size_t i = 0; i < s.loads.pressures.size(); ++i) {
        // Traction -p n on each boundary face whose nodes the region selects, n its outward
        // normal (boundary loops are outward for their cell): area A, force -p A n, split
        // equally over the face's nodes (exact for P1 triangles, consistent for planar
        // parallelograms).
        const scene::Pressure& pr = s.loads.pressures[i];
        long faces = 0;
        for (const auto& face : m.faces) {
            if (!face.boundary())
                continue;
            bool inside = true;
            for (Index n : face.nodes)
                inside = inside && scene::selects(pr.region, m.rest[std::size_t(n)]);
            if (!inside)
                continue;
            ++faces;
            // Newell's vector: twice the area times the unit normal
            const Vec3 area_normal
                = 0.5 * geometry::newell_vector(geometry::gather(m.rest, face.nodes));
            const Vec3 share = -pr.pressure * area_normal / double(face.nodes.size());
            for (Index n : face.nodes)
                f.segment<3>(3 * n) += share;
        }
        if (faces == 0)
            throw SceneError(
                "/loads/pressure/" + std::to_string(i), "selects no boundary face of the mesh");
    }
    return f;
}

} // namespace polycut::sim

namespace polycut::sim {

void check_time_step(const scene::Scene& s, const elasticity::ElasticModel& model) {
    if (s.integrator.type != integrate::IntegratorKind::SemiImplicitEuler)
        return;
    const integrate::StabilityLimit limit = integrate::semi_implicit_limit(model);
    if (s.integrator.dt <= limit.critical_dt)
        return;
    char text[320];
    std::snprintf(text, sizeof text,
        "semi_implicit_euler is unstable at dt = %.3g s on this mesh and material: its limit is "
        "%.3g s (highest element frequency %.3g rad/s, with the scene's Rayleigh damping); use "
        "dt <= %.3g s or \"implicit_euler\"",
        s.integrator.dt, limit.critical_dt, limit.omega_max, limit.critical_dt);
    throw SceneError("/integrator/dt", text);
}

integrate::LinearSolverKind linear_solver_kind(const scene::Solver& sv) {
    using K = integrate::LinearSolverKind;
    switch (sv.type) {
    case scene::SolverType::Cholmod:
        return K::Cholmod;
    case scene::SolverType::CgRelaxation:
        return K::CgRelaxation;
    case scene::SolverType::Pcg:
        break;
    }
    switch (sv.preconditioner) {
    case scene::Preconditioner::BlockJacobi:
        return K::PcgBlockJacobi;
    case scene::Preconditioner::CellBlockJacobi:
        return K::PcgCellBlockJacobi;
    case scene::Preconditioner::LaggedCholesky:
        return K::PcgLagged;
    case scene::Preconditioner::Amg:
        return K::PcgAmg;
    case scene::Preconditioner::TwoLevel:
        return K::PcgTwoLevel;
    case scene::Preconditioner::Jacobi:
        break;
    }
    return K::PcgJacobi;
}

integrate::IntegratorOptions integrator_options(const scene::Scene& s) {
    integrate::IntegratorOptions o;
    const auto& it = s.integrator;
    o.kind = it.type;
    o.dt = it.dt;
    o.force_mode = it.corotated ? elasticity::ForceMode::Corotated : elasticity::ForceMode::Linear;
    o.static_mode = it.corotated ? it.static_mode : integrate::StaticMode::Linear;
    o.static_tolerance = it.tolerance;
    o.static_max_iterations = it.max_iterations;
    o.gravity = s.loads.gravity;
    const auto& sv = s.solver;
    o.solver.kind = linear_solver_kind(sv);
    o.solver.relative_tolerance = sv.tolerance;
    o.solver.load_tolerance = sv.load_tolerance;
    o.solver.max_iterations = sv.max_iterations;
    o.solver.iteration_budget = sv.iteration_budget;
    o.solver.refactor_every = sv.refactor_every;
    o.solver.refactor_iterations = sv.refactor_iterations;
    // projected: the extrapolated guess while no solutions are kept (the first step, after a
    // rolled-back step or a cut that set the preconditioner up anew)
    o.extrapolate_warm_start = sv.warm_start != scene::WarmStart::Previous;
    o.solver.start_vectors = sv.warm_start == scene::WarmStart::Projected ? sv.start_vectors : 0;
    o.solver.amg.strong_threshold = sv.amg_strong_threshold;
    o.solver.amg.aggressive_levels = sv.amg_aggressive_levels;
    o.solver.amg.interpolation_max_elements = sv.amg_interpolation_max_elements;
    o.solver.amg.max_coarse_size = sv.amg_max_coarse_size;
    o.solver.amg.rigid_body_modes = sv.amg_rigid_body_modes;
    o.solver.amg.node_blocks = sv.amg_node_blocks;
    o.solver.amg.background_solves = sv.amg_background_solves;
    o.solver.amg.background_serial = sv.amg_background_serial;
    o.solver.amg.refresh_delay = sv.amg_refresh_delay;
    o.threads = it.threads;
    o.stiffness_every = it.stiffness_every;
    o.energy_guard = it.energy_guard;
    return o;
}

double element_cost(const mesh::Mesh& m) {
    // Per entry, a cell of any other kind (a cut polyhedron, a hex) costs this many times a
    // tet's, which the batched P1 kernel assembles: a 2,000-triangle soup split through
    // organ_5k, assembly 0.97 ns per tet entry and 3.9 per polyhedron entry (r over 285 ticks),
    // each PCG iteration 0.34 and 1.65 (docs/perf.md 2026-12-05 fifteenth).
    constexpr double kGeneralCellWeight = 4.0;
    double cost = 0;
    for (const mesh::Cell& c : m.cells) {
        const double n = double(c.nodes.size());
        cost += (c.nodes.size() == 4 ? 1.0 : kGeneralCellWeight) * 9.0 * n * n;
    }
    return cost;
}

Index cut_call_cost(const mesh::Mesh& m) {
    // Replayed organ_5k split logs (2026-12-05): time of a call = 6.5 ms + 0.025 ms per unit of
    // the cells it changed; the default block's 3,000 cells 0.2-1 ms.
    constexpr Index kCellsPerUnit = 200;
    return Index(m.cells.size()) / kCellsPerUnit;
}

} // namespace polycut::sim
