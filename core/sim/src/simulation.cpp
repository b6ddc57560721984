// sim::Simulation: construction from a scene, stepping, forces and grabs.
#include "build_clock.hpp"
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/contact/triangle_mesh_distance.hpp"
#include "polycut/embed/embedding.hpp"
#include "polycut/embed/split.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/meshing/octree.hpp"
#include "polycut/sim/build_mesh.hpp"
#include "setup.hpp"

#include <cmath>

namespace polycut::sim {

Simulation::Simulation(scene::Scene scene)
    : m_impl(std::make_unique<Impl>()) {
    m_impl->scene = std::move(scene);
    PartClock clock;
    m_impl->initial_mesh = build_mesh(m_impl->scene, &m_impl->meshing);
    clock.lap(m_impl->build_parts, "mesh", true);
    m_impl->build();
    m_impl->build_scripted_tools(*this);
}

Simulation::~Simulation() = default;

const scene::Scene& Simulation::scene() const {
    return m_impl->scene;
}
long Simulation::tick() const {
    return m_impl->tick;
}
double Simulation::time() const {
    return m_impl->time;
}
bool Simulation::is_static() const {
    return m_impl->scene.integrator.type == integrate::IntegratorKind::Static;
}

void Simulation::Impl::build() {
    build_parts.resize(std::min<std::size_t>(build_parts.size(), 1)); // keep the mesh's
    PartClock clock;
    cut_undo.reset();
    swept_area = 0;
    swept_area_undone = 0;
    body_volume = initial_mesh.rest_volume();
    initial_cell_size
        = std::cbrt(body_volume / double(std::max<Index>(1, initial_mesh.num_cells())));
    max_cell_diameter = 0;
    for (Index c = 0; c < initial_mesh.num_cells(); ++c) {
        geometry::Aabb box;
        for (const Index n : initial_mesh.cells[std::size_t(c)].nodes)
            box.extend(initial_mesh.rest[std::size_t(n)]);
        max_cell_diameter = std::max(max_cell_diameter, box.diagonal());
    }
    mesh = initial_mesh;
    if (scene.method == scene::Method::Dg) {
        // DG (seed 003): the integrator steps the coefficients; nodes only carry the stitched
        // field (docs/decisions/0021). Fixed regions are weak, so no DOF is eliminated.
        model.reset();
        node_fixed_mask.assign(3 * mesh.rest.size(), 0);
        scene_forces = VecX::Zero(3 * mesh.num_nodes());
        dg = make_dg_part(scene, mesh);
        clock.lap(build_parts, "dg_model", true);
        integrator = std::make_unique<integrate::Integrator>(*dg->model, integrator_options(scene));
    } else {
        dg.reset();
        node_fixed_mask = fixed_dofs_from_scene(scene, mesh);
        scene_forces = scene_loads(scene, mesh);
        model = std::make_unique<elasticity::ElasticModel>(
            mesh, elasticity_material(scene), basis_options(scene), node_fixed_mask);
        clock.lap(build_parts, "model", true);
        initial_element_cost = element_cost(mesh);
        integrator = std::make_unique<integrate::Integrator>(*model, integrator_options(scene));
        check_time_step(scene, *model); // refuses a step an explicit integrator cannot take
    }
    clock.lap(build_parts, "integrator", true);
    cutting.reset();
    cutting_prepared = false;
    cut_cells_left = scene.cutting.max_cells_per_tick;
    state = integrator->rest_state();
    forces.clear();
    grabs.clear();
    tools.clear();
    reactions.clear();
    contact.reset();
    build_obstacles();
    tick = 0;
    time = 0;
    static_solved = false;
    clock.lap(build_parts, "contact", contact != nullptr);
    sync_positions();
    refresh_topology();
    clock.lap(build_parts, "surface", true);
    build_embedded();
    clock.lap(build_parts, "embedded", embedded != nullptr);
    build_octree();
    clock.lap(build_parts, "octree", octree != nullptr);
    // the first step's AMG set-up, here (off the tick when a server loads a scene)
    const bool prepared = integrator->prepare(state);
    clock.lap(build_parts, "solver", prepared);
}

void Simulation::reset() {
    m_impl->build();
    m_impl->build_scripted_tools(*this);
    ++m_impl->topology_version;
}

void Simulation::Impl::sync_positions() {
    if (dg) {
        dg->stitching->positions(state.x, positions); // 003 eq. 17
        return;
    }
    positions.resize(std::size_t(state.x.rows()));
    for (Index i = 0; i < Index(state.x.rows()); ++i)
        positions[std::size_t(i)] = state.x.row(i).transpose();
}

void Simulation::Impl::refresh_topology() {
    topology = surface::extract_topology(mesh);
    ++topology_version;
    refresh_embedded();
}

NodeWeights Simulation::Impl::pick(const Vec3& p, double radius) const {
    // Hat kernel over the nodes within `radius` of p in the current configuration; the nearest
    // node alone when none lies within but p is within `radius` of the material. Only nodes that
    // belong to a cell are picked. A material point within `radius` of p lies in a cell whose
    // nodes are all within the cell's diameter of it, so no node within radius + the largest
    // cell diameter means no material within `radius`: StateError, nothing changed.
    NodeWeights out;
    double total = 0;
    Index nearest = kNone;
    double best = std::numeric_limits<double>::infinity();
    for (Index i = 0; i < Index(positions.size()); ++i) {
        if (dg ? !dg->stitching->used(i) : !(model->nodal_mass()[i] > 0))
            continue;
        const double d = (positions[std::size_t(i)] - p).norm();
        if (d < best) {
            best = d;
            nearest = i;
        }
        if (d < radius) {
            const double w = 1.0 - d / radius;
            out.nodes.push_back(i);
            out.weights.push_back(w);
            total += w;
        }
    }
    if (out.nodes.empty() && !(best <= radius + max_cell_diameter)) {
        throw StateError("point",
            nearest == kNone ? std::string("the tissue has no nodes")
                             : "no material within " + std::to_string(radius)
                    + " m of the point (the nearest node is " + std::to_string(best) + " m away)");
    }
    if (out.nodes.empty() && nearest != kNone) {
        out.nodes.push_back(nearest);
        out.weights.push_back(1.0);
        total = 1.0;
    }
    for (double& w : out.weights)
        w /= total;
    return out;
}

void Simulation::Impl::assemble_external(double sim_time) {
    f_ext = scene_forces;
    for (auto it = forces.begin(); it != forces.end();) {
        if (it->second.expires > 0 && sim_time > it->second.expires + 1e-12) {
            it = forces.erase(it);
            static_solved = false;
            continue;
        }
        const auto& a = it->second.at;
        for (std::size_t k = 0; k < a.nodes.size(); ++k)
            f_ext.segment<3>(3 * a.nodes[k]) += a.weights[k] * it->second.spec.force;
        ++it;
    }
}

std::vector<integrate::NodeSpring> Simulation::Impl::grab_springs() {
    std::vector<integrate::NodeSpring> out;
    for (auto& [id, g] : grabs) {
        if (g.offset_nodes != g.at.nodes) {
            // A cut renumbered the nodes: look each one's offset up by its rest position.
            g.node_offset.assign(g.at.nodes.size(), Vec3::Zero());
            for (std::size_t k = 0; k < g.at.nodes.size(); ++k) {
                const Vec3& X = mesh.rest[std::size_t(g.at.nodes[k])];
                double best = std::numeric_limits<double>::infinity();
                for (std::size_t j = 0; j < g.offset_rest.size(); ++j)
                    if (const double d = (g.offset_rest[j] - X).squaredNorm(); d < best) {
                        best = d;
                        g.node_offset[k] = g.offset[j];
                    }
            }
            g.offset_nodes = g.at.nodes;
        }
        for (std::size_t k = 0; k < g.at.nodes.size(); ++k)
            out.push_back(
                { g.at.nodes[k], g.target + g.node_offset[k], g.spec.stiffness * g.at.weights[k] });
    }
    return out;
}

StepReport Simulation::step() {
    Impl& s = *m_impl;
    Stopwatch watch;
    StepReport r;
    const double dt = is_static() ? 0.0 : s.scene.integrator.dt;
    try {
        s.refresh_embedded(); // after the undo of a failed cut
        s.assemble_external(s.time + dt);
        if (is_static() && s.static_solved) {
            // Equilibrium already holds for unchanged loads.
        } else {
            if (s.dg) {
                // DG: nodal forces and grabs act on the stitched nodes, through the
                // stitching's adjoint; grabs are explicit springs here (their stiffness
                // couples whole cells, not one row). Contact is not coupled to DG yet.
                for (const integrate::NodeSpring& k : s.grab_springs())
                    s.f_ext.segment<3>(3 * k.node)
                        += k.stiffness * (k.anchor - s.positions[std::size_t(k.node)]);
                s.dg->stitching->loads(s.f_ext, s.dg->load);
                s.dg->load += s.dg->scene_load;
                s.integrator->set_external_forces(s.dg->load);
                s.integrator->set_springs({});
            } else {
                s.integrator->set_external_forces(s.f_ext);
                s.integrator->set_springs(s.grab_springs());
                s.prepare_contact(dt);
            }
            const integrate::StepReport ir = s.integrator->step(s.state);
            r.assembly_ms = ir.assembly_ms;
            r.solve_ms = ir.solve_ms;
            r.solver_iterations = ir.solver_iterations;
            r.solver_budget_reached = ir.solver_budget_reached;
            r.newton_iterations = ir.newton_iterations;
            r.residual = ir.residual;
            r.rolled_back = ir.rolled_back;
            r.warnings = ir.warnings;
            s.static_solved = is_static() && !ir.rolled_back;
            if (ir.penalty_entries_dropped > 0)
                r.warnings.push_back(std::to_string(ir.penalty_entries_dropped)
                    + " contact matrix entries outside the sparsity pattern were dropped");
            if (s.dg && s.scene.dg.refine_stress > 0 && !ir.rolled_back)
                if (auto refined = dg_refine(*s.dg, s.scene, s.mesh, s.state.x, s.state.v)) {
                    // 003 sec. 10: stressed cells split 1-to-8, children from the parent
                    s.dg = std::move(refined);
                    s.integrator = std::make_unique<integrate::Integrator>(
                        *s.dg->model, integrator_options(s.scene));
                    s.node_fixed_mask.assign(3 * s.mesh.rest.size(), 0);
                    s.scene_forces = VecX::Zero(3 * s.mesh.num_nodes());
                    s.cutting.reset(); // its adjacency is of the old mesh
                    s.cutting_prepared = false;
                    s.static_solved = false; // a static scene solves again on the finer mesh
                    s.refresh_topology();
                    r.topology_changed = true;
                }
            if (s.octree && !ir.rolled_back && s.refine_octree(r) > 0)
                r.topology_changed = true; // 001 sec. 8: stressed cells split 1-to-8
        }
        s.sync_positions();
        s.measure_contact();
    } catch (const std::exception& e) {
        // step() never throws: report and keep the last good state.
        r.warnings.push_back(std::string("step failed: ") + e.what());
        r.rolled_back = true;
    }
    if (r.rolled_back && s.cut_undo) {
        // The first step on a freshly cut mesh failed (diverged, exploded, did not converge):
        // the cut made the model unsound, so it goes too, and the tissue steps on uncut.
        // An exploded state is never published.
        try {
            s.restore(*s.cut_undo, true);
            r.cut_undone = true;
            r.warnings.push_back("cut undone: the first step after it failed");
        } catch (const std::exception& e) {
            r.warnings.push_back(std::string("cut could not be undone: ") + e.what());
        }
    }
    if (s.cut_inverted > 0) {
        // Said after the step's own warnings (a warning event shows the first).
        r.warnings.push_back("cut through folded tissue: " + std::to_string(s.cut_inverted)
            + (s.cut_inverted == 1 ? " inverted cell" : " inverted cells")
            + " around the blade; there the world-to-rest map is not one-to-one and the cut "
              "follows the fold only approximately");
        s.cut_inverted = 0;
    }
    if (s.cut_stretched > 0) {
        r.warnings.push_back(std::to_string(s.cut_stretched)
            + (s.cut_stretched == 1 ? " sweep triangle" : " sweep triangles")
            + " not cut: mapped to rest space through folded or crushed tissue, the image came "
              "out more than "
            + std::to_string(int(cut::kMaxRestStretch))
            + "x longer or larger than the blade swept (docs/scenes.md \"Completeness\")");
        s.cut_stretched = 0;
    }
    if (s.cut_undo)
        s.spare = std::move(s.cut_undo); // its buffers serve the next cut's undo copy
    if (s.cutting && !r.rolled_back)
        s.cutting->accept(); // the cuts so far made a sound model: the undo mirror takes them
    if (s.model)
        s.model->forget_marks(); // no snapshot of before this step can be restored any more
    s.cut_cells_left = s.scene.cutting.max_cells_per_tick;
    ++s.tick;
    s.time += dt;
    r.tick = s.tick;
    r.sim_time = s.time;
    r.step_ms = watch.ms();
    return r;
}

namespace {
void require_finite(const Vec3& v, const char* what) {
    if (!v.allFinite())
        throw InputError(what, "must be finite");
}
void require_positive(double x, const char* what) {
    if (!std::isfinite(x) || !(x > 0))
        throw InputError(what, "must be a finite number > 0");
}
} // namespace

long Simulation::add_force(const ForceSpec& f) {
    require_finite(f.point, "point");
    require_finite(f.force, "force");
    require_positive(f.radius, "radius");
    if (!std::isfinite(f.duration) || f.duration < 0)
        throw InputError("duration", "must be a finite number >= 0");
    Impl& s = *m_impl;
    ActiveForce a;
    a.spec = f;
    a.at = s.pick(f.point, f.radius);
    a.expires = f.duration > 0 ? s.time + f.duration : 0.0;
    const long id = s.next_id++;
    s.forces.emplace(id, std::move(a));
    s.static_solved = false;
    return id;
}

bool Simulation::remove_force(long id) {
    m_impl->static_solved = false;
    return m_impl->forces.erase(id) > 0;
}

long Simulation::grab(const GrabSpec& g) {
    require_finite(g.point, "point");
    require_positive(g.stiffness, "stiffness");
    require_positive(g.radius, "radius");
    Impl& s = *m_impl;
    ActiveGrab a;
    a.spec = g;
    a.at = s.pick(g.point, g.radius);
    Vec3 xc = Vec3::Zero();
    for (std::size_t k = 0; k < a.at.nodes.size(); ++k)
        xc += a.at.weights[k] * s.positions[std::size_t(a.at.nodes[k])];
    a.target = xc;
    for (const Index n : a.at.nodes) {
        a.offset_rest.push_back(s.mesh.rest[std::size_t(n)]);
        a.offset.push_back(s.positions[std::size_t(n)] - xc);
    }
    a.offset_nodes = a.at.nodes;
    a.node_offset = a.offset;
    const long id = s.next_id++;
    s.grabs.emplace(id, std::move(a));
    s.static_solved = false;
    return id;
}

bool Simulation::move_grab(long id, const Vec3& target) {
    require_finite(target, "target");
    auto it = m_impl->grabs.find(id);
    if (it == m_impl->grabs.end())
        return false;
    it->second.target = target;
    m_impl->static_solved = false;
    return true;
}

bool Simulation::release(long id) {
    m_impl->static_solved = false;
    return m_impl->grabs.erase(id) > 0;
}

} // namespace polycut::sim
